#!/usr/bin/python3
"""Tests of tools/experiments/paper_tables: part b (Hochdorfer Table I on rooms, a few seconds)
fills exactly its marked block of a RESULTS.md and leaves the hand-written text alone; a second run
runs nothing; rawlog cutting gives the asked number of steps and ground-truth rows; part d (the map
the robot keeps) driven by a fake budget-slam whose numbers have a known answer: the traversals
each job relocalizes on, the means, the significance marks and ties, and the one-line refusal of a
budget-slam without compare --relocalize.

    test_paper_tables.py --budget-slam build/bin/budget-slam [unittest options]
"""
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scripttest  # noqa: E402
import fake_budget_slam as fake  # noqa: E402

EXP, ROOT, HERE = scripttest.EXP, scripttest.ROOT, scripttest.HERE
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


class RatioCells(unittest.TestCase):
    def test_a_ratio_undefined_on_one_seed_is_no_mean(self):
        pt = scripttest.load_script("paper_tables")
        self.assertTrue(pt.ratio_defined({1: 1.0, 2: 3.0}, {1: 0.0, 2: 4.5}))
        # seed 2: the unreduced map lost nothing and this one lost 4.5 %: x / 0, no ratio
        self.assertFalse(pt.ratio_defined({1: 1.0}, {1: 0.0, 2: 4.5}))
        self.assertFalse(pt.ratio_defined({}, {}))


