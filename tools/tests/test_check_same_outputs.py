#!/usr/bin/python3
"""tools/check_same_outputs.py passes one binary against itself and catches a changed output.

    test_check_same_outputs.py --budget-slam BUILD/bin/budget-slam

On the smallest shipped rawlog (paper_synthetic): `run`, `localize` and `compare --backend ekf`
with the same binary on both sides must match; the same with the after side's cap lowered
(`--after-set LandmarkBudget.max_landmarks=10`) must fail naming the files that changed; and the
normalization must hide exactly the timing fields, nothing else.
"""
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import check_same_outputs as cso  # noqa: E402

CHECKER = os.path.join(os.path.dirname(HERE), "check_same_outputs.py")
BUILD = None
SMALL = ["--rawlogs", "paper_synthetic", "--commands", "run,compare-ekf,localize"]


def check(*args):
    r = subprocess.run([sys.executable, CHECKER, "--before", BUILD, "--after", BUILD] + list(args),
                       capture_output=True, text=True)
    return r.returncode, r.stdout.splitlines(), r.stderr


class SameBinary(unittest.TestCase):
    def test_one_binary_against_itself_matches(self):
        with tempfile.TemporaryDirectory() as d:
            o = os.path.join(d, "o")
            rc, out, err = check(*SMALL, "--out", o)
            self.assertEqual(rc, 0, "\n".join(out) + err)
            self.assertRegex(out[-1],
                             r"^\d+ files identical over 3 command lines \(\d+ s, \d+ s CPU\)$")
            # the same outputs compared again, without the timing columns' rule: they differ
            again = [sys.executable, CHECKER, "--compare-only", o] + SMALL
            r = subprocess.run(again, capture_output=True, text=True)
            self.assertEqual((r.returncode, r.stdout.splitlines()[-1]), (0, out[-1].split(" (")[0]))
            r = subprocess.run(again + ["--leave-out", "csv_columns"], capture_output=True,
                               text=True)
            self.assertEqual(r.returncode, 1, r.stdout + r.stderr)
            self.assertIn("paper_synthetic/run/steps.csv: line 2 col ", r.stdout)

    def test_a_lower_cap_on_the_after_side_fails_naming_the_files(self):
        with tempfile.TemporaryDirectory() as d:
            rc, out, err = check(*SMALL, "--out", os.path.join(d, "o"),
                                 "--after-set", "LandmarkBudget.max_landmarks=10")
        self.assertEqual(rc, 1, "\n".join(out) + err)
        named = {line.split(":")[0] for line in out[:-1]}
        for rel in ["paper_synthetic/run/landmarks.csv", "paper_synthetic/run/summary.json",
                    "paper_synthetic/localize/summary.json",
                    "paper_synthetic/compare-ekf/comparison.csv"]:
            self.assertIn(rel, named)
        # the reference run of compare drops nothing: the cap does not change its map
        self.assertNotIn("paper_synthetic/compare-ekf/reference/landmarks.csv", named)
        summary = [line for line in out if line.startswith("paper_synthetic/run/summary.json:")]
        self.assertRegex(summary[0], r"^paper_synthetic/run/summary.json: key [\w.\[\]]+: ")
        self.assertRegex(out[-1], r"^\d+ of \d+ files differ over 3 command lines")

    def test_an_output_folder_in_use_is_refused(self):
        with tempfile.TemporaryDirectory() as d:
            open(os.path.join(d, "mine"), "w").close()
            rc, out, err = check(*SMALL, "--out", d)
            self.assertEqual((rc, os.listdir(d)), (2, ["mine"]))
            self.assertIn("not empty", err)


class Normalization(unittest.TestCase):
    def test_csv_timing_columns_only(self):
        a = "step,x,step_ms,rss_bytes\n0,1.5,0.25,1000\n"
        self.assertEqual(cso.norm_csv(a, cso.CSV_COLUMNS["steps.csv"]),
                         cso.norm_csv("step,x,step_ms,rss_bytes\n0,1.5,9.75,2000\n",
                                      cso.CSV_COLUMNS["steps.csv"]))
        self.assertNotEqual(cso.norm_csv(a, cso.CSV_COLUMNS["steps.csv"]),
                            cso.norm_csv("step,x,step_ms,rss_bytes\n0,1.6,0.25,1000\n",
                                         cso.CSV_COLUMNS["steps.csv"]))

    def test_csv_quoting_is_still_compared(self):
        cols = cso.CSV_COLUMNS["comparison.csv"]
        self.assertNotEqual(cso.norm_csv('run,time_s\n"mi",1\n', cols),
                            cso.norm_csv("run,time_s\nmi,2\n", cols))

    def test_markdown_time_column_only(self):
        t = "| run | ATE | time (s) |\n|---|---|---|\n| mi | 0.1 | {} |\n"
        cols = cso.MD_COLUMNS["comparison.md"]
        self.assertEqual(cso.norm_md(t.format("3.1"), cols), cso.norm_md(t.format("0.2"), cols))
        self.assertNotEqual(cso.norm_md(t.format("3.1"), cols),
                            cso.norm_md(t.replace("0.1", "0.2").format("3.1"), cols))

    def test_summary_timings_only(self):
        keys = cso.JSON_KEYS["summary.json"]
        a = '{"timings": {"steps_s": 1.5}, "counts": {"steps": 5}}'
        b = '{"timings": {"steps_s": 2.5}, "counts": {"steps": 5}}'
        c = '{"timings": {"steps_s": 1.5}, "counts": {"steps": 6}}'
        self.assertEqual(cso.norm_json(a, keys), cso.norm_json(b, keys))
        self.assertEqual(cso.first_difference(cso.norm_json(a, keys), cso.norm_json(c, keys)),
                         "key counts.steps: 5 != 6")
        self.assertEqual(cso.first_difference('{"l": [{"x": 1}]}', '{"l": [{"x": 1, "y": 2}]}'),
                         "key l[0].y only after")

    def test_progress_lines_and_seconds_of_slam_only(self):
        a = ("budget-slam: compare 53%, 2027 of 3816 steps, 405 steps/s, elapsed 0:05, ETA 0:04\n"
             "outputs in /o/before/x/ (0.33 s of SLAM)\n")
        b = "outputs in /o/before/x/ (1.25 s of SLAM)\n"
        self.assertEqual(cso.norm_stream(a), cso.norm_stream(b))
        self.assertNotEqual(cso.norm_stream(a), cso.norm_stream(b.replace("/x/", "/y/")))
        self.assertEqual(cso.norm_text("in /o/before/x", "/o/before"),
                         cso.norm_text("in /o/after/x", "/o/after"))


if __name__ == "__main__":
    if "--budget-slam" in sys.argv:
        i = sys.argv.index("--budget-slam")
        BUILD = os.path.abspath(sys.argv[i + 1])
        del sys.argv[i:i + 2]
    if BUILD is None:
        sys.exit("usage: test_check_same_outputs.py --budget-slam BUILD/bin/budget-slam")
    unittest.main()
