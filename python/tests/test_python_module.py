#!/usr/bin/python3
"""Tests of the budget_slam Python module against the budget-slam command line on the same runs:
run() and compare() give the CLI's numbers, reducer_scores() the scores the CLI logs in
evictions.csv (active reducer and shadows) from its state dumps and a hand computation, and bad
arguments raise exceptions carrying the CLI's one-line message.

    PYTHONPATH=build/python test_python_module.py --budget-slam build/bin/budget-slam
"""
import argparse
import csv
import json
import math
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
import unittest
import unittest.mock
import warnings

import numpy as np

import budget_slam

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
CONFIG = os.path.join(ROOT, "config.ini")
DEMO = os.path.join(ROOT, "rawlogs", "kf-slam_demo.rawlog")
BUDGET_SLAM = None
TIMING_COLUMNS = {"step_ms", "step_cpu_ms", "rss_bytes", "time_s"}


def cli(*args):
    return subprocess.run([BUDGET_SLAM, *args], capture_output=True, text=True, timeout=300)


def csv_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def as_value(text):
    """A CSV cell as the module gives it: a number (empty = NaN) or the text."""
    try:
        return float(text) if text != "" else math.nan
    except ValueError:
        return text


def assertColumnsEqual(tc, table, rows, skip=()):
    """A structured array equals the CLI's CSV rows, column by column, exactly (NaN = NaN)."""
    tc.assertEqual(len(table), len(rows))
    for name in rows[0].keys() if rows else []:
        if name in skip:
            continue
        for k, r in enumerate(rows):
            want, got = as_value(r[name]), table[name][k]
            if isinstance(want, float):
                if math.isnan(want) and isinstance(got, str):  # an empty text field
                    tc.assertEqual(got, "", f"{name} row {k}")
                elif math.isnan(want):
                    tc.assertTrue(math.isnan(float(got)), f"{name} row {k}")
                else:
                    tc.assertEqual(float(got), want, f"{name} row {k}")
            else:
                tc.assertEqual(str(got), want, f"{name} row {k}")


def without_timings(summary):
    s = dict(summary)
    s.pop("timings", None)
    return s


