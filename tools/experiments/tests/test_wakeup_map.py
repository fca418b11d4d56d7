#!/usr/bin/python3
"""Tests of tools/experiments/wakeup_map.py on a hand-made places file: each start place lands in
its class (found, off, at a wrong place, ambiguous, not found by reason) with the counts printed,
places outside the mapped area are counted, the figure is a PNG, and an existing figure is not
replaced without --force.

    test_wakeup_map.py [unittest options]   (--budget-slam / --budget-simulate are accepted, unused)
"""
import os
import subprocess
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scripttest  # noqa: E402

SCRIPT = os.path.join(scripttest.EXP, "wakeup_map.py")
HEADER = ("start_step,x,y,yaw,status,reason,steps_used,landmarks,inliers,runner_up,hypotheses,score,"
          "runner_up_score,error_xy,error_yaw_deg,ms,in_mapped_area\n")


def row(step, status, reason="", exy="", eyaw="", inside=1):
    return f"{step},{step},0,0,{status},{reason},1,2,2,0,0,0,0,{exy},{eyaw},0.1,{inside}\n"


class WakeUpMap(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        d = self.tmp.name
        self.map = os.path.join(d, "map")
        os.makedirs(self.map)
        with open(os.path.join(self.map, "landmarks.csv"), "w") as f:
            f.write("id,x,y,cov_xx,cov_xy,cov_yy\n1,0,1,0.01,0,0.01\n2,3,1,0.01,0,0.01\n")
        with open(os.path.join(self.map, "trajectory.tum"), "w") as f:
            f.write("0 0 0 0 0 0 0 1\n1 5 0 0 0 0 0 1\n")
        self.places = os.path.join(d, "places.csv")
        with open(self.places, "w") as f:
            f.write(HEADER)
            f.write(row(0, "found", exy=0.1, eyaw=1))  # found
            f.write(row(1, "found", exy=0.2, eyaw=4.9))  # found
            f.write(row(2, "found", exy=0.3, eyaw=1))  # off (beyond 0.25 m, within 1 m)
            f.write(row(3, "found", exy=5.0, eyaw=1))  # at a wrong place
            f.write(row(4, "found", exy=0.1, eyaw=30))  # at a wrong place (yaw)
            f.write(row(5, "ambiguous"))
            f.write(row(6, "not_found", "too_few_landmarks", inside=0))
            f.write(row(7, "not_found", "too_uncertain"))
            f.write(row(8, "not_found", "inconsistent"))
        self.out = os.path.join(d, "fig.png")

    def tearDown(self):
        self.tmp.cleanup()

    def run_script(self, *extra):
        return subprocess.run([sys.executable, SCRIPT, "--map", self.map, "--places", self.places,
                               "--out", self.out, *extra], capture_output=True, text=True)

    def test_each_place_in_its_class(self):
        r = self.run_script()
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(r.stdout, f"{self.out}: 9 places (1 outside the mapped area), too_few 1, "
                         "too_uncertain 1, not_found 1, ambiguous 1, found 2, off 1, wrong 2\n")
        with open(self.out, "rb") as f:
            self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")

    def test_an_existing_figure_is_kept_without_force(self):
        with open(self.out, "w") as f:
            f.write("mine")
        r = self.run_script()
        self.assertEqual(r.returncode, 1)
        self.assertEqual(r.stderr, f"wakeup_map.py: {self.out} exists; give --force to replace it\n")
        with open(self.out) as f:
            self.assertEqual(f.read(), "mine")
        self.assertEqual(self.run_script("--force").returncode, 0)


if __name__ == "__main__":
    _, _, argv = scripttest.parse_binaries(__doc__)
    unittest.main(argv=argv)
