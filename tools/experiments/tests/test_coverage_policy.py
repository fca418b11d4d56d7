#!/usr/bin/python3
"""Tests of tools/experiments/coverage_policy: the report on hand-made rows (paired tests, ties,
ratios, a failed seed left out and named), and the shipped rooms world (seed 1, its shipped revisit
rawlog) with two combinations and the offline optimum, through the real budget-slam.

    test_coverage_policy.py --budget-slam build/bin/budget-slam --budget-simulate build/bin/budget-simulate
"""
import csv
import math
import os
import subprocess
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scripttest  # noqa: E402

SCRIPT = os.path.join(scripttest.EXP, "coverage_policy")
BUDGET_SLAM = BUDGET_SIMULATE = None
SHIPPED, OTHER = "place-coverage/newly_added/compete", "random/newly_added/compete"


def row(cp, seed, combo, rmse, error=""):
    r = {"scenario": "rooms", "cap": 50, "seed": seed, "combo": combo,
         **{m: 1.0 for m, _ in cp.METRICS}, "landmarks_unreduced": 154, "error": error}
    r.update(reloc_rmse_m=rmse, reloc_rmse_ratio=rmse / 0.1, reloc_lost_pct=0.0 if rmse < 0.2 else 5.0)
    return r


class Report(unittest.TestCase):
    def test_paired_tests_ties_ratios_and_a_failed_seed(self):
        cp = scripttest.load_script("coverage_policy")
        rows = []
        for seed in range(1, 12):
            rows.append(row(cp, seed, "none", 0.1))
            # the shipped map relocalizes 0.111-0.121 m on every seed, the other 0.3 m: every one of
            # the 10 kept pairs favours the shipped map by a different amount (no ties), exact
            # p = 2 / 2^10
            rows.append(row(cp, seed, SHIPPED, 0.1103 + 0.001 * seed))
            rows.append(row(cp, seed, OTHER, 0.3 + 0.003 * seed,
                            error="mapping run failed: diverged" if seed == 11 else ""))
        text = cp.report(rows, [SHIPPED, OTHER], "1-11")
        self.assertIn("10 seeds; left out with every run of their seed: seed 11 (%s: mapping run failed: "
                      "diverged)." % OTHER, text)
        lines = {l.split(" | ")[0][2:]: l.split(" | ") for l in text.splitlines() if l.startswith("| ")}
        p_reloc = lines[OTHER][-1].rstrip(" |")
        self.assertEqual(p_reloc, "%.2g" % (2 / 2 ** 10))  # 0.002
        # equal samples: p = 1, a tie
        self.assertEqual(lines[OTHER][-3], "1.00 (tie)")
        self.assertEqual(lines[SHIPPED][-1].rstrip(" |"), "–")
        # mean relocalization RMSE of the shipped map over seeds 1-10, and its ratio
        mean = sum(0.1103 + 0.001 * s for s in range(1, 11)) / 10  # 0.1158
        self.assertEqual(lines[SHIPPED][6], "%.3f" % mean)
        self.assertEqual(lines[SHIPPED][8], "%.2f" % (mean / 0.1))
        self.assertIn("within 1.25x the unreduced map's on 10 of 10 seeds (max %.2f); lost at < 2%% of steps "
                      "on 10 of 10 seeds (max 0.0%%)." % ((0.1103 + 0.01) / 0.1), text)

    def test_offline_optimum_table(self):
        cp = scripttest.load_script("coverage_policy")
        opt = [{"scenario": "rooms", "cap": 50, "seed": 1, "combo_pct_of_optimum": "98.0", "error": ""},
               {"scenario": "rooms", "cap": 50, "seed": 2, "combo_pct_of_optimum": "94.0", "error": ""},
               {"scenario": "rooms", "cap": 50, "seed": 3, "combo_pct_of_optimum": "",
                "error": "--offline-optimum: too large"}]
        text = cp.report([row(cp, 1, "none", 0.1), row(cp, 1, SHIPPED, 0.1)], [SHIPPED], "1", opt)
        self.assertIn("| rooms | 2 | 96.0 | 94.0 (2) | seed 3 (--offline-optimum: too large) |", text)


class Rooms(unittest.TestCase):
    def test_rooms_seed_1_maps_relocalizes_and_bounds(self):
        with tempfile.TemporaryDirectory() as tmp:
            p = subprocess.run(["/usr/bin/python3", SCRIPT, "-o", tmp, "--scenarios", "rooms:50", "--seeds", "1",
                                "--combos", SHIPPED + "," + OTHER, "--offline-optimum",
                                "--budget-slam", BUDGET_SLAM, "--budget-simulate", BUDGET_SIMULATE],
                               capture_output=True, text=True, timeout=600)
            self.assertEqual(p.returncode, 0, p.stderr)
            with open(os.path.join(tmp, "results.csv")) as f:
                rows = {r["combo"]: r for r in csv.DictReader(f)}
            self.assertEqual(sorted(rows), sorted(["none", SHIPPED, OTHER]))
            for name, r in rows.items():
                self.assertEqual(r["error"], "")
                # each final map localized the shipped revisit rawlog (the same world, seed 1)
                self.assertTrue(os.path.isfile(os.path.join(tmp, "runs", "rooms", "seed1", name.replace("/", "_"),
                                                            "relocalize", "rooms_revisit", "summary.json")))
                self.assertTrue(0 < float(r["reloc_rmse_m"]) < 5.0)
                self.assertTrue(0 <= float(r["reloc_lost_pct"]) <= 100)
            self.assertEqual(float(rows["none"]["reloc_rmse_ratio"]), 1.0)
            self.assertTrue(math.isclose(float(rows[SHIPPED]["reloc_rmse_ratio"]),
                                         float(rows[SHIPPED]["reloc_rmse_m"]) / float(rows["none"]["reloc_rmse_m"])))
            # the unreduced map localizes the revisit well (ground truth, 1 m lost threshold)
            self.assertLess(float(rows["none"]["reloc_rmse_m"]), 0.5)
            self.assertEqual(float(rows["none"]["reloc_lost_pct"]), 0.0)
            self.assertEqual(int(rows[SHIPPED]["landmarks_unreduced"]), 154)
            with open(os.path.join(tmp, "offline_optimum.csv")) as f:
                opt = list(csv.DictReader(f))
            self.assertEqual(len(opt), 1)
            # the optimum bounds the reducer's coverage
            self.assertLessEqual(int(opt[0]["combo_places"]), int(opt[0]["optimum_places"]))
            self.assertTrue(0 < float(opt[0]["combo_pct_of_optimum"]) <= 100)
            self.assertIn("## Offline optimum", p.stdout)

    def test_unknown_combination(self):
        p = subprocess.run(["/usr/bin/python3", SCRIPT, "-o", "/nonexistent/x", "--combos", "mi/always"],
                           capture_output=True, text=True, timeout=60)
        self.assertNotEqual(p.returncode, 0)
        self.assertIn("coverage_policy: unknown combination 'mi/always' (known: ", p.stderr)


if __name__ == "__main__":
    BUDGET_SLAM, BUDGET_SIMULATE, argv = scripttest.parse_binaries(__doc__)
    unittest.main(argv=argv)
