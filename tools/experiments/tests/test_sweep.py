#!/usr/bin/python3
"""Tests of tools/experiments/sweep: the tiny sweep (2 reducers x 2 caps on the kf-slam demo) gives
exactly the expected results.csv rows and non-empty plots, and a sweep killed after its first job
runs only the rest when started again; with a fake budget-slam whose numbers have a known answer
(tests/fake_budget_slam.py), the pairwise comparisons paired by seed (p-values, intervals, marks),
the relocalization columns carried through, empty and `nan` fields skipped, and the relocalize key.

    test_sweep.py --budget-slam build/bin/budget-slam [unittest options]
"""
import csv
import math
import os
import statistics
import signal
import subprocess
import sys
import tempfile
import textwrap
import time
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scripttest  # noqa: E402

EXP, ROOT, HERE = scripttest.EXP, scripttest.ROOT, scripttest.HERE
SWEEP = os.path.join(EXP, "sweep")
TINY = os.path.join(EXP, "experiments", "tiny.ini")
import sweeplib  # noqa: E402
import paired_stats  # noqa: E402
import fake_budget_slam as fake  # noqa: E402

BUDGET_SLAM = None

REDUCERS = ["none", "coverage", "mi"]
CAPS = ["20", "50%"]
# Every run of the kf-slam demo has ground truth, so every metric is finite.
METRICS_REFERENCE = [
    "status_ok", "gt_trajectory_rmse_aligned_m", "gt_trajectory_rpe_10m_m", "landmarks",
    "landmarks_reduction_pct", "poses", "poses_reduction_pct", "evictions", "refused", "ref_ate_m",
    "ref_ale_m", "ref_are_deg", "ref_ud_pct", "ref_ud_std_factor", "ref_eig_min", "ref_eig_max",
    "gt_trajectory_rmse_m", "gt_trajectory_max_m", "gt_landmark_rmse_m", "gt_landmark_rmse_aligned_m",
    "nees_mean", "time_s", "reloc_coverage_pct", "reloc_mean_landmarks", "step_ms_mean", "step_ms_max",
    "peak_rss_bytes", "steps"]
METRICS_REDUCED = METRICS_REFERENCE + ["cap_landmarks"]
PLOTS = ["kf-slam_demo__ekf__error_vs_cap.png"] + [
    f"kf-slam_demo__ekf__cap{c}__{kind}.png" for c in ("20", "50pct") for kind in ("landmarks", "error", "step_time")]
JOB_DIRS = ["runs/main/kf-slam_demo/ekf/cap20/seed1", "runs/main/kf-slam_demo/ekf/cap50pct/seed1"]


def run_sweep(out, *extra, budget_slam=None):
    return subprocess.run(["/usr/bin/python3", SWEEP, TINY, "-o", out, "-j", "2",
                           "--budget-slam", budget_slam or BUDGET_SLAM, *extra],
                          capture_output=True, text=True, timeout=300)


