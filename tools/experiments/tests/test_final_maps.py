#!/usr/bin/python3
"""Tests of tools/experiments/final_maps: the map of the last landmarks seen on a hand-made map,
and a small grid through the real binary (MRCLAM 7 robot 1 at cap 1/5, random on 4 seeds under
the shipped policy and per_landmark, rule oldest; a few seconds), resumed without running anything.

    test_final_maps.py --budget-slam build/bin/budget-slam
"""
import csv
import os
import subprocess
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scripttest  # noqa: E402

ROOT = scripttest.ROOT
SCRIPT = os.path.join(scripttest.EXP, "final_maps")
BUDGET_SLAM = None
fm = scripttest.load_script("final_maps")


class LastSeen(unittest.TestCase):
    def test_latest_last_steps_ties_to_the_lowest_id(self):
        self.assertEqual(fm.last_seen_map({1: 5, 2: 9, 3: 9, 4: 1, 7: 8}, 3), frozenset({2, 3, 7}))
        self.assertEqual(fm.last_seen_map({1: 5, 2: 9, 3: 9}, 1), frozenset({2}))

    def test_caps_round_as_the_benchmark(self):
        self.assertEqual((fm.cap_count(1 / 3, 15), fm.cap_count(1 / 5, 15)), (5, 3))
        self.assertEqual((fm.cap_count(1 / 3, 154), fm.cap_count(1 / 5, 154)), (51, 31))


class SmallGrid(unittest.TestCase):
    def test_mrclam_through_the_binary_and_resume(self):
        with tempfile.TemporaryDirectory(prefix="test_final_maps_") as tmp:
            cmd = [SCRIPT, "-o", tmp, "--rawlogs", os.path.join(ROOT, "rawlogs", "mrclam7_robot1.rawlog"),
                   "--seeds", "1-4", "--caps", "1/5", "--policies", "shipped,per-landmark", "--rules", "oldest",
                   "--budget-slam", BUDGET_SLAM]
            p = subprocess.run(cmd, capture_output=True, text=True)
            self.assertEqual(p.returncode, 0, p.stderr[-3000:])
            with open(os.path.join(tmp, "final_maps.csv")) as f:
                rows = {(r["policy"], r["reducer"]): r for r in csv.DictReader(f)}
            self.assertEqual(set(rows), {("shipped", "random"), ("per-landmark", "random"), ("shipped", "oldest")})
            for key in (("shipped", "random"), ("per-landmark", "random")):
                r = rows[key]
                self.assertEqual((r["landmarks"], r["k"], r["runs"]), ("15", "3", "4"))
                self.assertTrue(1 <= int(r["distinct_maps"]) <= 4)
                self.assertTrue(0 <= float(r["overlap_last_seen"]) <= 1)
            # Each run's map has k landmarks of the unreduced map.
            unreduced = fm.read_landmarks(os.path.join(tmp, "mrclam7_robot1", "unreduced"))
            for s in range(1, 5):
                m = fm.read_landmarks(os.path.join(tmp, "mrclam7_robot1", "cap3", "per-landmark", f"random-seed{s}"))
                self.assertEqual(len(m), 3)
                self.assertTrue(set(m) <= set(unreduced))
            self.assertIn("| mrclam7_robot1 | 15 | 1/5 | 3 | per-landmark | 4 |", p.stdout)
            p = subprocess.run(cmd, capture_output=True, text=True)
            self.assertEqual(p.returncode, 0, p.stderr[-3000:])
            self.assertIn("9 runs, 9 done, 0 to run", p.stderr)

    def test_a_bad_policy_is_one_line(self):
        p = subprocess.run([SCRIPT, "-o", "/nonexistent/x", "--policies", "lax"], capture_output=True, text=True)
        self.assertEqual(p.returncode, 2)
        self.assertIn("--policies: 'lax' is not one of shipped, always, no-protection, no-readmission, per-landmark",
                      p.stderr)


if __name__ == "__main__":
    BUDGET_SLAM, _, argv = scripttest.parse_binaries(__doc__)
    unittest.main(argv=argv)