class RunMatchesTheCommandLine(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="test_python_module_")
        cls.cli_dir = os.path.join(cls.tmp.name, "cli")
        p = cli("run", "-c", CONFIG, "-i", DEMO, "-o", cls.cli_dir, "--reducer", "mi", "--cap", "20",
                "--set", "LandmarkBudget.seed=3", "--set", "LandmarkBudget.dump_states=true", "--quiet")
        assert p.returncode == 0, p.stderr
        cls.py_dir = os.path.join(cls.tmp.name, "py")
        cls.r = budget_slam.run(CONFIG, DEMO, {"LandmarkBudget.seed": 3, "LandmarkBudget": {"dump_states": True}},
                                outdir=cls.py_dir, reducer="mi", cap=20)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_summary_is_the_cli_summary(self):
        with open(os.path.join(self.cli_dir, "summary.json")) as f:
            want = json.load(f)
        self.assertEqual(without_timings(self.r["summary"]), without_timings(want))
        self.assertEqual(self.r["summary"]["counts"]["landmarks_final"], 20)
        self.assertEqual(self.r["outdir"], self.py_dir)

    def test_summary_read_through_the_run_layer(self):
        path = os.path.join(self.cli_dir, "summary.json")
        with open(path) as f:
            want = json.load(f)
        got = budget_slam._core.read_summary(path)
        self.assertEqual(got["json"], want)
        self.assertEqual((got["status"], got["ok"], got["error"], got["exit_code"]), ("ok", True, "", 0))
        # Every key the run layer writes is one summary_keys() lists; the rest were given.
        given = {"rawlog", "sidecar_ini", "config", "started", "session_state"}
        self.assertEqual(set(want) - given, set(want) & set(budget_slam._core.summary_keys()))

    def test_steps_trajectory_landmarks_evictions_are_the_cli_numbers(self):
        assertColumnsEqual(self, self.r["steps"], csv_rows(os.path.join(self.cli_dir, "steps.csv")),
                           skip=TIMING_COLUMNS)
        self.assertEqual(self.r["steps"].dtype["step"], np.int64)
        self.assertEqual(len(self.r["steps"]), 249)
        assertColumnsEqual(self, self.r["landmarks"], csv_rows(os.path.join(self.cli_dir, "landmarks.csv")))
        assertColumnsEqual(self, self.r["evictions"], csv_rows(os.path.join(self.cli_dir, "evictions.csv")))
        tum = np.loadtxt(os.path.join(self.cli_dir, "trajectory.tum"))
        np.testing.assert_array_equal(self.r["trajectory"]["t"], tum[:, 0])
        np.testing.assert_array_equal(self.r["trajectory"]["x"], tum[:, 1])
        np.testing.assert_array_equal(self.r["trajectory"]["y"], tum[:, 2])
        # yaw from the quaternion, against the online yaw of steps.csv (one EKF pose a step)
        np.testing.assert_allclose(self.r["trajectory"]["yaw"], self.r["steps"]["yaw"], atol=1e-12)
        self.assertEqual(len(self.r["ground_truth"]), len(tum))

    def test_state_dumps_are_written_as_asked(self):
        states = os.listdir(os.path.join(self.py_dir, "states"))
        self.assertEqual(sorted(states), sorted(os.listdir(os.path.join(self.cli_dir, "states"))))
        self.assertGreater(len(states), 10)

    def test_two_sessions_with_resume_equal_one_run(self):
        with tempfile.TemporaryDirectory() as d:
            one = budget_slam.run(CONFIG, DEMO, outdir=os.path.join(d, "one"), cap=10)
            budget_slam.run(CONFIG, DEMO, outdir=os.path.join(d, "a"), cap=10, max_steps=60)
            b = budget_slam.run(CONFIG, DEMO, outdir=os.path.join(d, "b"), cap=10,
                                resume=os.path.join(d, "a"), skip_steps=60)
            self.assertEqual(b["summary"]["resumed_from"], os.path.join(d, "a"))
            self.assertEqual(list(b["landmarks"]["id"]), list(one["landmarks"]["id"]))
            self.assertEqual(float(np.max(np.abs(b["landmarks"]["x"] - one["landmarks"]["x"]))), 0.0)
            with self.assertRaises(budget_slam.Error) as e:
                budget_slam.run(CONFIG, DEMO, outdir=os.path.join(d, "c"), cap=12,
                                resume=os.path.join(d, "a"))
            self.assertIn("[LandmarkBudget] max_landmarks = 12, the saved session had 10", str(e.exception))
            self.assertFalse(os.path.exists(os.path.join(d, "c")))

    def test_in_memory_config_and_temporary_folder(self):
        # config as a dict (BudgetSlamApp::params), no output folder: the same map as the CLI with
        # the same ini as a file, and nothing left in the temporary folder.
        config = {"MappingApplication": {"rawlog_file": DEMO, "max_steps": 120},
                  "LandmarkBudget": {"reducer": "info-content", "max_landmarks": 15}}
        ini = os.path.join(self.tmp.name, "mem.ini")
        with open(ini, "w") as f:
            f.write("[MappingApplication]\nrawlog_file = %s\nmax_steps = 120\n"
                    "[LandmarkBudget]\nreducer = info-content\nmax_landmarks = 15\n" % DEMO)
        out = os.path.join(self.tmp.name, "mem_cli")
        p = cli("run", "-c", ini, "-o", out, "--quiet")
        self.assertEqual(p.returncode, 0, p.stderr)
        scratch = os.path.join(self.tmp.name, "scratch")
        os.makedirs(scratch)
        saved, budget_slam.tempfile.tempdir = budget_slam.tempfile.tempdir, scratch
        try:
            r = budget_slam.run(config)
        finally:
            budget_slam.tempfile.tempdir = saved
        self.assertIsNone(r["outdir"])
        self.assertEqual(os.listdir(scratch), [])
        self.assertEqual(len(r["steps"]), 120)
        assertColumnsEqual(self, r["landmarks"], csv_rows(os.path.join(out, "landmarks.csv")))
        self.assertEqual(r["summary"]["reducer"], "info-content")
        self.assertEqual(r["summary"]["config"], "config")  # in-memory: no file name


class SummaryKeysOfTheScripts(unittest.TestCase):
    def test_sweeplib_reads_only_keys_the_run_layer_writes(self):
        # The experiment scripts read summary.json as JSON, through the run layer's key list
        # (docs/ARCHITECTURE.md "A run"): every block they take is one summary_keys() names.
        sys.path.insert(0, os.path.join(ROOT, "tools", "experiments"))
        try:
            import sweeplib
        finally:
            sys.path.pop(0)
        keys = set(budget_slam._core.summary_keys())
        for name, (block, _) in sweeplib.SUMMARY_METRICS:
            self.assertIn(block, keys, name)
        self.assertTrue({"status", "counts"} <= keys)


class ExitCodes(unittest.TestCase):
    def test_the_run_layers_one_mapping(self):
        code = budget_slam._core.exit_code
        self.assertEqual(code("ok"), 0)
        self.assertEqual(code("failed", "input"), 1)
        self.assertEqual(code("failed", "command_line"), 2)
        self.assertEqual(code("interrupted", "stopped"), 130)
        self.assertEqual(code("not_found"), 3)
        with self.assertRaises(budget_slam._core.ConfigError):
            code("done")


