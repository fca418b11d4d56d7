#!/usr/bin/python3
"""Tests of tools/experiments/changing_world: which kept landmarks still exist (aligned, by id and
place) on a hand-made map, and a short changing world through the binaries in which landmarks
only disappear: every drop for negative evidence is of a landmark that disappeared, and the
RESULTS block is written without touching the rest of the file.

    test_changing_world.py --budget-slam build/bin/budget-slam --budget-simulate build/bin/budget-simulate
"""
import json
import math
import os
import subprocess
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scripttest  # noqa: E402

SCRIPT = os.path.join(scripttest.EXP, "changing_world")
BUDGET_SLAM = BUDGET_SIMULATE = None


class Existing(unittest.TestCase):
    def test_a_drifted_map_is_aligned_and_a_moved_or_gone_landmark_does_not_exist(self):
        cw = scripttest.load_script("changing_world")
        truth = {i: (float(i), float(i % 3)) for i in range(1, 9)}
        # The map: the truth turned by 10 degrees and shifted by (2, -1) m; landmark 3 moved 1 m
        # since it was mapped, landmark 9 is not in the world any more.
        c, s = math.cos(0.17), math.sin(0.17)
        rows = []
        for i in list(range(1, 9)) + [9]:
            x, y = truth.get(i, (20.0, 20.0))
            if i == 3:
                x -= 1.0
            rows.append({"id": str(i), "x": str(c * x - s * y + 2), "y": str(s * x + c * y - 1)})
        self.assertEqual(cw.existing(rows, truth), 7)
        self.assertEqual(cw.existing([], truth), 0)


class ThroughTheBinaries(unittest.TestCase):
    def test_only_disappeared_landmarks_are_dropped_for_negative_evidence(self):
        with tempfile.TemporaryDirectory() as tmp:
            md = os.path.join(tmp, "RESULTS.md")
            with open(md, "w") as f:
                f.write("# Results\n\nhand-written\n")
            out = os.path.join(tmp, "work")
            p = subprocess.run(["/usr/bin/python3", SCRIPT, "--seeds", "1-2", "--sessions", "3",
                                "--change", "0.3", "--change-split", "1:0:0", "--modes", "off,always",
                                "-o", out, "--results-md", md, "--budget-slam", BUDGET_SLAM,
                                "--budget-simulate", BUDGET_SIMULATE],
                               capture_output=True, text=True, timeout=600)
            self.assertEqual(p.returncode, 0, p.stderr)
            with open(os.path.join(out, "changing_world.json")) as f:
                res = json.load(f)
            self.assertEqual([r["seed"] for r in res], [1, 2])
            for r in res:
                self.assertEqual(r["off"]["ne_drops"], 0)
                self.assertGreater(r["always"]["ne_drops"], 0)
                self.assertEqual(r["always"]["ne_right"], 1.0)  # none of a landmark still there
                self.assertGreaterEqual(r["always"]["share_existing"], r["off"]["share_existing"])
                self.assertLessEqual(r["always"]["share_in_place"], r["always"]["share_existing"])
                self.assertEqual(r["always"]["status"], "ok")
            with open(os.path.join(out, "seed1", "always", "evictions.csv")) as f:
                self.assertIn(",negative_evidence,", f.read())
            # The table is in OUT too, as printed (it was on stdout only).
            with open(os.path.join(out, "changing_world.md")) as f:
                table = f.read()
            self.assertIn("| `always` − `off` | share_existing |", table)
            self.assertEqual(table, p.stdout)
            with open(md) as f:
                text = f.read()
            self.assertTrue(text.startswith("# Results\n\nhand-written\n\n## A world that changes\n"))
            self.assertIn("| `always` − `off` | share_existing |", text)
            self.assertTrue(text.rstrip().endswith("<!-- changing_world:end -->"))

    def test_a_world_that_does_not_change_loses_nothing_to_negative_evidence(self):
        # rooms has walls and rooms: landmarks in range and in the field of view behind a wall,
        # never seen from where the robot stands, must not count as missed.
        with tempfile.TemporaryDirectory() as tmp:
            out = os.path.join(tmp, "work")
            p = subprocess.run(["/usr/bin/python3", SCRIPT, "--seeds", "3", "--sessions", "2",
                                "--change", "0", "--modes", "off,always", "-o", out,
                                "--budget-slam", BUDGET_SLAM, "--budget-simulate", BUDGET_SIMULATE],
                               capture_output=True, text=True, timeout=600)
            self.assertEqual(p.returncode, 0, p.stderr)
            with open(os.path.join(out, "changing_world.json")) as f:
                r = json.load(f)[0]
            self.assertEqual(r["always"]["ne_drops"], 0)
            self.assertEqual(r["always"]["share_existing"], 1.0)
            with open(os.path.join(out, "seed3", "always", "landmarks.csv")) as f:
                rows = f.read().splitlines()
            self.assertTrue(rows[0].endswith(",last_step,last_confirmed_step,misses"))
            self.assertEqual([row.split(",")[-1] for row in rows[1:]], ["0"] * (len(rows) - 1))


if __name__ == "__main__":
    BUDGET_SLAM, BUDGET_SIMULATE, argv = scripttest.parse_binaries(__doc__)
    unittest.main(argv=argv)
