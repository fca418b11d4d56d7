#!/usr/bin/python3
"""Tests of tools/experiments/paired_stats.py on synthetic numbers with a known answer: identical
samples give p = 1; a constant shift over 20 pairs gives p < 0.01; small cases against p-values
computed by hand and against an enumeration of every sign pattern; zero differences and ties; the
bootstrap interval holds the true shift and is the same on every call.

    test_paired_stats.py [unittest options]   (--budget-slam / --budget-simulate are accepted, unused)
"""
import itertools
import math
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scripttest  # noqa: E402
import numpy as np  # noqa: E402
import paired_stats as ps  # noqa: E402


def exact_p_by_enumeration(d):
    """Two-sided exact signed-rank p-value of non-zero differences without ties, by listing all
    2^n sign patterns: 2 * min(P(W+ <= w), P(W+ >= w)), capped at 1."""
    ranks = np.argsort(np.argsort(np.abs(d))) + 1
    w = ranks[np.asarray(d) > 0].sum()
    sums = [sum(r for r, s in zip(ranks, signs) if s) for signs in itertools.product((0, 1), repeat=len(d))]
    le = sum(1 for s in sums if s <= w) / len(sums)
    ge = sum(1 for s in sums if s >= w) / len(sums)
    return min(1.0, 2 * min(le, ge))


class Wilcoxon(unittest.TestCase):
    def test_identical_samples_give_p_one(self):
        x = [0.3, 0.1, 0.7, 0.2, 0.9, 0.4, 0.5, 0.6, 0.8, 1.0]
        self.assertEqual(ps.wilcoxon_p(x, list(x)), 1.0)
        c = ps.Comparison(x, list(x))
        self.assertEqual((c.median_diff, c.ci_low, c.ci_high, c.p_value, c.significant), (0.0, 0.0, 0.0, 1.0, False))
        self.assertIsNone(c.lower())

    def test_values_equal_but_for_rounding_count_as_equal(self):
        self.assertNotEqual(0.1 + 0.2, 0.3)
        self.assertEqual(ps.wilcoxon_p([0.1 + 0.2] * 10, [0.3] * 10), 1.0)

    def test_constant_shift_over_twenty_pairs_is_significant(self):
        rng = np.random.default_rng(7)
        b = rng.uniform(0.05, 2.0, size=20)
        a = b + 0.05
        p = ps.wilcoxon_p(a, b)
        self.assertLess(p, 0.01)
        c = ps.Comparison(a, b)
        self.assertTrue(c.significant)
        self.assertEqual(c.lower(), "b")  # b is lower by 0.05 on every pair
        self.assertAlmostEqual(c.median_diff, 0.05, places=12)
        self.assertEqual(ps.Comparison(b, a).lower(), "a")

    def test_small_cases_against_hand_computed_exact_p(self):
        # d = 1..5, all positive: W- = 0; P(W- = 0) = 1/32, two-sided p = 2/32
        self.assertEqual(ps.wilcoxon_p([1, 2, 3, 4, 5], [0] * 5), 0.0625)
        # d = 1, -2, 3, 4, 5, 6: W- = 2; the rank subsets of 1..6 with sum <= 2 are {}, {1}, {2}:
        # P(W- <= 2) = 3/64, two-sided p = 6/64
        self.assertEqual(ps.wilcoxon_p([1, -2, 3, 4, 5, 6], [0] * 6), 0.09375)
        # ten pairs all one way: 2/1024 < 0.01; seven pairs all one way: 2/128 > 0.01 (never significant)
        self.assertEqual(ps.wilcoxon_p(list(range(1, 11)), [0] * 10), 2 / 1024)
        self.assertEqual(ps.wilcoxon_p(list(range(1, 8)), [0] * 7), 2 / 128)
        self.assertFalse(ps.significant(ps.wilcoxon_p(list(range(1, 8)), [0] * 7)))

    def test_exact_p_equals_enumeration_of_every_sign_pattern(self):
        rng = np.random.default_rng(3)
        for n in (5, 9, 12):
            for _ in range(4):
                d = rng.normal(0.2, 1.0, size=n)
                self.assertAlmostEqual(ps.wilcoxon_p(d, np.zeros(n)), exact_p_by_enumeration(d), places=12)

    def test_zero_differences_are_dropped(self):
        # two pairs equal, then the d = 1..5 case: the same p as without the zeros
        self.assertEqual(ps.wilcoxon_p([0, 0, 1, 2, 3, 4, 5], [0, 0, 0, 0, 0, 0, 0]), 0.0625)
        c = ps.Comparison([7, 7, 1, 2, 3, 4, 5], [7, 7, 0, 0, 0, 0, 0])
        self.assertEqual(c.n_pairs, 7)

    def test_ties_use_the_normal_approximation_with_tie_correction(self):
        # d = 1, 1, -1, 2: |d| ranks 2, 2, 2, 4; W+ = 8, W- = 2, T = 2; mean n(n+1)/4 = 5;
        # variance (n(n+1)(2n+1) - (t^3 - t)/2) / 24 = (180 - 12) / 24 = 7 for the tie of t = 3;
        # continuity correction 0.5 towards the mean: z = (2 - 5 + 0.5) / sqrt(7)
        z = 2.5 / math.sqrt(7)
        self.assertAlmostEqual(ps.wilcoxon_p([1, 1, -1, 2], [0, 0, 0, 0]), math.erfc(z / math.sqrt(2)), places=12)

    def test_one_pair_has_no_test(self):
        self.assertIsNone(ps.wilcoxon_p([1.0], [2.0]))
        c = ps.Comparison([1.0], [2.0])
        self.assertEqual((c.n_pairs, c.median_diff, c.ci_low, c.p_value, c.significant), (1, -1.0, None, None, False))
        self.assertFalse(ps.significant(None))

    def test_pairs_are_matched_by_seed(self):
        a = {3: 5.0, 1: 1.0, 2: 2.0, 9: None}
        b = {1: 0.5, 2: 1.0, 3: 4.0, 4: 7.0, 9: 1.0}
        self.assertEqual(ps.paired(a, b), ([1.0, 2.0, 5.0], [0.5, 1.0, 4.0]))
        self.assertEqual(ps.compare(a, b).n_pairs, 3)

    def test_p_value_formatting(self):
        self.assertEqual([ps.fmt_p(p) for p in (None, 1.0, 0.5, 0.0625, 0.0019531, 3e-5)],
                         ["–", "1.00", "0.50", "0.062", "0.002", "< 0.0001"])
        self.assertEqual([ps.p_phrase(p) for p in (None, 0.0095, 3e-5)], ["no test", "p = 0.0095", "p < 0.0001"])