class CompareMatchesTheCommandLine(unittest.TestCase):
    def test_comparison_and_runs(self):
        with tempfile.TemporaryDirectory(prefix="test_python_compare_") as tmp:
            p = cli("compare", "-c", CONFIG, "-i", DEMO, "-o", os.path.join(tmp, "cli"), "--reducers",
                    "mi,coverage", "--cap", "20", "--quiet")
            self.assertEqual(p.returncode, 0, p.stderr)
            # The table and the summaries come from the run layer in memory: no summary.json
            # is read back (json.load) and no CSV but each run's per-step files.
            read = []
            real_read_csv = budget_slam.read_csv
            with unittest.mock.patch.object(budget_slam.json, "load",
                                            side_effect=AssertionError("a summary.json read back")), \
                 unittest.mock.patch.object(budget_slam, "read_csv",
                                            side_effect=lambda p: read.append(p) or real_read_csv(p)):
                c = budget_slam.compare(CONFIG, DEMO, reducers=["mi", "coverage"], cap=20,
                                        outdir=os.path.join(tmp, "py"))
            self.assertEqual(sorted(os.path.relpath(p, os.path.join(tmp, "py")) for p in read),
                             sorted(os.path.join(run, f) for run in ["reference", "mi", "coverage"]
                                    for f in ["steps.csv", "landmarks.csv", "evictions.csv"]
                                    if os.path.isfile(os.path.join(tmp, "py", run, f))))
            rows = csv_rows(os.path.join(tmp, "cli", "comparison.csv"))
            assertColumnsEqual(self, c["comparison"], rows, skip=TIMING_COLUMNS)
            self.assertEqual(list(c["comparison"]["run"]), ["reference", "mi", "coverage"])
            self.assertEqual(list(c["comparison"]["landmarks"]), [70, 20, 20])
            # A column's type is the table's: the counts int64, a measure float64.
            self.assertEqual(c["comparison"]["landmarks"].dtype, np.int64)
            self.assertEqual(c["comparison"]["ref_ate_m"].dtype, np.float64)
            self.assertEqual(c["comparison"]["status"].dtype.kind, "U")
            self.assertEqual(set(c["runs"]), {"reference", "mi", "coverage"})
            for name in c["runs"]:
                assertColumnsEqual(self, c["runs"][name]["landmarks"],
                                   csv_rows(os.path.join(tmp, "cli", name, "landmarks.csv")))
                with open(os.path.join(tmp, "cli", name, "summary.json")) as f:
                    want = json.load(f)
                self.assertEqual(without_timings(c["runs"][name]["summary"]),
                                 without_timings(want), name)
                self.assertEqual(c["runs"][name]["outdir"], os.path.join(tmp, "py", name))
            self.assertEqual(c["summary"]["status"], "ok")
            self.assertEqual(c["summary"]["runs"], 3)


def ig_bits(cov, i):
    """Information gain of landmark i by hand: 1/2 log2(|P_LL| |Lambda_LL|) (docs/ALGORITHMS.md)."""
    r = slice(3 + 2 * i, 5 + 2 * i)
    lam = np.linalg.inv(cov)
    return 0.5 * math.log2(np.linalg.det(cov[r, r]) * np.linalg.det(lam[r, r]))