class PartD(unittest.TestCase):
    """Part d with fake binaries (tests/fake_budget_slam.py as budget-slam and budget-simulate), the
    real Victoria Park rawlog (cut with rawlog-edit) and stub MRCLAM files; 20 seeds, the unreduced
    run of park seed 7 failing (as the real one diverges)."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="test_paper_tables_d_")
        t = cls.tmp.name
        os.makedirs(os.path.join(t, "bin"))
        os.makedirs(os.path.join(t, "rawlogs"))
        for b in ("budget-slam", "budget-simulate"):
            os.symlink(os.path.join(HERE, "fake_budget_slam.py"), os.path.join(t, "bin", b))
        for i in range(1, 6):
            with open(os.path.join(t, "rawlogs", f"mrclam7_robot{i}.rawlog"), "w") as f:
                f.write("stub\n")
        for ext in (".rawlog", ".ini"):
            shutil.copyfile(os.path.join(ROOT, "rawlogs", "victoria_park" + ext), os.path.join(t, "rawlogs", "victoria_park" + ext))
        cls.results = os.path.join(t, "RESULTS.md")
        cls.before = "# Results\n\n## The map the robot keeps\n\n"
        cls.after = "\n\n## Closing note\n\nHand-written.\n"
        with open(cls.results, "w") as f:
            f.write(cls.before + "<!-- paper_tables:d begin -->\nold\n<!-- paper_tables:d end -->" + cls.after)
        cls.work = os.path.join(t, "work")
        cls.cmd = ["/usr/bin/python3", SCRIPT, "--only", "d", "-j", "2", "--work", cls.work, "--results", cls.results,
                   "--figures", os.path.join(t, "results"), "--rawlogs", os.path.join(t, "rawlogs"),
                   "--budget-slam", os.path.join(t, "bin", "budget-slam"),
                   "--budget-simulate", os.path.join(t, "bin", "budget-simulate")]
        cls.log = os.path.join(t, "fake.log")
        cls.proc = subprocess.run(cls.cmd, capture_output=True, text=True, timeout=600,
                                  env=dict(os.environ, FAKE_LOG=cls.log, FAKE_REFERENCE_FAILS="park:7"))
        with open(cls.results) as f:
            cls.text = f.read()
        with open(os.path.join(cls.work, "d", "out", "jobs.txt")) as f:
            cls.jobs = f.read().splitlines()

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def table_row(self, name, cap, reducer):
        """Cells of a part d table row: the table of rawlog `name`, the row of reducer at cap."""
        block = self.text[self.text.index(f"**{name}**"):]
        block = block[:block.index("\n\n", block.index("| cap |"))]
        rows = [l.split(" | ") for l in block.splitlines() if l.startswith("| ") and not l.startswith("| cap")]
        current = None
        for r in rows:
            current = r[0][2:].strip() or current
            if current.startswith(cap) and r[1] == reducer:
                return [c.strip(" |") for c in r[2:]]
        self.fail(f"no row {name} {cap} {reducer}")

    def test_block_replaced_and_hand_text_kept(self):
        self.assertEqual(self.proc.returncode, 0, self.proc.stderr)
        self.assertTrue(self.text.startswith(self.before + "<!-- paper_tables:d begin -->\n"))
        self.assertTrue(self.text.endswith("<!-- paper_tables:d end -->" + self.after))
        self.assertNotIn("\nold\n", self.text)
        self.assertIn("tools/experiments/paper_tables --only d -j 2\n", self.text)

    def test_each_job_relocalizes_on_its_traversals(self):
        out = os.path.join(self.work, "d", "out")
        self.assertEqual(len(self.jobs), 2 * 20 * 2 + 2 * 2)  # rooms, park: 20 seeds x 2 caps; MRCLAM, VP: 2 caps
        rooms3 = [l for l in self.jobs if "/rooms/sim-rooms/ekf/cap25pct/seed3.part" in l]
        self.assertEqual(len(rooms3), 1)
        self.assertIn(f"-i {out}/rawlogs/sim-rooms-seed3.rawlog", rooms3[0])
        self.assertIn(f"--relocalize {out}/rawlogs/sim-rooms-revisit-seed3.rawlog --quiet", rooms3[0])
        mrclam = [l for l in self.jobs if "mrclam7_robot1.rawlog" in l]
        self.assertEqual(len(mrclam), 2)
        raw = os.path.join(self.tmp.name, "rawlogs")
        self.assertIn("--relocalize " + ",".join(f"{raw}/mrclam7_robot{i}.rawlog" for i in range(2, 6)), mrclam[0])
        vp = [l for l in self.jobs if "victoria_park" in l]
        self.assertEqual(len(vp), 2)
        cut = os.path.join(self.work, "d", "rawlogs")
        self.assertIn(f"-i {cut}/victoria_park-3500.rawlog", vp[0])
        self.assertIn(f"--relocalize {cut}/victoria_park-from3500.rawlog ", vp[0])
        # no ground truth: measured against one unreduced EKF run over the whole rawlog
        ref = os.path.join(self.work, "d", "victoria_park-unreduced")
        self.assertIn(f"--reference-trajectory {ref}/trajectory.tum ", vp[0])
        with open(self.log) as f:
            full = [l for l in f if l.startswith("budget-slam run ") and f"-o {ref}.part " in l]
        self.assertEqual(len(full), 1)
        self.assertIn(f"-i {os.path.join(self.tmp.name, 'rawlogs')}/victoria_park.rawlog -o ", full[0])
        self.assertIn("--reducer none --backend ekf", full[0])
        # the revisit traversals were simulated with the mapping run's seed
        with open(self.log) as f:
            sims = [l for l in f if l.startswith("budget-simulate") and "--route revisit" in l]
        self.assertEqual(len(sims), 2 * 20)
        self.assertTrue(any("--scenario park --seed 17 --route revisit" in l for l in sims))

    def test_victoria_park_is_split_at_3500_steps(self):
        pt = scripttest.load_script("paper_tables")
        cut = os.path.join(self.work, "d", "rawlogs")
        self.assertEqual(pt.rawlog_objects(os.path.join(cut, "victoria_park-3500.rawlog")), 2 * 3500)
        total = pt.rawlog_objects(os.path.join(ROOT, "rawlogs", "victoria_park.rawlog"))
        self.assertEqual(pt.rawlog_objects(os.path.join(cut, "victoria_park-from3500.rawlog")), total - 2 * 3500)

    def test_cells_are_means_over_seeds_of_ok_runs(self):
        for red in ("none", "coverage", "random"):
            cov = [fake.value("sim-rooms", red, s, "reloc_coverage_pct") for s in range(1, 21)]
            rmse = [fake.value("sim-rooms", red, s, "reloc_rmse_m") for s in range(1, 21)]
            cells = self.table_row("rooms", "25%", "none (no cap)" if red == "none" else red)
            self.assertEqual(cells[0].strip("*"), f"{statistics.fmean(cov):.1f} ± {statistics.stdev(cov):.1f}")
            self.assertTrue(cells[2].strip("*").startswith(f"{statistics.fmean(rmse):.3f} ± "), cells)
        ratio = [fake.ratio("victoria_park-3500", "mi", 1, "reloc_rmse_m")]
        self.assertEqual(self.table_row("Victoria Park", "25%", "mi")[4], f"{ratio[0]:.2f}")
        self.assertIn("| 25% (=10) | none (no cap) |", self.text)  # one-run rawlogs show the cap's number

    def test_significance_marks_and_ties(self):
        # coverage is the best map on every seed: bold, and said with its p-value; random and
        # oldest are the same map (p = 1), never bold
        row = self.table_row("park", "50%", "coverage")
        self.assertTrue(row[0].startswith("**") and row[2].startswith("**"), row)
        self.assertIn("- park at 50%, coverage [%]: **coverage** 91.9, higher than the runner-up coverage-mi 83.9 "
                      "(p < 0.0001)", self.text)
        self.assertIn("- rooms at 25%, relocalization RMSE [m]: **coverage** 0.405, lower than the runner-up "
                      "coverage-mi 0.505 (p < 0.0001)", self.text)
        # coverage and coverage-mi lose as many steps on every seed: a tie, no bold
        self.assertIn("- rooms at 25%, lost [%]: tie: coverage 7.1, coverage-mi 7.1 (p = 1.00)", self.text)
        self.assertFalse(self.table_row("rooms", "25%", "coverage")[3].startswith("**"))
        # a ratio is marked where the reducer's number differs from the unreduced map's
        self.assertTrue(self.table_row("rooms", "25%", "mi")[4].endswith(" †"))
        # one run: no test, no bold
        self.assertIn("- MRCLAM 7 at 25%, coverage [%]: highest coverage 92.0; one run, no test", self.text)
        self.assertNotIn("**", "".join(self.table_row("MRCLAM 7", "25%", "coverage")))

    def test_best_lines_say_by_how_much(self):
        import paired_stats
        rmse = {r: {sd: fake.value("sim-rooms", r, sd, "reloc_rmse_m") for sd in range(1, 21)}
                for r in ("none", "coverage", "coverage-mi", "random")}

        def margin(other):
            x = paired_stats.compare(rmse["coverage"], rmse[other])
            return (f"{x.median_diff:.3f} [{x.ci_low:.3f}, {x.ci_high:.3f}]".replace("-", "−"),
                    paired_stats.p_phrase(x.p_value))
        (d1, p1), (d2, p2) = margin("coverage-mi"), margin("random")
        self.assertTrue(d1.startswith("−0.10") and d2.startswith("−0.40"), (d1, d2))
        self.assertIn(f"- rooms at 25%, relocalization RMSE [m]: **coverage** 0.405, lower than the runner-up "
                      f"coverage-mi 0.505 (p < 0.0001); best − other: {d1} over the runner-up coverage-mi ({p1}, 20 seeds), "
                      f"{d2} over random ({p2}, 20 seeds); unreduced map {statistics.fmean(rmse['none'].values()):.3f}\n",
                      self.text)
        # one run: no test, no margin, the unreduced map for scale
        self.assertRegex(self.text, r"- MRCLAM 7 at 25%, coverage \[%\]: highest coverage 92.0; one run, no test; "
                                    r"unreduced map \d+\.\d\n")

    def test_seed_whose_unreduced_run_failed_is_left_out_everywhere(self):
        self.assertIn("Seeds left out because the unreduced run did not end ok: park 25% (seed 7); park 50% (seed 7).",
                      self.text)
        self.assertIn("- failed: step 12: the ekf estimate diverged: sim:park none 25% (seed 7); "
                      "sim:park none 50% (seed 7)", self.text)
        # the reducers' own runs of seed 7 ended ok, and still count nowhere: means over 19 seeds
        seeds = [sd for sd in range(1, 21) if sd != 7]
        cov = [fake.value("sim-park", "mi", sd, "reloc_coverage_pct") for sd in seeds]
        self.assertEqual(self.table_row("park", "50%", "mi")[0].strip("*"),
                         f"{statistics.fmean(cov):.1f} ± {statistics.stdev(cov):.1f}")
        self.assertIn("over random (p < 0.0001, 19 seeds)", self.text)

    def test_place_coverage_is_run_and_shown(self):
        self.assertTrue(all("--reducers coverage,coverage-mi,info-content,mi,oldest,place-coverage,random " in l
                            for l in self.jobs), self.jobs[0])
        self.assertEqual(len(self.table_row("rooms", "50%", "place-coverage")), 6)

    def test_mrclam_table_per_robot(self):
        self.assertIn("| cap | reducer | mrclam7_robot2 | mrclam7_robot3 | mrclam7_robot4 | mrclam7_robot5 |", self.text)
        cell = (f"{fake.value('mrclam7_robot1', 'mi', 1, 'reloc_rmse_m'):.3f} / "
                f"{fake.value('mrclam7_robot1', 'mi', 1, 'reloc_lost_pct'):.1f}")
        self.assertIn("|  | mi | " + " | ".join([cell] * 4) + " |", self.text)

    def test_pairwise_csv_has_the_tests(self):
        import csv
        with open(os.path.join(self.work, "d", "pairwise.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        r = [r for r in rows if (r["rawlog"], r["cap"], r["metric"], r["reducer_a"], r["reducer_b"])
             == ("rooms", "25%", "reloc_rmse_m", "oldest", "random")]  # the registry's (name) order
        self.assertEqual(len(r), 1)
        self.assertEqual((r[0]["n_pairs"], r[0]["p_value"], r[0]["significant"]), ("20", "1.0", "0"))
        # the same tests beside the figures, each reducer against the unreduced map too; park without seed 7
        with open(os.path.join(self.tmp.name, "results", "map_kept_pairwise.csv"), newline="") as f:
            self.assertEqual(list(csv.DictReader(f)), rows)
        r = [r for r in rows if (r["rawlog"], r["cap"], r["metric"], r["reducer_a"], r["reducer_b"])
             == ("park", "50%", "reloc_lost_pct", "none", "mi")]
        self.assertEqual((r[0]["n_pairs"], r[0]["significant"]), ("19", "1"))
        self.assertLess(float(r[0]["median_diff"]), 0)
        self.assertFalse([r for r in rows if r["metric"].endswith("_ratio") and r["reducer_a"] == "none"])
        self.assertIn("[results/map_kept_pairwise.csv](results/map_kept_pairwise.csv)", self.text)

    def test_budget_slam_without_relocalize_is_refused_in_one_line(self):
        with open(self.results) as f:
            before = f.read()
        p = subprocess.run(self.cmd, capture_output=True, text=True, timeout=300,
                           env=dict(os.environ, FAKE_NO_RELOCALIZE="1"))
        self.assertEqual(p.returncode, 1)
        self.assertIn(f"part d failed: {os.path.join(self.tmp.name, 'bin', 'budget-slam')}: this budget-slam has no "
                      "'compare --relocalize'; part d (the map the robot keeps) needs a budget-slam with relocalization",
                      p.stderr)
        with open(self.results) as f:
            self.assertEqual(f.read(), before)


if __name__ == "__main__":
    BUDGET_SLAM, BUDGET_SIMULATE, argv = scripttest.parse_binaries(__doc__)
    unittest.main(argv=argv)