class Bootstrap(unittest.TestCase):
    def sample(self):
        rng = np.random.default_rng(11)
        b = rng.uniform(0.1, 3.0, size=20)
        return b + 0.3 + rng.normal(0.0, 0.05, size=20), b

    def test_interval_holds_the_true_shift(self):
        a, b = self.sample()
        low, high = ps.bootstrap_median_ci(a, b)
        self.assertLess(low, 0.3)
        self.assertGreater(high, 0.3)
        self.assertGreater(low, 0.2)   # and is narrow: the noise is 0.05
        self.assertLess(high, 0.4)

    def test_interval_is_reproducible(self):
        a, b = self.sample()
        self.assertEqual(ps.bootstrap_median_ci(a, b), ps.bootstrap_median_ci(a, b))
        self.assertEqual(ps.bootstrap_median_ci(a, b), ps.bootstrap_median_ci(list(a), list(b)))
        # its own seeded generator: the global numpy state does not change it
        first = ps.bootstrap_median_ci(a, b)
        np.random.seed(99)
        np.random.uniform(size=1000)
        self.assertEqual(ps.bootstrap_median_ci(a, b), first)

    def test_interval_of_a_median_of_distinct_values_lies_within_the_sample(self):
        d = np.array([-2.0, 0.5, 1.0, 3.0, 4.0, 8.0])
        low, high = ps.bootstrap_median_ci(d, np.zeros(6))
        self.assertGreaterEqual(low, d.min())
        self.assertLessEqual(high, d.max())
        self.assertLessEqual(low, np.median(d))
        self.assertGreaterEqual(high, np.median(d))


if __name__ == "__main__":
    _, _, argv = scripttest.parse_binaries(__doc__)
    unittest.main(argv=argv)
