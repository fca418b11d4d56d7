#!/usr/bin/python3
"""Tests of tools/experiments/paper_tables: part b (Hochdorfer Table I on rooms, a few seconds)
fills exactly its marked block of a RESULTS.md and leaves the hand-written text alone; a second run
runs nothing; rawlog cutting gives the asked number of steps and ground-truth rows.

    test_paper_tables.py --budget-slam build/bin/budget-slam [unittest options]
"""
import os
import subprocess
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scripttest  # noqa: E402

EXP, ROOT = scripttest.EXP, scripttest.ROOT
SCRIPT = os.path.join(EXP, "paper_tables")
BUDGET_SLAM = BUDGET_SIMULATE = None

HAND_BEFORE = "# Results\n\nHand-written introduction.\n\n## Hochdorfer\n\n"
HAND_AFTER = "\n\n## Closing note\n\nHand-written conclusions.\n"
OLD_BLOCK = "<!-- paper_tables:b begin -->\nold table\n<!-- paper_tables:b end -->"


class PartB(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="test_paper_tables_")
        t = cls.tmp.name
        cls.results = os.path.join(t, "RESULTS.md")
        with open(cls.results, "w") as f:
            f.write(HAND_BEFORE + OLD_BLOCK + HAND_AFTER)
        cls.cmd = ["/usr/bin/python3", SCRIPT, "--only", "b", "-j", "2", "--work", os.path.join(t, "work"),
                   "--results", cls.results, "--figures", os.path.join(t, "results"),
                   "--budget-slam", BUDGET_SLAM, "--budget-simulate", BUDGET_SIMULATE]
        cls.proc = subprocess.run(cls.cmd, capture_output=True, text=True, timeout=600)
        with open(cls.results) as f:
            cls.text = f.read()

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_block_replaced_and_hand_text_kept(self):
        self.assertEqual(self.proc.returncode, 0, self.proc.stderr)
        self.assertTrue(self.text.startswith(HAND_BEFORE + "<!-- paper_tables:b begin -->\n"))
        self.assertTrue(self.text.endswith("<!-- paper_tables:b end -->" + HAND_AFTER))
        self.assertNotIn("old table", self.text)
        self.assertEqual(self.text.count("<!-- paper_tables:b begin -->"), 1)

    def test_table_has_sixteen_time_steps_and_every_run(self):
        lines = [l for l in self.text.splitlines() if l.startswith("| ")]
        header = lines[0]
        self.assertEqual(header, "| time step | none (no cap) | random | oldest | info-content | mi | coverage "
                                 "| coverage-mi |")
        body = lines[1:]
        self.assertEqual([l.split(" | ")[0][2:] for l in body],
                         [str(t) for t in [1, 25, 52, 75, 100, 125, 150, 175, 200, 225, 251, 281, 300, 325, 350, 375]]
                         + ["RMSE"])
        for l in body:
            self.assertEqual(l.count("|"), 9, l)
            self.assertNotIn("–", l)
        # time step 1 is the still start step: no error, no uncertainty
        self.assertEqual(body[0], "| 1 | " + " | ".join(["0.000 (0.000, 0.000)"] * 7) + " |")
        self.assertEqual(self.text.count("**"), 2)  # the best reducer's RMSE, once
        self.assertIn("tools/experiments/paper_tables --only b -j 2", self.text)

    def test_plots_written(self):
        for p in ("rooms_cap50_error.png", "rooms_cap50_landmarks.png"):
            path = os.path.join(self.tmp.name, "results", p)
            self.assertGreater(os.path.getsize(path), 5000, p)
            self.assertIn(f"(results/{p})", self.text)

    def test_second_run_runs_nothing_and_gives_the_same_table(self):
        p = subprocess.run(self.cmd, capture_output=True, text=True, timeout=600)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertIn("1 job(s): 1 already done, 0 to run", p.stderr)
        with open(self.results) as f:
            again = f.read()
        self.assertEqual(again, self.text)  # the time measured from scratch is kept too
        self.assertIn("From an empty work folder this part takes ", again)


class CutRawlog(unittest.TestCase):
    def test_cut_paper_synthetic_after_32_steps(self):
        pt = scripttest.load_script("paper_tables")
        with tempfile.TemporaryDirectory() as tmp:
            path = pt.cut_rawlog("paper_synthetic", 32, tmp)
            self.assertEqual(path, os.path.join(tmp, "paper_synthetic-32.rawlog"))
            with open(os.path.join(tmp, "paper_synthetic-32_ground_truth_robot_path.txt")) as f:
                rows = [l for l in f if not l.startswith("%") and l.strip()]
            self.assertEqual(len(rows), 33)
            self.assertTrue(os.path.isfile(os.path.join(tmp, "paper_synthetic-32.ini")))
            out = os.path.join(tmp, "run")
            subprocess.run([BUDGET_SLAM, "run", "-c", os.path.join(ROOT, "config.ini"), "-i", path, "-o", out,
                            "--reducer", "none", "--quiet"], check=True)
            import json
            with open(os.path.join(out, "summary.json")) as f:
                s = json.load(f)
            self.assertEqual(s["counts"]["steps"], 32)
            self.assertEqual(s["ground_truth"]["poses"], 32)


if __name__ == "__main__":
    BUDGET_SLAM, BUDGET_SIMULATE, argv = scripttest.parse_binaries(__doc__)
    unittest.main(argv=argv)