class ReducerScoresMatchTheLoggedScores(unittest.TestCase):
    """config.ini's coverage run with the shadow reducers mi and info-content, cap 20, state dumps:
    every drop's score, and both shadows' scores, recomputed from the dumps."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="test_python_scores_")
        cls.dir = os.path.join(cls.tmp.name, "run")
        p = cli("run", "-c", CONFIG, "-i", DEMO, "-o", cls.dir, "--cap", "20", "--quiet",
                "--reducer", "coverage", "--set", "LandmarkBudget.protect=recently_seen",
                "--set", "LandmarkBudget.admission=always",
                "--set", "LandmarkBudget.dump_states=true")
        assert p.returncode == 0, p.stderr
        cls.evictions = csv_rows(os.path.join(cls.dir, "evictions.csv"))

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_every_logged_score_is_recomputed_from_the_dumps(self):
        by_step = {}
        for row in self.evictions:
            by_step.setdefault(int(row["step"]), []).append(row)
        checked = 0
        for step, rows in by_step.items():
            s = budget_slam.load_state(os.path.join(self.dir, "states", f"step_{step}.txt"))
            self.assertEqual(s["step"], step)
            ids, mean, cov = s["ids"], s["mean"], s["cov"]
            for row in rows:  # drops of one event, in order
                self.assertEqual(row["reducer"], "coverage")
                logged = {"coverage": (int(row["landmark_id"]), float(row["score"]))}
                for shadow in row["shadow_choices"].split(";"):
                    name, lid, score = shadow.rsplit(":", 2)
                    logged[name] = (int(lid), float(score))
                self.assertEqual(set(logged), {"coverage", "mi", "info-content"})
                for name, (lid, score) in logged.items():
                    got = budget_slam.reducer_scores(name, mean, cov, ids, step=step)
                    self.assertEqual(list(got["ids"]), list(ids))
                    k = list(ids).index(lid)
                    self.assertAlmostEqual(got["scores"][k], score, delta=1e-7 * max(1.0, abs(score)),
                                           msg=f"{name} step {step} landmark {lid}")
                checked += 1
                # The EKF drops a landmark by deleting its rows and columns.
                k = list(ids).index(int(row["landmark_id"]))
                keep = [j for j in range(len(mean)) if j not in (3 + 2 * k, 4 + 2 * k)]
                ids, mean, cov = np.delete(ids, k), mean[keep], cov[np.ix_(keep, keep)]
        self.assertEqual(checked, len(self.evictions))
        self.assertGreater(checked, 300)

    def test_scores_by_hand_and_choices(self):
        # the last dump (the first ones hold the zero robot covariance of the start)
        name = max(os.listdir(os.path.join(self.dir, "states")), key=lambda n: int(n[5:-4]))
        s = budget_slam.load_state(os.path.join(self.dir, "states", name))
        ids, mean, cov = s["ids"], s["mean"], s["cov"]
        mi = budget_slam.reducer_scores("mi", mean, cov, ids)
        for i in range(len(ids)):
            self.assertAlmostEqual(mi["scores"][i], ig_bits(cov, i), delta=1e-9)
        self.assertEqual(mi["choice"], ids[int(np.argmin(mi["scores"]))])
        ic = budget_slam.reducer_scores("info-content", mean, cov, ids)
        for i in range(len(ids)):
            c = cov[3 + 2 * i:5 + 2 * i, 3 + 2 * i:5 + 2 * i]
            # Dissanayake's 1/sigma_xx^2 + 1/sigma_yy^2, sigma^2 being the variances
            self.assertAlmostEqual(ic["scores"][i], 1 / c[0, 0] + 1 / c[1, 1],
                                   delta=1e-9 * ic["scores"][i])
        # oldest reads first_step; candidates restrict the choice
        first = np.arange(len(ids))[::-1] * 10
        old = budget_slam.reducer_scores("oldest", mean, cov, ids, first_step=first)
        np.testing.assert_array_equal(old["scores"], first)
        self.assertEqual(old["choice"], ids[-1])
        some = budget_slam.reducer_scores("oldest", mean, cov, ids, first_step=first, candidates=ids[:2])
        self.assertEqual(some["choice"], ids[1])
        # every registered reducer but none scores the state
        for r in budget_slam.reducer_names():
            if r != "none":
                got = budget_slam.reducer_scores(r, mean, cov, ids, obs_mean=mean[3:].reshape(-1, 2))
                self.assertIn(got["choice"], list(ids))
                self.assertEqual(len(got["scores"]), len(ids))


class RegistriesAsTheCommandLineListsThem(unittest.TestCase):
    def test_reducers_and_backends_are_budget_slam_list_json(self):
        for kind, listed in (("reducers", budget_slam.reducers()), ("backends", budget_slam.backends())):
            p = subprocess.run([BUDGET_SLAM, "--list", kind, "--json"], capture_output=True, text=True)
            self.assertEqual(p.returncode, 0, p.stderr)
            self.assertEqual(listed, json.loads(p.stdout))
        names = [r["name"] for r in budget_slam.reducers()]
        self.assertEqual(names, budget_slam.reducer_names())
        self.assertIn("place-coverage", names)
        self.assertEqual([b["name"] for b in budget_slam.backends()], ["ekf", "graph"])
        mi = next(r for r in budget_slam.reducers() if r["name"] == "mi")
        self.assertIn({"section": "MutualInformationReducer", "key": "mode", "default": "cap",
                       "doc": mi["options"][0]["doc"]}, mi["options"])
        graph = next(b for b in budget_slam.backends() if b["name"] == "graph")
        self.assertTrue(all(o["default"] is not None for o in graph["options"]))


class CtrlC(unittest.TestCase):
    def test_sigint_ends_the_run_cleanly_and_raises_keyboard_interrupt(self):
        # A long run (Victoria Park, EKF) in a child Python; SIGINT once steps are being written.
        with tempfile.TemporaryDirectory(prefix="test_python_sigint_") as tmp:
            out = os.path.join(tmp, "out")
            code = ("import budget_slam, sys\n"
                    "try:\n"
                    f"    budget_slam.run({CONFIG!r}, {os.path.join(ROOT, 'rawlogs', 'victoria_park.rawlog')!r},"
                    f" outdir={out!r}, reducer='info-content', cap=30)\n"
                    "except KeyboardInterrupt as e:\n"
                    "    print('KeyboardInterrupt:', e); sys.exit(130)\n")
            proc = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                    text=True, env=dict(os.environ))
            steps = os.path.join(out, "steps.csv")
            deadline = time.time() + 120
            while time.time() < deadline and proc.poll() is None:
                if os.path.isfile(steps) and os.path.getsize(steps) > 2000:
                    break
                time.sleep(0.05)
            self.assertIsNone(proc.poll(), "the run ended before it could be interrupted")
            proc.send_signal(signal.SIGINT)
            stdout, stderr = proc.communicate(timeout=120)
            self.assertEqual(proc.returncode, 130, stderr)
            # Between two steps, or while the next one was being read (a race with the signal).
            m = re.match(r"^KeyboardInterrupt: interrupted by Ctrl-C (after|while reading) step (\d+)\n$", stdout)
            self.assertIsNotNone(m, stdout)
            done = int(m.group(2)) + (1 if m.group(1) == "after" else 0)
            with open(os.path.join(out, "summary.json")) as f:
                summary = json.load(f)
            self.assertEqual(summary["status"], "interrupted")
            self.assertEqual(summary["counts"]["steps"], done)
            self.assertEqual(len(csv_rows(steps)), done)
            self.assertTrue(os.path.isfile(os.path.join(out, "landmarks.csv")))


class OutputFoldersAsOnTheCommandLine(unittest.TestCase):
    """The module's runs own their output folders as the executable's do (issue 23, 25)."""

    def test_a_failed_start_does_not_block_the_retry(self):
        with tempfile.TemporaryDirectory(prefix="test_python_retry_") as tmp:
            out = os.path.join(tmp, "out")
            with self.assertRaises(budget_slam.Error) as ctx:
                budget_slam.run(CONFIG, DEMO, {"LandmarkBudget.max_landmarks": "abc"}, outdir=out)
            self.assertEqual(str(ctx.exception),
                             "--set 'LandmarkBudget.max_landmarks=abc': [LandmarkBudget] max_landmarks "
                             "= 'abc': not an integer (or none for no cap)")
            r = budget_slam.run(CONFIG, DEMO, {"MappingApplication.max_steps": 20}, outdir=out, cap=10)
            self.assertEqual(r["summary"]["status"], "ok")
            self.assertEqual(sorted(n for n in os.listdir(out) if n.startswith("earlier_run_")), [])

    def test_a_folder_in_use_is_refused_naming_the_holder(self):
        with tempfile.TemporaryDirectory(prefix="test_python_lock_") as tmp:
            # Another process holds the folder, as a running budget-slam or sweep does.
            holder = subprocess.Popen(
                [sys.executable, "-c",
                 "import fcntl, os, sys, time\n"
                 f"f = open(os.path.join({tmp!r}, '.budget-slam.lock'), 'a+')\n"
                 "fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB)\n"
                 "f.write(str(os.getpid()) + '\\n'); f.flush(); print('held', flush=True)\n"
                 "time.sleep(60)\n"], stdout=subprocess.PIPE, text=True)
            try:
                self.assertEqual(holder.stdout.readline(), "held\n")
                with self.assertRaises(budget_slam.Error) as ctx:
                    budget_slam.run(CONFIG, DEMO, outdir=tmp, force=True)
                self.assertEqual(str(ctx.exception),
                                 f"output folder '{tmp}' is in use by process {holder.pid} (it holds "
                                 f"{tmp}/.budget-slam.lock); wait for it to end or give another output folder")
                self.assertFalse(os.path.exists(os.path.join(tmp, "summary.json")))
            finally:
                holder.kill()
                holder.wait()
                holder.stdout.close()


class BadArgumentsRaiseTheCliMessage(unittest.TestCase):
    def both(self, tmp, python_call, cli_args):
        """The CLI's last stderr line and the exception of the same call in Python."""
        p = cli(*cli_args)
        with self.assertRaises(budget_slam.Error) as ctx:
            python_call()
        return p, ctx.exception

    def test_failed_runs_and_refused_command_lines(self):
        with tempfile.TemporaryDirectory(prefix="test_python_errors_") as tmp:
            cases = [
                # (python call, CLI args): bad reducer, bad value, missing rawlog, missing config
                (lambda o: budget_slam.run(CONFIG, DEMO, outdir=o, reducer="nosuch"),
                 lambda o: ["run", "-c", CONFIG, "-i", DEMO, "-o", o, "--reducer", "nosuch", "--quiet"]),
                (lambda o: budget_slam.run(CONFIG, DEMO, {"LandmarkBudget.max_landmarks": -3}, outdir=o),
                 lambda o: ["run", "-c", CONFIG, "-i", DEMO, "-o", o, "--set", "LandmarkBudget.max_landmarks=-3",
                            "--quiet"]),
                (lambda o: budget_slam.run(CONFIG, "/nonexistent/x.rawlog", outdir=o),
                 lambda o: ["run", "-c", CONFIG, "-i", "/nonexistent/x.rawlog", "-o", o, "--quiet"]),
                (lambda o: budget_slam.compare(CONFIG, DEMO, reducers=["mi", "nosuch"], outdir=o),
                 lambda o: ["compare", "-c", CONFIG, "-i", DEMO, "-o", o, "--reducers", "mi,nosuch", "--quiet"]),
                (lambda o: budget_slam.run("/nonexistent/config.ini", DEMO, outdir=o),
                 lambda o: ["run", "-c", "/nonexistent/config.ini", "-i", DEMO, "-o", o, "--quiet"]),
            ]
            for k, (python_call, cli_args) in enumerate(cases):
                o_py, o_cli = os.path.join(tmp, f"py{k}"), os.path.join(tmp, f"cli{k}")
                p, e = self.both(tmp, lambda: python_call(o_py), cli_args(o_cli))
                self.assertNotEqual(p.returncode, 0)
                self.assertEqual(e.exit_code, p.returncode, str(e))
                lines = p.stderr.strip().splitlines()
                self.assertEqual(len(lines), 1, p.stderr)  # one line
                line = lines[0].replace(o_cli, o_py)
                self.assertTrue(line.startswith("budget-slam: "), line)
                line = line[len("budget-slam: "):]
                self.assertEqual(line[len("error: "):] if line.startswith("error: ") else line, str(e))
                self.assertEqual(isinstance(e, budget_slam.ConfigError), p.returncode == 2)
                if p.returncode == 2:
                    self.assertIsInstance(e, ValueError)
                if os.path.isfile(os.path.join(o_cli, "summary.json")):  # the folder says why
                    with open(os.path.join(o_py, "summary.json")) as f:
                        self.assertEqual(json.load(f)["error"], str(e))
                    self.assertEqual(e.outdir, o_py)
            # a non-empty output folder is refused unless force
            with self.assertRaises(budget_slam.Error) as ctx:
                budget_slam.run(CONFIG, DEMO, outdir=tmp, cap=20)
            self.assertIn("is not empty (use --force to write into it)", str(ctx.exception))

    def test_in_memory_config_gets_the_ini_checks(self):
        # A dict config goes through the same text checks as a -c file: an undefined ${...}
        # is a ConfigError naming the line, not an abort inside MRPT's variable expansion.
        config = {"MappingApplication": {"rawlog_file": DEMO, "max_steps": 5},
                  "LandmarkBudget": {"reducer": "${NOPE}"}}
        with self.assertRaises(budget_slam.ConfigError) as ctx:
            budget_slam.run(config)
        self.assertEqual(str(ctx.exception),
                         "config: line 5: unknown variable ${NOPE} (no @define NOPE above it)")

    def test_reducer_scores_arguments(self):
        mean, cov, ids = np.zeros(7), np.eye(7), [4, 9]
        with self.assertRaises(budget_slam.ConfigError) as ctx:
            budget_slam.reducer_scores("nosuch", mean, cov, ids)
        with tempfile.TemporaryDirectory(prefix="test_python_errors_") as tmp:
            p = cli("run", "-c", CONFIG, "-i", DEMO, "-o", tmp, "--reducer", "nosuch", "--quiet")
        self.assertIn(str(ctx.exception), p.stderr)  # the registry's own message
        self.assertTrue(str(ctx.exception).startswith("unknown reducer 'nosuch' (registered: "))
        cases = [(("none", mean, cov, ids), "reducer 'none' scores nothing: it is the unreduced run"),
                 (("mi", np.zeros(6), np.eye(6), ids), "mean: 6 values, expected 3 + 2 x 2 ids = 7"),
                 (("mi", mean, np.ones((7, 6)), ids), "cov: expected a square 2-D array"),
                 (("mi", mean, np.eye(9), ids), "cov: 9 x 9, expected 7 square"),
                 (("mi", mean, np.eye(7), [4, 4]), "ids: landmark 4 is listed twice")]
        for args, message in cases:
            with self.assertRaises(budget_slam.ConfigError) as ctx:
                budget_slam.reducer_scores(*args)
            self.assertEqual(str(ctx.exception), message)
        bad = np.eye(7)
        bad[3, 4] = 0.5
        with self.assertRaises(budget_slam.ConfigError) as ctx:
            budget_slam.reducer_scores("mi", mean, bad, ids)
        self.assertEqual(str(ctx.exception), "cov: not symmetric")
        with self.assertRaises(TypeError):
            budget_slam.run(CONFIG, DEMO, overrides=["LandmarkBudget.seed=3"])