class TinySweep(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="test_sweep_")
        cls.out = os.path.join(cls.tmp.name, "out")
        cls.proc = run_sweep(cls.out)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_exit_status(self):
        self.assertEqual(self.proc.returncode, 0, self.proc.stderr)

    def test_results_have_exactly_the_expected_rows(self):
        with open(os.path.join(self.out, "results.csv"), newline="") as f:
            reader = csv.reader(f)
            self.assertEqual(next(reader), ["rawlog", "backend", "reducer", "cap", "seed", "metric", "value"])
            rows = list(reader)
        expected = sorted(("kf-slam_demo", "ekf", r, c, "1", m)
                          for r in REDUCERS for c in CAPS
                          for m in (METRICS_REFERENCE if r == "none" else METRICS_REDUCED))
        self.assertEqual(len(rows), 2 * (28 + 2 * 29))
        self.assertEqual(sorted(tuple(r[:6]) for r in rows), expected)
        for r in rows:
            float(r[6])
        value = {tuple(r[:6]): float(r[6]) for r in rows}
        # the unreduced demo keeps 70 landmarks: 50% is a cap of 35, and each reducer keeps exactly the cap
        self.assertEqual(value[("kf-slam_demo", "ekf", "none", "20", "1", "landmarks")], 70)
        for red in ("coverage", "mi"):
            self.assertEqual(value[("kf-slam_demo", "ekf", red, "50%", "1", "cap_landmarks")], 35)
            self.assertEqual(value[("kf-slam_demo", "ekf", red, "50%", "1", "landmarks")], 35)
            self.assertEqual(value[("kf-slam_demo", "ekf", red, "20", "1", "landmarks")], 20)
            self.assertEqual(value[("kf-slam_demo", "ekf", red, "20", "1", "status_ok")], 1)

    def test_plots_are_nonempty_pngs(self):
        self.assertEqual(sorted(os.listdir(os.path.join(self.out, "plots"))), sorted(PLOTS))
        for p in PLOTS:
            with open(os.path.join(self.out, "plots", p), "rb") as f:
                data = f.read()
            self.assertTrue(data.startswith(b"\x89PNG\r\n\x1a\n"), p)
            self.assertGreater(len(data), 5000, p)

    def test_job_list_has_one_full_command_line_a_job(self):
        with open(os.path.join(self.out, "jobs.txt")) as f:
            lines = f.read().splitlines()
        self.assertEqual(len(lines), 2)
        for line, cap, d in zip(lines, ("20", "35"), JOB_DIRS):
            self.assertIn(f"{BUDGET_SLAM} compare -c {ROOT}/config.ini -i {ROOT}/rawlogs/kf-slam_demo.rawlog", line)
            self.assertIn(f"--reducers coverage,mi --cap {cap} --backend ekf --set LandmarkBudget.seed=1", line)
            self.assertIn(f"mv -T {self.out}/{d}.part {self.out}/{d};", line)

    def test_report_has_the_tables_and_plots(self):
        with open(os.path.join(self.out, "report.md")) as f:
            text = f.read()
        self.assertIn("| reducer | cap 20 | cap 50% (=35) |", text)
        for p in PLOTS:
            self.assertIn(f"(plots/{p})", text)

    def test_second_run_runs_nothing(self):
        stamp = os.stat(os.path.join(self.out, JOB_DIRS[0], "comparison.csv")).st_mtime_ns
        p = run_sweep(self.out)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertIn("2 job(s): 2 already done, 0 to run", p.stderr)
        self.assertEqual(os.stat(os.path.join(self.out, JOB_DIRS[0], "comparison.csv")).st_mtime_ns, stamp)


