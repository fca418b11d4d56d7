#!/usr/bin/python3
"""Tests of tools/experiments/lifelong: the ratios on a hand-made steps.csv, the arguments of a
reducer/protect/admission entry, and a one-lap run (a reducer with the config's policy, one with its
own policy, the uncapped run stopped by SIGINT after 3 s) that writes the "Lifelong run" block of a
PERFORMANCE.md without touching the rest.

    test_lifelong.py --budget-slam build/bin/budget-slam --budget-simulate build/bin/budget-simulate
"""
import json
import os
import subprocess
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scripttest  # noqa: E402

EXP, ROOT = scripttest.EXP, scripttest.ROOT
SCRIPT = os.path.join(EXP, "lifelong")
BUDGET_SLAM = BUDGET_SIMULATE = None


class Ratios(unittest.TestCase):
    def test_ratios_of_a_known_run(self):
        ll = scripttest.load_script("lifelong")
        with tempfile.TemporaryDirectory() as tmp:
            # 1000 steps; the map reaches the cap of 10 at step 100. Step time 1 ms until step 899,
            # 1.5 ms over the last 100 steps (the last 10%); RSS 100 MiB at the cap, growing by
            # 1024 bytes a step after it.
            with open(os.path.join(tmp, "steps.csv"), "w") as f:
                f.write("step,t,n_landmarks,n_new,n_dropped,n_poses,x,y,yaw,var_x,var_y,var_yaw,step_ms,rss_bytes\n")
                for k in range(1000):
                    lm = min(10, k // 10)
                    ms = 1.5 if k >= 900 else 1.0
                    rss = 100 * 2**20 + max(0, k - 100) * 1024
                    f.write(f"{k},{k + 1},{lm},0,0,1,0,0,0,0,0,0,{ms},{rss}\n")
            r = ll.analyse(tmp, 10)
            self.assertEqual(r["cap_reached_step"], 100)
            self.assertAlmostEqual(r["median_ms_after_cap"], 1.0)
            self.assertAlmostEqual(r["time_ratio"], 1.5)
            self.assertAlmostEqual(r["memory_ratio"], (100 * 2**20 + 899 * 1024) / (100 * 2**20))
            self.assertAlmostEqual(r["bytes_per_step_after_cap"], 1024.0)
            self.assertEqual(r["steps"], 1000)


class PolicyEntries(unittest.TestCase):
    def test_a_name_keeps_the_config_policy_and_a_triple_sets_it(self):
        ll = scripttest.load_script("lifelong")
        self.assertEqual(ll.policy_args("mi"), ["--reducer", "mi"])
        self.assertEqual(ll.policy_args("coverage/recently_seen/always"),
                         ["--reducer", "coverage", "--set", "LandmarkBudget.protect=recently_seen",
                          "--set", "LandmarkBudget.admission=always"])
        for bad in ("coverage/recently_seen", "coverage//always", "a/b/c/d"):
            with self.assertRaises(SystemExit) as e:
                ll.policy_args(bad)
            self.assertEqual(str(e.exception), f"lifelong: --reducers entry '{bad}' is not reducer or "
                             "reducer/protect/admission")


class OneLap(unittest.TestCase):
    def test_one_lap_writes_the_section(self):
        with tempfile.TemporaryDirectory() as tmp:
            perf = os.path.join(tmp, "PERFORMANCE.md")
            before = "# Performance\n\n## Reducers\n\nhand table\n\n## Lifelong run\n\nHand-written intro.\n\n"
            after = "\n\nHand-written discussion.\n"
            ll = scripttest.load_script("lifelong")
            with open(perf, "w") as f:
                f.write(before + ll.BEGIN + "\nold\n" + ll.END + after)
            out = os.path.join(tmp, "work")
            p = subprocess.run(["/usr/bin/python3", SCRIPT, "--laps", "1", "--reducers", "random,coverage/recently_seen/always",
                                "--uncapped-budget", "3", "-o", out, "--performance-md", perf,
                                "--plot", os.path.join(tmp, "results", "lifelong.png"),
                                "--budget-slam", BUDGET_SLAM, "--budget-simulate", BUDGET_SIMULATE],
                               capture_output=True, text=True, timeout=600)
            self.assertEqual(p.returncode, 0, p.stderr)
            with open(perf) as f:
                text = f.read()
            self.assertTrue(text.startswith(before + ll.BEGIN + "\n"))
            self.assertTrue(text.endswith(ll.END + after))
            self.assertNotIn("\nold\n", text)
            rows = [l for l in text.splitlines() if l.startswith("| random |") or l.startswith("| coverage/recently_seen/always |")]
            self.assertEqual(len(rows), 2)
            with open(os.path.join(out, "lifelong.json")) as f:
                res = json.load(f)
            self.assertEqual(sorted(res), ["coverage/recently_seen/always", "none (no cap)", "random"])
            steps = res["random"]["steps"]
            for r in ("random", "coverage/recently_seen/always"):
                self.assertEqual(res[r]["steps"], steps)
                self.assertEqual(res[r]["landmarks_max"], 100)
                self.assertGreater(res[r]["time_ratio"], 0)
                self.assertGreater(res[r]["memory_ratio"], 0.5)
            # the entry's own policy, over the config's (newly_added / compete)
            with open(os.path.join(out, "coverage_recently_seen_always", "config_used.ini")) as f:
                used = f.read()
            self.assertIn("\nprotect = recently_seen\n", used)
            self.assertIn("\nadmission = always\n", used)
            # the uncapped run was stopped by SIGINT: ended cleanly, interrupted, fewer steps
            with open(os.path.join(out, "none", "summary.json")) as f:
                self.assertEqual(json.load(f)["status"], "interrupted")
            self.assertLess(res["none (no cap)"]["steps"], steps)
            self.assertGreater(res["none (no cap)"]["landmarks_end"], 100)
            self.assertIn("**No cap** (stopped with Ctrl-C after a budget of 3 s wall time)", text)
            self.assertGreater(os.path.getsize(os.path.join(tmp, "results", "lifelong.png")), 5000)
            # finished runs are not run again
            p = subprocess.run(["/usr/bin/python3", SCRIPT, "--laps", "1", "--reducers", "random,coverage/recently_seen/always",
                                "--uncapped-budget", "3", "-o", out, "--budget-slam", BUDGET_SLAM,
                                "--budget-simulate", BUDGET_SIMULATE], capture_output=True, text=True, timeout=600)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertIn("3 run(s), 3 already done, running 0", p.stderr)


if __name__ == "__main__":
    BUDGET_SLAM, BUDGET_SIMULATE, argv = scripttest.parse_binaries(__doc__)
    unittest.main(argv=argv)
