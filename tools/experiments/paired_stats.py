"""Paired comparison of two reducers over seeds (docs/EXPERIMENTS.md, "Statistics").

Two runs are a pair when they share the rawlog, the backend, the cap and the seed (for a simulated
rawlog the seed is also the simulation's), so the difference a - b removes what the seed changes
for both. For each pair of reducers this gives:

- the two-sided Wilcoxon signed-rank p-value of the differences (scipy.stats.wilcoxon);
- the median difference and a percentile-bootstrap 95% interval of it;
- significance: p < ALPHA (0.01). "A beats B" is said only then; otherwise it is a tie.

Zero differences and ties, deliberately:
- Differences are first quantized to QUANTUM_REL (1e-12) of the largest |value| of the sample, so
  that values that differ only by floating-point rounding count as equal.
- All differences zero (identical samples, e.g. two reducers that kept the same landmarks on
  every seed): p = 1, interval [0, 0]. There is no evidence of any difference.
- Otherwise zero differences are dropped and the test runs on the others (Wilcoxon's own
  convention, scipy's zero_method="wilcox"); n_pairs still counts them.
- Without ties among the remaining |differences| and with at most EXACT_MAX_N of them, the p-value
  is exact (the null distribution of the signed-rank sum); with ties, or more pairs, the normal
  approximation with tie correction and continuity correction.
- A consequence worth knowing: with n differing pairs the smallest attainable exact two-sided p is
  2 / 2^n, so fewer than 8 differing pairs can never reach p < 0.01 (2 / 2^7 = 0.0156).
- One pair (a single run, e.g. a real rawlog without seeds): no test, p is None.

Bootstrap: BOOTSTRAP_RESAMPLES (10,000) resamples of the n differences with replacement from
numpy's default generator seeded with BOOTSTRAP_SEED, the same seed for every comparison, so a
report regenerated from the same runs has the same intervals; the interval is the 2.5th and
97.5th percentile of the resampled medians.
"""
import math
import warnings

import numpy as np
from scipy import stats

ALPHA = 0.01
BOOTSTRAP_RESAMPLES = 10000
BOOTSTRAP_SEED = 12345
CONFIDENCE = 0.95
EXACT_MAX_N = 50
QUANTUM_REL = 1e-12


def _differences(a, b):
    """a - b, quantized to QUANTUM_REL of the largest |value| (as multiples of that quantum)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    if a.shape != b.shape or a.ndim != 1:
        raise ValueError("paired samples must be two 1-D sequences of the same length")
    if not (np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
        raise ValueError("paired samples must be finite")
    scale = max(float(np.max(np.abs(a), initial=0.0)), float(np.max(np.abs(b), initial=0.0)))
    if scale == 0.0:
        return a - b, np.zeros(len(a))
    quantum = QUANTUM_REL * scale
    return a - b, np.round((a - b) / quantum)


def wilcoxon_p(a, b):
    """Two-sided Wilcoxon signed-rank p-value of the pairs (a[i], b[i]); None for fewer than two
    pairs. Zero differences and ties as in the module's docstring."""
    d, q = _differences(a, b)
    if len(d) < 2:
        return None
    nonzero = q[q != 0]
    if len(nonzero) == 0:
        return 1.0
    magnitudes = np.abs(nonzero)
    ties = len(np.unique(magnitudes)) < len(magnitudes)
    method = "exact" if not ties and len(nonzero) <= EXACT_MAX_N else "approx"
    with warnings.catch_warnings():  # "sample size too small for normal approximation": known, see above
        warnings.simplefilter("ignore")
        res = stats.wilcoxon(nonzero, zero_method="wilcox", correction=(method == "approx"),
                             alternative="two-sided", method=method)
    return float(min(1.0, res.pvalue))


def rank_sums(a, b):
    """(W+, W-): the signed-rank sums of the non-zero differences a - b (average ranks for ties).
    W- > W+ means a tends to be lower than b."""
    _, q = _differences(a, b)
    nonzero = q[q != 0]
    if len(nonzero) == 0:
        return 0.0, 0.0
    r = stats.rankdata(np.abs(nonzero))
    return float(r[nonzero > 0].sum()), float(r[nonzero < 0].sum())


def bootstrap_median_ci(a, b, resamples=BOOTSTRAP_RESAMPLES, seed=BOOTSTRAP_SEED, confidence=CONFIDENCE):
    """Percentile-bootstrap interval (low, high) of the median of a - b; None for fewer than two
    pairs (one run has no interval)."""
    d, q = _differences(a, b)
    if len(d) < 2:
        return None
    d = np.where(q == 0, 0.0, d)
    rng = np.random.default_rng(seed)
    idx = rng.integers(0, len(d), size=(resamples, len(d)))
    medians = np.median(d[idx], axis=1)
    tail = 100.0 * (1.0 - confidence) / 2.0
    low, high = np.percentile(medians, [tail, 100.0 - tail])
    return float(low), float(high)


def significant(p, alpha=ALPHA):
    """Whether a p-value marks a real difference: p < alpha (0.01). No test (None): no."""
    return p is not None and not math.isnan(p) and p < alpha


class Comparison:
    """a against b over their common seeds: n_pairs, median_diff (a - b), ci_low, ci_high,
    p_value (None without a test) and significant; lower(): which side is significantly lower."""

    def __init__(self, a, b):
        self.n_pairs = len(a)
        if self.n_pairs:
            d, q = _differences(a, b)
            self.median_diff = float(np.median(np.where(q == 0, 0.0, d)))
        else:
            self.median_diff = None
        ci = bootstrap_median_ci(a, b)
        self.ci_low, self.ci_high = ci if ci else (None, None)
        self.p_value = wilcoxon_p(a, b)
        self.significant = significant(self.p_value)
        self.w_plus, self.w_minus = rank_sums(a, b) if self.n_pairs else (0.0, 0.0)

    def lower(self):
        """'a' or 'b': the side whose values are significantly lower (by the signed-rank sums the
        test uses); None when the difference is not significant."""
        if not self.significant or self.w_plus == self.w_minus:
            return None
        return "a" if self.w_minus > self.w_plus else "b"


def paired(values_a, values_b):
    """The two samples paired by key ({seed: value} each, None values skipped): ([a], [b]) over
    the keys both have, in key order."""
    keys = sorted(k for k in values_a if k in values_b and values_a[k] is not None and values_b[k] is not None)
    return [values_a[k] for k in keys], [values_b[k] for k in keys]


def compare(values_a, values_b):
    """Comparison of two {seed: value} samples over their common seeds."""
    return Comparison(*paired(values_a, values_b))


def fmt_p(p):
    """p-value for a table: '–' without a test, '< 0.0001', else 2 significant digits."""
    if p is None:
        return "–"
    if p < 1e-4:
        return "< 0.0001"
    return f"{p:.2g}" if p < 0.1 else f"{p:.2f}"


def p_phrase(p):
    """'p = 0.0095', 'p < 0.0001', or 'no test' for prose."""
    if p is None:
        return "no test"
    return f"p {fmt_p(p)}" if p < 1e-4 else f"p = {fmt_p(p)}"