class KilledSweepResumes(unittest.TestCase):
    def test_killed_after_first_job_then_only_the_rest_runs(self):
        with tempfile.TemporaryDirectory(prefix="test_sweep_kill_") as tmp:
            out = os.path.join(tmp, "out")
            # budget-slam stand-in: the first compare is real; any later one leaves a half-written
            # output folder and hangs until killed, as a job caught by the kill would.
            wrapper = os.path.join(tmp, "budget-slam")
            with open(wrapper, "w") as f:
                f.write(textwrap.dedent(f"""\
                    #!/bin/bash
                    if [ "$1" = compare ]; then
                      if ! mkdir {tmp}/first-compare 2>/dev/null; then
                        while [ $# -gt 0 ]; do [ "$1" = -o ] && out="$2"; shift; done
                        mkdir -p "$out" && echo "run,reducer" > "$out/comparison.csv"
                        exec sleep 300
                      fi
                    fi
                    exec {BUDGET_SLAM} "$@"
                    """))
            os.chmod(wrapper, 0o755)
            proc = subprocess.Popen(["/usr/bin/python3", SWEEP, TINY, "-o", out, "-j", "2", "--budget-slam", wrapper],
                                    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
            deadline = time.time() + 120
            finished = []
            while time.time() < deadline and not finished:
                finished = [d for d in JOB_DIRS if os.path.isdir(os.path.join(out, d))]
                time.sleep(0.05)
            time.sleep(0.3)  # the hanging job has written its partial output by now
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
            self.assertEqual(len(finished), 1, "exactly one job must have finished before the kill")
            first = finished[0]
            other = [d for d in JOB_DIRS if d != first][0]
            self.assertFalse(os.path.exists(os.path.join(out, other)))
            self.assertTrue(os.path.isfile(os.path.join(out, other + ".part", "comparison.csv")))
            stamp = os.stat(os.path.join(out, first, "comparison.csv")).st_mtime_ns
            log_first = os.path.join(out, "logs", first.replace("/", "_") + ".log")
            log_stamp = os.stat(log_first).st_mtime_ns

            p = run_sweep(out)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertIn("2 job(s): 1 already done, 1 to run", p.stderr)
            self.assertEqual(p.stderr.count("[job "), 1, p.stderr)
            self.assertIn(f"[job 1/1] {other} ", p.stderr)
            self.assertEqual(os.stat(os.path.join(out, first, "comparison.csv")).st_mtime_ns, stamp)
            self.assertEqual(os.stat(log_first).st_mtime_ns, log_stamp)
            self.assertFalse(os.path.exists(os.path.join(out, other + ".part")))
            with open(os.path.join(out, "results.csv")) as f:
                self.assertEqual(sum(1 for _ in f), 1 + 2 * (28 + 2 * 29))


class PairwiseWithFakeBudgetSlam(unittest.TestCase):
    """Twelve seeds of four reducers on one file rawlog, relocalizing on another, with the fake."""

    SEEDS = range(1, 13)

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="test_sweep_fake_")
        t = cls.tmp.name
        cls.out = os.path.join(t, "out")
        exp = os.path.join(t, "fake.ini")
        with open(exp, "w") as f:
            f.write(textwrap.dedent("""\
                [sweep]
                rawlogs = rawlogs/rooms.rawlog
                reducers = coverage mi random oldest
                caps = 10
                seeds = 1-12
                metrics = reloc_coverage_pct
                relocalize = rawlogs/park.rawlog
                """))
        cls.proc = subprocess.run(["/usr/bin/python3", SWEEP, exp, "-o", cls.out, "-j", "2", "--no-plots",
                                   "--budget-slam", os.path.join(HERE, "fake_budget_slam.py")],
                                  capture_output=True, text=True, timeout=300, cwd=ROOT)
        with open(os.path.join(cls.out, "pairwise.csv"), newline="") as f:
            cls.pairs = list(csv.DictReader(f))
        with open(os.path.join(cls.out, "report.md")) as f:
            cls.report = f.read()

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def designed(self, reducer, metric):
        return [fake.value("rooms", reducer, s, metric) for s in self.SEEDS]

    def pair(self, metric, a, b):
        rows = [r for r in self.pairs if (r["metric"], r["reducer_a"], r["reducer_b"]) == (metric, a, b)]
        self.assertEqual(len(rows), 1, (metric, a, b))
        return rows[0]

    def test_every_pair_on_the_main_error_and_the_asked_metric(self):
        self.assertEqual(self.proc.returncode, 0, self.proc.stderr)
        self.assertEqual(list(self.pairs[0]), ["rawlog", "backend", "cap", "metric", "reducer_a", "reducer_b",
                                               "n_pairs", "median_diff", "ci_low", "ci_high", "p_value", "significant"])
        runs = ["none", "coverage", "mi", "random", "oldest"]
        expected = [(m, a, b) for m in ("gt_trajectory_rmse_aligned_m", "reloc_coverage_pct")
                    for i, a in enumerate(runs) for b in runs[i + 1:]]
        self.assertEqual([(r["metric"], r["reducer_a"], r["reducer_b"]) for r in self.pairs], expected)
        self.assertTrue(all(r["rawlog"] == "rooms" and r["cap"] == "10" and r["n_pairs"] == "12" for r in self.pairs))

    def test_numbers_equal_the_statistics_of_the_designed_values(self):
        for metric in ("gt_trajectory_rmse_aligned_m", "reloc_coverage_pct"):
            a, b = self.designed("coverage", metric), self.designed("mi", metric)
            r = self.pair(metric, "coverage", "mi")
            self.assertAlmostEqual(float(r["p_value"]), paired_stats.wilcoxon_p(a, b), places=15)
            self.assertLess(float(r["p_value"]), 0.01)
            self.assertEqual(r["significant"], "1")
            self.assertAlmostEqual(float(r["median_diff"]), statistics.median(x - y for x, y in zip(a, b)), places=12)
            low, high = paired_stats.bootstrap_median_ci(a, b)
            self.assertAlmostEqual(float(r["ci_low"]), low, places=12)
            self.assertAlmostEqual(float(r["ci_high"]), high, places=12)
        same = self.pair("gt_trajectory_rmse_aligned_m", "random", "oldest")  # the same map on every seed
        self.assertEqual((same["median_diff"], same["ci_low"], same["ci_high"], same["p_value"], same["significant"]),
                         ("0.0", "0.0", "0.0", "1.0", "0"))

    def test_report_marks_only_significant_differences(self):
        self.assertIn("| 10 | coverage | mi | 12 | ", self.report)
        lines = [l for l in self.report.splitlines() if l.startswith("| 10 | coverage | mi | 12 |")]
        self.assertEqual(len(lines), 2)
        # twelve pairs all one way: exact p = 2 / 2^12
        self.assertTrue(lines[0].endswith("| 0.00049 | **coverage lower** |"), lines[0])  # error: coverage lower
        self.assertTrue(lines[1].endswith("| 0.00049 | **mi lower** |"), lines[1])  # coverage: mi's is lower
        same = [l for l in self.report.splitlines() if l.startswith("| 10 | random | oldest | 12 |")]
        self.assertTrue(all(l.endswith("| 1.00 |  |") for l in same), same)

    def test_relocalization_columns_carried_and_empty_or_nan_fields_skipped(self):
        with open(os.path.join(self.out, "results.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        metrics = {r["metric"] for r in rows}
        for m in ("reloc_coverage_pct", "reloc_mean_landmarks", "reloc_rmse_m", "reloc_max_m", "reloc_lost_pct",
                  "reloc_traversal_coverage_pct", "reloc_rmse_ratio", "reloc_lost_ratio", "ref_ate_m", "time_s"):
            self.assertIn(m, metrics)
        for m in ("ref_ale_m", "ref_ud_pct", "nees_mean", "ref_are_deg", "ref_eig_min", "ref_eig_max", "gt_landmark_rmse_aligned_m"):
            self.assertNotIn(m, metrics)  # written empty, `nan` or null by the fake
        v = {(r["reducer"], r["seed"], r["metric"]): float(r["value"]) for r in rows}
        self.assertEqual(v[("mi", "7", "reloc_rmse_m")], fake.value("rooms", "mi", 7, "reloc_rmse_m"))

    def test_relocalization_csv_is_collected_per_traversal(self):
        with open(os.path.join(self.out, "relocalization.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        self.assertEqual(list(rows[0]), ["rawlog", "backend", "reducer", "cap", "seed", "traversal", "metric", "value"])
        # 12 seeds x 5 runs x 1 traversal x 4 numbers (nees_mean is empty)
        self.assertEqual(len(rows), 12 * 5 * 4)
        self.assertEqual({r["traversal"] for r in rows}, {"park"})
        self.assertEqual({r["metric"] for r in rows}, {"rmse_m", "max_m", "lost_pct", "coverage_pct"})
        v = {(r["reducer"], r["seed"], r["metric"]): float(r["value"]) for r in rows}
        self.assertEqual(v[("coverage", "3", "lost_pct")], fake.value("rooms", "coverage", 3, "reloc_lost_pct"))

    def test_jobs_pass_the_traversals(self):
        with open(os.path.join(self.out, "jobs.txt")) as f:
            lines = f.read().splitlines()
        self.assertEqual(len(lines), 12)
        self.assertTrue(all(f"--relocalize {ROOT}/rawlogs/park.rawlog --quiet" in l for l in lines))


class SlurmDefaults(unittest.TestCase):
    """Issue 25: without --cpus-per-task a task asks for 4 CPUs, or for the largest node's count
    when the partition has no node that large (a 2-core node), as sinfo reports it."""

    def fake_sinfo(self, tmp, output):
        path = os.path.join(tmp, "sinfo")
        with open(path, "w") as f:
            f.write("#!/bin/sh\n" + "".join(f"echo '{line}'\n" for line in output))
        os.chmod(path, 0o755)

    def test_default_cpus_per_task_fits_the_largest_node(self):
        import slurmlib
        old_path = os.environ["PATH"]
        with tempfile.TemporaryDirectory(prefix="test_slurm_defaults_") as tmp:
            os.environ["PATH"] = tmp + os.pathsep + old_path
            try:
                self.fake_sinfo(tmp, ["2"])
                self.assertEqual(slurmlib.default_cpus_per_task("local"), 2)
                self.fake_sinfo(tmp, ["2", "16+"])
                self.assertEqual(slurmlib.default_cpus_per_task(), 4)
                self.fake_sinfo(tmp, [])
                self.assertIsNone(slurmlib.default_cpus_per_task())
                os.environ["PATH"] = tmp  # no sinfo at all (only an empty folder and this one)
                os.remove(os.path.join(tmp, "sinfo"))
                self.assertIsNone(slurmlib.default_cpus_per_task())
            finally:
                os.environ["PATH"] = old_path


class Readers(unittest.TestCase):
    def test_steps_csv_with_empty_and_nan_fields_reads_them_as_nan(self):
        with tempfile.TemporaryDirectory() as tmp:
            with open(os.path.join(tmp, "steps.csv"), "w") as f:
                f.write("step,t,x,var_x\n0,1.5,0.25,\n1,2.5,nan,0.01\n")
            s = sweeplib.read_steps(tmp)
            self.assertEqual(list(s["step"]), [0, 1])
            self.assertEqual(s["x"][0], 0.25)
            self.assertTrue(math.isnan(s["var_x"][0]) and math.isnan(s["x"][1]))
            self.assertEqual(s["var_x"][1], 0.01)

    def test_comparison_fields_empty_or_nan_give_no_row_and_new_columns_pass(self):
        self.assertIsNone(sweeplib.as_number(""))
        self.assertIsNone(sweeplib.as_number("nan"))
        self.assertIsNone(sweeplib.as_number("inf"))
        self.assertEqual(sweeplib.as_number("2.5"), 2.5)


class ExperimentFile(unittest.TestCase):
    def write(self, tmp, text):
        path = os.path.join(tmp, "e.ini")
        with open(path, "w") as f:
            f.write(textwrap.dedent(text))
        return path

    def test_percentage_caps_round_half_up_and_stay_positive(self):
        self.assertEqual(sweeplib.resolve_cap("25%", 70), 18)   # 17.5 -> 18
        self.assertEqual(sweeplib.resolve_cap("50%", 151), 76)  # 75.5 -> 76
        self.assertEqual(sweeplib.resolve_cap("1%", 23), 1)
        self.assertEqual(sweeplib.resolve_cap("40", 1000), 40)

    def test_groups_expand_to_the_product_and_seeds_to_sim_rawlogs(self):
        with tempfile.TemporaryDirectory() as tmp:
            path = self.write(tmp, """\
                [sweep]
                reducers = mi coverage
                caps = 10, 25%
                [group real]
                rawlogs = rawlogs/kf-slam_demo.rawlog, rawlogs/rooms.rawlog
                [group sim]
                rawlogs = sim:rooms sim:lifelong:2
                backends = ekf, graph
                seeds = 1-3, 7
                """)
            exp = sweeplib.Experiment(path, os.path.join(tmp, "o"), "/bin/true", "/bin/true")
            self.assertEqual(len(exp.jobs), 2 * 2 + 2 * 2 * 2 * 4)
            self.assertEqual(len(exp.simulations), 2 * 4)
            self.assertIn(os.path.join(tmp, "o", "rawlogs", "sim-lifelong-2laps-seed7.rawlog"), exp.simulations)
            self.assertEqual(len(exp.baselines), 2 + 2 * 2 * 4)
            self.assertIn("--laps 2", exp.simulation_command(
                os.path.join(tmp, "o", "rawlogs", "sim-lifelong-2laps-seed7.rawlog")))

    def test_relocalize_route_simulates_the_other_route_with_the_jobs_seed(self):
        with tempfile.TemporaryDirectory() as tmp:
            path = self.write(tmp, """\
                [sweep]
                reducers = mi
                caps = 10
                [group sim]
                rawlogs = sim:rooms sim:lifelong:2
                seeds = 4-5
                relocalize = route:revisit rawlogs/park.rawlog
                [group plain]
                rawlogs = rawlogs/kf-slam_demo.rawlog
                """)
            o = os.path.join(tmp, "o")
            exp = sweeplib.Experiment(path, o, "/bin/true", "/bin/true")
            self.assertEqual(len(exp.simulations), 2 * 2 * 2)  # two scenarios x two seeds x (own route, revisit)
            revisit = os.path.join(o, "rawlogs", "sim-lifelong-2laps-revisit-seed5.rawlog")
            self.assertIn("--scenario lifelong --seed 5 --laps 2 --route revisit -o ", exp.simulation_command(revisit))
            self.assertNotIn("--route", exp.simulation_command(os.path.join(o, "rawlogs", "sim-rooms-seed4.rawlog")))
            job = [j for j in exp.jobs if j.rawlog.label == "sim:lifelong:2" and j.seed == 5][0]
            self.assertEqual(job.traversals, [("sim:lifelong:2:revisit", revisit),
                                              ("park", os.path.join(ROOT, "rawlogs", "park.rawlog"))])
            self.assertIn(f"--relocalize {revisit},{ROOT}/rawlogs/park.rawlog --quiet", exp.job_command(job))
            self.assertNotIn("--reference-trajectory", exp.job_command(job))
            plain = [j for j in exp.jobs if j.group["name"] == "plain"][0]
            self.assertEqual(plain.traversals, [])
            self.assertNotIn("--relocalize", exp.job_command(plain))
            # /bin/true lists no option: the experiment is refused before anything runs
            with self.assertRaisesRegex(sweeplib.ExperimentError, "this budget-slam has no 'compare --relocalize'"):
                sweeplib.check_relocalization_support(exp)

    def test_no_cap_is_passed_as_none_and_empty_fields_are_missing_values(self):
        self.assertEqual(sweeplib.resolve_cap("none", 70), "none")
        with tempfile.TemporaryDirectory() as tmp:
            path = self.write(tmp, """\
                [sweep]
                rawlogs = rawlogs/paper_synthetic.rawlog
                backends = graph
                reducers = mi
                caps = none
                set = MutualInformationReducer.mode=objective
                """)
            exp = sweeplib.Experiment(path, os.path.join(tmp, "o"), "/bin/true", "/bin/true")
            self.assertEqual(len(exp.jobs), 1)
            self.assertEqual(exp.baselines, {})
            job = exp.jobs[0]
            self.assertTrue(job.rel.endswith(os.path.join("graph", "capnone", "seed1")), job.rel)
            self.assertIn("--cap none --backend graph", exp.job_command(job))
            # comparison.csv as budget-slam writes it without ground truth: a metric that does not
            # apply is an empty field, and no row of results.csv.
            os.makedirs(job.folder)
            header = "run,reducer,backend,status,cap,landmarks,ref_ate_m,gt_trajectory_rmse_m,time_s\n"
            with open(os.path.join(job.folder, "comparison.csv"), "w") as f:
                f.write(header + "reference,none,graph,ok,,23,0,,0.5\nmi,mi,graph,ok,,14,0.15,,0.7\n")
            rows = sweeplib.job_rows(job)
            metrics = {(r["reducer"], r["metric"]): r["value"] for r in rows}
            self.assertEqual(metrics[("mi", "ref_ate_m")], "0.15")
            self.assertEqual(metrics[("none", "landmarks")], "23")
            self.assertFalse(any(m in ("gt_trajectory_rmse_m", "cap_landmarks") for _, m in metrics))

    def test_bad_files_are_refused_with_the_key_named(self):
        with tempfile.TemporaryDirectory() as tmp:
            cases = [("[sweep]\nrawlogs = rawlogs/rooms.rawlog\nreducers = mi\ncaps = 10\nreducer = mi\n",
                      "unknown key 'reducer'"),
                     ("[sweep]\nrawlogs = rawlogs/rooms.rawlog\nreducers = mi\ncaps = 0\n", "caps: '0'"),
                     ("[sweep]\nrawlogs = rawlogs/rooms.rawlog\nreducers = mi\ncaps = 1x\n", "caps: '1x'"),
                     ("[sweep]\nrawlogs = nowhere.rawlog\nreducers = mi\ncaps = 10\n", "'nowhere.rawlog' not found"),
                     ("[sweep]\nrawlogs = rawlogs/rooms.rawlog\nreducers = mi\ncaps = 10\nbackends = ukf\n",
                      "backend 'ukf'"),
                     ("[sweep]\nrawlogs = rawlogs/rooms.rawlog\nreducers = mi\ncaps = 10\nseeds = 3-1\n",
                      "empty range '3-1'"),
                     ("[sweep]\nrawlogs = rawlogs/rooms.rawlog\nreducers = mi\ncaps = 10\nrelocalize = route:revisit\n",
                      "[sweep] relocalize 'route:revisit' needs sim: rawlogs, and 'rawlogs/rooms.rawlog' is a file"),
                     ("[sweep]\nrawlogs = sim:rooms\nreducers = mi\ncaps = 10\nrelocalize = nowhere.rawlog\n",
                      "relocalize: 'nowhere.rawlog' not found"),
                     ("[sweep]\nrawlogs = sim:rooms\nreducers = mi\ncaps = 10\nrelocalize = route:re/visit\n",
                      "relocalize: 'route:re/visit' is not route:<name>"),
                     ("[sweep]\nrawlogs = rawlogs/rooms.rawlog\nreducers = mi\ncaps = 10\nmetrics = ate-m\n",
                      "metrics: 'ate-m' is not a metric name"),
                     ("[sweep]\nrawlogs = rawlogs/rooms.rawlog\nreducers = mi\ncaps = 10\n"
                      "reference_trajectory = rawlogs/rooms_ground_truth.txt\n",
                      "[sweep] reference_trajectory needs 'relocalize'"),
                     ("[sweep]\nrawlogs = rawlogs/rooms.rawlog\nreducers = mi\ncaps = 10\n"
                      "relocalize = rawlogs/park.rawlog\nreference_trajectory = nowhere.tum\n",
                      "reference_trajectory '" + os.path.join(ROOT, "nowhere.tum") + "' not found")]
            for text, message in cases:
                path = self.write(tmp, text)
                p = subprocess.run(["/usr/bin/python3", SWEEP, path, "-o", os.path.join(tmp, "o"),
                                    "--budget-slam", BUDGET_SLAM], capture_output=True, text=True, cwd=ROOT)
                self.assertEqual(p.returncode, 2, text)
                self.assertIn(message, p.stderr)


if __name__ == "__main__":
    BUDGET_SLAM, _, argv = scripttest.parse_binaries(__doc__)
    unittest.main(argv=argv)
