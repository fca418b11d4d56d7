#!/usr/bin/python3
"""Tests of tools/experiments/life: the alignment of a turned, shifted map with a moved landmark
and the truth brought into its frame, the aligned trajectory error against its definition, and
`life --quick` through the binaries (MRCLAM 7 robots 1 -> 2, a simulated life of 3 sessions on
one seed with negative evidence on and off, Victoria Park's first 600 steps in two halves).

    test_life.py --budget-slam build/bin/budget-slam --budget-simulate build/bin/budget-simulate
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

SCRIPT = os.path.join(scripttest.EXP, "life")
BUDGET_SLAM = BUDGET_SIMULATE = None


def turned(x, y, yaw=0.3, t=(2.0, -1.0)):
    c, s = math.cos(yaw), math.sin(yaw)
    return c * x - s * y + t[0], s * x + c * y + t[1]


class Alignment(unittest.TestCase):
    def test_a_turned_map_is_aligned_without_the_moved_landmark(self):
        import worldlib
        truth = {i: (float(i), float(i % 3)) for i in range(1, 9)}
        # the map: the truth turned by 0.3 rad about the origin and shifted by (2, -1); landmark 3
        # is mapped 3 m from where the truth has it (it moved), landmark 9 is not in the world
        rows = []
        for i in list(range(1, 9)) + [9]:
            x, y = truth.get(i, (20.0, 20.0))
            if i == 3:
                x -= 3.0
            mx, my = turned(x, y)
            rows.append({"id": str(i), "x": str(mx), "y": str(my)})
        rot, t, err, common = worldlib.align_map(rows, truth)
        self.assertEqual(len(common), 8)
        self.assertAlmostEqual(math.atan2(rot[1, 0], rot[0, 0]), -0.3, places=9)
        self.assertAlmostEqual(float(err[2]), 3.0, places=9)
        self.assertLess(max(float(e) for i, e in enumerate(err) if i != 2), 1e-9)
        self.assertEqual(worldlib.existing(rows, truth), 7)
        # a truth pose in the map's frame: the pose turned and shifted as the map was
        x, y, yaw = worldlib.pose_to_map(rot, t, (4.0, 1.0, 0.5))
        ex, ey = turned(4.0, 1.0)
        self.assertAlmostEqual(x, ex, places=9)
        self.assertAlmostEqual(y, ey, places=9)
        self.assertAlmostEqual(yaw, 0.8, places=9)
        self.assertIsNone(worldlib.align_map(rows[:1], truth))

    def test_aligned_trajectory_error_is_the_rms_after_the_rigid_fit(self):
        import numpy as np
        life = scripttest.load_script("life")
        # a square path; the estimate is it turned and shifted, with +0.1 m on x at two of its
        # eight poses: after the fit the residuals are those of the two bumps, less their mean
        truth = [(0, 0, 0), (1, 0, 0), (2, 0, 0), (2, 1, 0), (2, 2, 0), (1, 2, 0), (0, 2, 0), (0, 1, 0)]
        traj = []
        for i, (x, y, _) in enumerate(truth):
            bx = x + (0.1 if i in (1, 5) else 0.0)
            traj.append([10.0 + i, *turned(bx, y)])
        by_time = {round(10.0 + i, 6): p for i, p in enumerate(truth)}
        rmse, used = life.aligned_ate(np.array(traj), by_time)
        self.assertEqual(used, 8)
        import worldlib
        est = np.array([r[1:3] for r in traj])
        tru = np.array([p[:2] for p in truth])
        rot, t = worldlib.rigid_fit(est, tru)
        want = math.sqrt(np.mean(np.sum((est @ rot.T + t - tru) ** 2, axis=1)))
        self.assertAlmostEqual(rmse, want, places=12)
        self.assertGreater(rmse, 0.02)
        self.assertLess(rmse, 0.05)
        # only the times the truth has count; under three poses there is no fit
        self.assertEqual(life.aligned_ate(np.array(traj[:2]), by_time), (None, 2))


class Quick(unittest.TestCase):
    def test_quick_life_through_the_binaries(self):
        with tempfile.TemporaryDirectory() as tmp:
            md = os.path.join(tmp, "RESULTS.md")
            with open(md, "w") as f:
                f.write("# Results\n\nhand-written\n")
            out = os.path.join(tmp, "work")
            res_dir = os.path.join(tmp, "results")
            cmd = ["/usr/bin/python3", SCRIPT, "--quick", "-o", out, "--results-md", md, "--results-dir", res_dir,
                   "--budget-slam", BUDGET_SLAM, "--budget-simulate", BUDGET_SIMULATE]
            p = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
            self.assertEqual(p.returncode, 0, p.stderr)
            with open(os.path.join(out, "life.json")) as f:
                res = json.load(f)

            # MRCLAM 7: two sessions, both ok under the cap; the second woke up on the first's map
            m = res["mrclam7"]
            self.assertEqual([(r["session"], r["robot"], r["status"]) for r in m], [(1, 1, "ok"), (2, 2, "ok")])
            for r in m:
                self.assertTrue(r["under_cap"])
                self.assertEqual(r["max_landmarks"], 5)
                self.assertLess(r["ate_m"], 1.0)
            # the first session is a plain run on its own rawlog: its error is summary.json's
            with open(os.path.join(out, "mrclam7", "s1_robot1", "summary.json")) as f:
                s1 = json.load(f)
            self.assertAlmostEqual(m[0]["ate_m"], s1["ground_truth"]["trajectory_rmse_aligned_m"], places=9)
            self.assertAlmostEqual(m[0]["ate_alone_m"], m[0]["ate_alone_summary_m"], places=9)
            self.assertEqual(m[1]["wake_status"], "found")
            self.assertLessEqual(m[1]["wake_steps"], 100)
            with open(os.path.join(out, "mrclam7", "s2_robot2", "summary.json")) as f:
                s2 = json.load(f)
            self.assertEqual(s2["resumed_from"], os.path.join(out, "mrclam7", "s1_robot1"))

            # the simulated life: both modes, 3 sessions each, every one at the cap and found
            sim = res["sim"]
            self.assertEqual(sorted((r["mode"], r["session"]) for r in sim),
                             [(m_, k) for m_ in ("always", "off") for k in (1, 2, 3)])
            for r in sim:
                self.assertEqual(r["status"], "ok")
                self.assertTrue(r["under_cap"])
                self.assertEqual(r["landmarks"], r["cap"])
                self.assertGreaterEqual(r["share_existing"], r["share_in_place"])
                self.assertLess(r["reloc_rmse_m"], 0.5)
                self.assertGreater(r["wake_places_found"], 0.5)
                if r["session"] > 1:
                    self.assertTrue(r["wake_found"])
                else:  # nothing has moved before the second session: the two map errors are one
                    self.assertEqual(r["map_median_error_unmoved_m"], r["map_median_error_m"])
                if r["mode"] == "off":
                    self.assertEqual(r["ne_drops"], 0)
            # the reference trajectory made here gives, on a first session, what localize gives
            # with the run's own ground-truth alignment
            d = os.path.join(out, "sim_rooms", "seed2001", "always")
            own = os.path.join(tmp, "own_loc")
            subprocess.run([BUDGET_SLAM, "localize", "-c", os.path.join(scripttest.ROOT, "config.ini"), "--map",
                            os.path.join(d, "s01"), "-i", os.path.join(out, "sim_rooms", "seed2001", "world", "revisit_s01.rawlog"),
                            "-o", own, "--quiet"], check=True, timeout=300)
            with open(os.path.join(own, "summary.json")) as f:
                own_rmse = json.load(f)["localization"]["rmse_m"]
            first = [r for r in sim if r["mode"] == "always" and r["session"] == 1][0]
            self.assertAlmostEqual(first["reloc_rmse_m"], own_rmse, places=6)

            # the same life as one process, both modes, measured on the last session's world
            joined = res["joined_rooms"]
            self.assertEqual([(j["seed"], j["mode"], j["status"]) for j in joined],
                             [(2001, "always", "ok"), (2001, "off", "ok")])
            for j in joined:
                self.assertLess(j["reloc_rmse_m"], 0.5)
                self.assertGreater(j["share_existing"], 0.8)

            # Victoria Park, EKF: the two halves are the one-shot run
            vp = res["vp"][0]
            self.assertEqual(vp["status"], "ok/ok/ok")
            self.assertEqual(vp["landmarks_one_shot"], vp["landmarks_same_id"])
            self.assertEqual(vp["landmark_max_diff_m"], 0.0)
            self.assertTrue(vp["decisions_all_identical"])
            self.assertGreater(vp["decisions_one_shot"], 0)
            self.assertEqual(vp["final_path_max_diff_m"], 0.0)

            # the outputs: the CSVs and the plot copied, the block written after the hand text
            for f in ("life_mrclam7.csv", "life_sim_rooms.csv", "life_victoria_park.csv", "life_sim_rooms.png"):
                self.assertTrue(os.path.isfile(os.path.join(res_dir, f)), f)
            with open(os.path.join(res_dir, "life_sim_rooms.csv")) as f:
                header = f.readline().strip().split(",")
            for col in ("scenario", "seed", "mode", "session", "share_existing", "reloc_rmse_m", "peak_rss_mib", "median_step_ms"):
                self.assertIn(col, header)
            with open(md) as f:
                text = f.read()
            self.assertTrue(text.startswith("# Results\n\nhand-written\n\n## A life\n\n<!-- life:begin"))
            self.assertIn("Regenerate: `tools/experiments/life --quick -o OUT`", text)
            self.assertTrue(text.rstrip().endswith("<!-- life:end -->"))

            # finished sessions are not run again: the second call runs no binary
            before = os.path.getmtime(os.path.join(d, "s03", "summary.json"))
            p = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertEqual(os.path.getmtime(os.path.join(d, "s03", "summary.json")), before)


if __name__ == "__main__":
    BUDGET_SLAM, BUDGET_SIMULATE, argv = scripttest.parse_binaries(__doc__)
    unittest.main(argv=argv)