class FirstHour(unittest.TestCase):
    """Issue 25: progress= in run() and compare(), cap checked, text columns kept as text."""

    def test_cap_none_works_and_a_fractional_cap_is_refused(self):
        r = budget_slam.run(CONFIG, DEMO, reducer="none", cap="none", max_steps=40)
        self.assertIsNone(r["summary"]["cap"])
        self.assertEqual(r["summary"]["counts"]["steps"], 40)
        with self.assertRaises(TypeError) as ctx:
            budget_slam.run(CONFIG, DEMO, cap=20.7)
        self.assertEqual(str(ctx.exception), "cap=20.7: expected a whole number of landmarks (int) or 'none'")
        with self.assertRaises(budget_slam.ConfigError) as ctx:
            budget_slam.compare(CONFIG, DEMO, cap="twenty")
        self.assertEqual(str(ctx.exception), "cap='twenty': a number of landmarks or 'none'")
        self.assertEqual(budget_slam.run(CONFIG, DEMO, cap=np.int64(20), max_steps=40)["summary"]["cap"], 20)

    def test_empty_text_columns_stay_text(self):
        with tempfile.TemporaryDirectory(prefix="test_python_text_") as tmp:
            r = budget_slam.run(CONFIG, DEMO, outdir=os.path.join(tmp, "o"), cap=20)
            ev = r["evictions"]
            self.assertGreater(len(ev), 0)
            self.assertTrue(all(v == "" for v in ev["shadow_errors"]))  # no shadow failed
            self.assertEqual(ev["shadow_errors"].dtype.kind, "U")
            self.assertEqual(ev["reason"].dtype.kind, "U")
            self.assertEqual(ev["step"].dtype, np.int64)

    def test_progress_callback_of_run_and_compare(self):
        heard = []
        budget_slam.run(CONFIG, DEMO, cap=20, progress=heard.append)
        self.assertTrue(heard[-1]["finished"])
        self.assertEqual(heard[-1]["fraction"], 1.0)
        self.assertEqual(heard[-1]["steps_done"], 249)
        self.assertEqual(heard[-1]["task"], "run")
        self.assertEqual(sorted(heard[-1]), sorted(["task", "fraction", "steps_done", "steps_total", "elapsed_s",
                                                    "steps_per_s", "eta_s", "detail", "finished"]))
        heard = []
        c = budget_slam.compare(CONFIG, DEMO, reducers=["random"], cap=20, seeds="1:2", progress=heard.append)
        self.assertEqual(list(c["comparison"]["run"]), ["reference", "random/seed1", "random/seed2"])
        self.assertEqual(list(c["comparison"]["seed"][1:]), [1, 2])
        tasks = [h["task"] for h in heard]
        self.assertEqual(tasks[-1], "compare")
        self.assertIn("reading the rawlog", tasks)
        self.assertTrue(heard[-1]["finished"])
        self.assertEqual(heard[-1]["steps_done"], 3 * 249)
        self.assertEqual(heard[-1]["steps_total"], 3 * 249)
        fractions = [h["fraction"] for h in heard if h["task"] == "compare"]
        self.assertEqual(fractions, sorted(fractions))

    def test_a_raising_callback_stops_the_run_with_its_outputs(self):
        def stop(p):
            if p["steps_done"] >= 50:
                raise RuntimeError("enough")
        with tempfile.TemporaryDirectory(prefix="test_python_progress_") as tmp:
            out = os.path.join(tmp, "o")
            # A step takes about a millisecond, the callback comes every 0.2 s: a long rawlog.
            with self.assertRaises(RuntimeError) as ctx:
                budget_slam.run(CONFIG, os.path.join(ROOT, "rawlogs", "victoria_park.rawlog"), outdir=out,
                                backend="graph", progress=stop)
            self.assertEqual(str(ctx.exception), "enough")
            with open(os.path.join(out, "summary.json")) as f:
                summary = json.load(f)
            self.assertEqual(summary["status"], "interrupted")
            self.assertEqual(len(csv_rows(os.path.join(out, "steps.csv"))), summary["counts"]["steps"])
        # the next run is not stopped by the last one's request
        self.assertEqual(budget_slam.run(CONFIG, DEMO, cap=20, max_steps=10)["summary"]["status"], "ok")



# ---- localize(): runs::localize through a typed specification (issue 26) ----

ROOMS = os.path.join(ROOT, "rawlogs", "rooms.rawlog")
ROOMS_REVISIT = os.path.join(ROOT, "rawlogs", "rooms_revisit.rawlog")


class LocalizeMatchesTheCommandLine(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="test_python_localize_")
        cls.map = os.path.join(cls.tmp.name, "map")
        p = cli("run", "-c", CONFIG, "-i", ROOMS, "-o", cls.map, "--quiet")
        assert p.returncode == 0, p.stderr
        cls.cli_dir = os.path.join(cls.tmp.name, "cli")
        p = cli("localize", "-c", CONFIG, "--map", cls.map, "-i", ROOMS_REVISIT, "-o", cls.cli_dir, "--quiet")
        assert p.returncode == 0, p.stderr
        cls.py_dir = os.path.join(cls.tmp.name, "py")
        cls.heard = []
        cls.r = budget_slam.localize(CONFIG, ROOMS_REVISIT, cls.map, outdir=cls.py_dir, progress=cls.heard.append)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_summary_steps_and_trajectory_are_the_cli_ones(self):
        with open(os.path.join(self.cli_dir, "summary.json")) as f:
            want = json.load(f)
        self.assertEqual(without_timings(self.r["summary"]), without_timings(want))
        self.assertEqual(self.r["summary"]["start_pose"]["source"], "ground truth")
        self.assertLess(self.r["summary"]["localization"]["rmse_m"], 0.2)
        assertColumnsEqual(self, self.r["steps"], csv_rows(os.path.join(self.cli_dir, "steps.csv")),
                           skip=TIMING_COLUMNS)
        self.assertEqual(len(self.r["steps"]), want["counts"]["steps"])
        tum = np.loadtxt(os.path.join(self.cli_dir, "trajectory.tum"))
        np.testing.assert_array_equal(self.r["trajectory"]["x"], tum[:, 1])
        self.assertEqual(len(self.r["ground_truth"]), want["localization"]["steps_compared"])
        self.assertIsNone(self.r["reference"])
        self.assertIsNone(self.r["evictions"])
        self.assertEqual(self.r["outdir"], self.py_dir)

    def test_progress_reports_the_reading_and_the_steps(self):
        tasks = [h["task"] for h in self.heard]
        self.assertIn("reading the rawlog", tasks)
        self.assertEqual(tasks[-1], "localize")
        self.assertTrue(self.heard[-1]["finished"])
        self.assertEqual(self.heard[-1]["steps_done"], self.r["summary"]["counts"]["steps"])

    def test_start_pose_dict_config_and_temporary_folder(self):
        cli_dir = os.path.join(self.tmp.name, "cli_pose")
        p = cli("localize", "-c", CONFIG, "--map", self.map, "-i", ROOMS_REVISIT, "-o", cli_dir, "--quiet",
                "--start-pose", "11.07,7.27,-179.9", "--max-steps", "100")
        self.assertEqual(p.returncode, 0, p.stderr)
        with open(os.path.join(cli_dir, "summary.json")) as f:
            want = json.load(f)
        with open(CONFIG) as f:
            text = f.read()
        config = {}  # config.ini as a dict: the in-memory ini
        section = None
        for line in text.splitlines():
            line = line.split(";")[0].split("#")[0].strip()
            if line.startswith("["):
                section = config.setdefault(line.strip("[]"), {})
            elif "=" in line and section is not None:
                k, v = line.split("=", 1)
                section[k.strip()] = v.strip()
        r = budget_slam.localize(config, ROOMS_REVISIT, self.map, start_pose=(11.07, 7.27, -179.9), max_steps=100)
        self.assertIsNone(r["outdir"])
        got = without_timings(r["summary"])
        self.assertEqual(got.pop("config"), "config")
        want = without_timings(want)
        want.pop("config")
        self.assertEqual(got, want)
        self.assertEqual(r["summary"]["start_pose"]["source"], "--start-pose")
        self.assertEqual(r["summary"]["counts"]["steps"], 100)

    def test_refusals_and_failures_raise_the_cli_line(self):
        cases = [  # (python kwargs, CLI flags, exit code)
            ({"start_pose": "1,2"}, ["--start-pose", "1,2"], 2),
            ({"start_pose": (1, 2, 3), "wake_up": True}, ["--start-pose", "1.0,2.0,3.0", "--wake-up"], 2),
            ({"max_steps": -1}, ["--max-steps", "-1"], 2),
            ({"overrides": {"Localization.lost_threshold": -1}}, ["--set", "Localization.lost_threshold=-1"], 1),
            ({"map": "/nonexistent/map"}, [], 1),
        ]
        for k, (kwargs, flags, code) in enumerate(cases):
            with self.subTest(flags=flags):
                o_py, o_cli = os.path.join(self.tmp.name, f"e_py{k}"), os.path.join(self.tmp.name, f"e_cli{k}")
                the_map = kwargs.pop("map", self.map)
                p = cli("localize", "-c", CONFIG, "--map", the_map, "-i", ROOMS_REVISIT, "-o", o_cli, "--quiet",
                        *flags)
                self.assertEqual(p.returncode, code, p.stderr)
                with self.assertRaises(budget_slam.Error) as ctx:
                    budget_slam.localize(CONFIG, ROOMS_REVISIT, the_map, outdir=o_py, **kwargs)
                e = ctx.exception
                self.assertEqual(e.exit_code, code)
                self.assertEqual(isinstance(e, budget_slam.ConfigError), code == 2)
                line = p.stderr.strip().splitlines()[-1].replace(o_cli, o_py)
                self.assertEqual(line, "budget-slam: " + ("" if code == 2 else "error: ") + str(e))
                if code == 1:
                    with open(os.path.join(o_py, "summary.json")) as f:
                        self.assertEqual(json.load(f)["error"], str(e))
                    self.assertEqual(e.outdir, o_py)
        with self.assertRaises(TypeError):
            budget_slam.localize(CONFIG, ROOMS_REVISIT, self.map, start_pose=(1, 2))
        with self.assertRaises(TypeError):
            budget_slam.localize(CONFIG, ROOMS_REVISIT)

    def test_a_wake_up_that_finds_nothing_raises_not_found(self):
        other = os.path.join(self.tmp.name, "other_map")
        p = cli("run", "-c", CONFIG, "-i", os.path.join(ROOT, "rawlogs", "paper_synthetic.rawlog"), "-o", other,
                "--quiet")
        self.assertEqual(p.returncode, 0, p.stderr)
        o_cli = os.path.join(self.tmp.name, "nf_cli")
        p = cli("localize", "-c", CONFIG, "--map", other, "-i", ROOMS_REVISIT, "-o", o_cli, "--wake-up")
        self.assertEqual(p.returncode, 3)
        with self.assertRaises(budget_slam.NotFound) as ctx:
            budget_slam.localize(CONFIG, ROOMS_REVISIT, other, wake_up=True)
        e = ctx.exception
        self.assertEqual(e.exit_code, 3)
        self.assertIsNone(e.outdir)
        self.assertEqual(p.stderr.strip(), "budget-slam: error: " + str(e))
        self.assertTrue(str(e).startswith("wake-up: the robot was not found on the map in 10 steps"))
        self.assertEqual(e.summary["status"], "not_found")
        self.assertFalse(e.summary["wake_up"]["found"])
        # found on the map it was made from: the start is the wake-up's
        r = budget_slam.localize(CONFIG, ROOMS_REVISIT, self.map, wake_up=True)
        self.assertTrue(r["summary"]["wake_up"]["found"])
        self.assertEqual(r["summary"]["start_pose"]["source"], "wake-up")

    def test_a_map_of_another_place_warns_as_the_cli(self):
        park = os.path.join(ROOT, "rawlogs", "park.rawlog")
        p = cli("localize", "-c", CONFIG, "--map", self.map, "-i", park, "-o", os.path.join(self.tmp.name, "w_cli"),
                "--start-pose", "1,2,30", "--quiet")
        self.assertEqual(p.returncode, 0, p.stderr)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            budget_slam.localize(CONFIG, park, self.map, start_pose="1,2,30")
        said = [str(w.message) for w in caught if issubclass(w.category, RuntimeWarning)]
        self.assertEqual(["budget-slam: warning: " + s for s in said], p.stderr.strip().splitlines())
        self.assertTrue(said[-1].endswith("the map and the traversal share no place"))

if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--budget-slam", default=os.path.join(ROOT, "build", "bin", "budget-slam"))
    args, rest = ap.parse_known_args()
    BUDGET_SLAM = os.path.abspath(args.budget_slam)
    unittest.main(argv=[sys.argv[0]] + rest)
