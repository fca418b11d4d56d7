#!/usr/bin/python3
"""Tests of reducers written in Python (docs/PYTHON.md "A reducer in Python"), through the
command line (`budget-slam --plugin FILE.py`) and the module (budget_slam.register_reducer):
python/plugins/oldest.py makes exactly the built-in oldest's decisions; each bad behaviour of a
plugin ends the run failed with its one line and exit code; a plugin's ini section is checked;
Ctrl-C during a plugin's drop ends the run interrupted; the worked example runs in compare beside
the shipped reducers and is listed with its option.

    PYTHONPATH=build/python test_plugins.py --budget-slam build/bin/budget-slam
"""
import argparse
import csv
import json
import os
import re
import signal
import subprocess
import sys
import tempfile
import textwrap
import time
import unittest

import budget_slam

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
CONFIG = os.path.join(ROOT, "config.ini")
PLUGINS = os.path.join(ROOT, "python", "plugins")
DEMO = os.path.join(ROOT, "rawlogs", "kf-slam_demo.rawlog")
BUDGET_SLAM = None
NO_SHADOWS = ["--set", "LandmarkBudget.shadow_reducers="]


def cli(*args, timeout=600):
    return subprocess.run([BUDGET_SLAM, *args], capture_output=True, text=True, timeout=timeout)


def csv_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def read_json(path):
    with open(path) as f:
        return json.load(f)


def plugin_file(folder, name, body):
    """A plugin file `name` in `folder` with the given source (dedented)."""
    path = os.path.join(folder, name)
    with open(path, "w") as f:
        f.write("import math, os, budget_slam\n" + textwrap.dedent(body))
    return path


class OldestInPython(unittest.TestCase):
    """python/plugins/oldest.py against the built-in oldest: the same evictions.csv (every column
    but the reducer's name) and the same final map, on three rawlogs."""

    def test_same_decisions_on_three_rawlogs(self):
        with tempfile.TemporaryDirectory(prefix="test_plugins_oldest_") as tmp:
            for rawlog, cap in [("kf-slam_demo", 10), ("rooms", 40), ("mrclam7_robot1", 6)]:
                with self.subTest(rawlog=rawlog):
                    src = os.path.join(ROOT, "rawlogs", rawlog + ".rawlog")
                    common = ["-c", CONFIG, "-i", src, "--cap", str(cap), "--quiet"]
                    builtin, plugin = os.path.join(tmp, rawlog, "c"), os.path.join(tmp, rawlog, "p")
                    b = cli("run", *common, "--reducer", "oldest", "-o", builtin)
                    p = cli("run", *common, "--plugin", os.path.join(PLUGINS, "oldest.py"),
                            "--reducer", "py-oldest", "-o", plugin)
                    self.assertEqual(b.returncode, 0, b.stderr)
                    self.assertEqual(p.returncode, 0, p.stderr)
                    eb = csv_rows(os.path.join(builtin, "evictions.csv"))
                    ep = csv_rows(os.path.join(plugin, "evictions.csv"))
                    self.assertGreater(len(eb), 10)
                    self.assertEqual(len(eb), len(ep))
                    for rb, rp in zip(eb, ep):
                        self.assertEqual(rb.pop("reducer"), "oldest")
                        self.assertEqual(rp.pop("reducer"), "py-oldest")
                        self.assertEqual(rb, rp)
                    with open(os.path.join(builtin, "landmarks.csv")) as f1, \
                            open(os.path.join(plugin, "landmarks.csv")) as f2:
                        self.assertEqual(f1.read(), f2.read())

    def test_in_process_registration(self):
        # The module registers the same class in this process; run() then runs it as the CLI does.
        import runpy
        ns = runpy.run_path(os.path.join(PLUGINS, "oldest.py"))  # registers py-oldest here
        self.assertIn("py-oldest", budget_slam.reducer_names())
        with self.assertRaisesRegex(budget_slam.ConfigError, "already registered"):
            budget_slam.register_reducer("py-oldest", ns["Oldest"])
        a = budget_slam.run(CONFIG, DEMO, reducer="oldest", cap=10)
        b = budget_slam.run(CONFIG, DEMO, reducer="py-oldest", cap=10)
        self.assertEqual(list(a["evictions"]["landmark_id"]), list(b["evictions"]["landmark_id"]))
        self.assertEqual(list(a["evictions"]["score"]), list(b["evictions"]["score"]))
        self.assertEqual(set(b["evictions"]["reducer"]), {"py-oldest"})
        # Beside the built-in one in one comparison, the runs in two threads taking the GIL in turn.
        c = budget_slam.compare(CONFIG, DEMO, reducers=["py-oldest", "oldest"], cap=10, threads=2)
        rows = {str(r["run"]): r for r in c["comparison"]}
        self.assertEqual(rows["py-oldest"]["status"], "ok")
        self.assertEqual(rows["py-oldest"]["gt_trajectory_rmse_aligned_m"],
                         rows["oldest"]["gt_trajectory_rmse_aligned_m"])


# Each bad behaviour: the plugin's body, and the end of the one line it gives.
BAD = {
    "bad-raise": ("""
        class R:
            def choose(self, drop):
                raise ValueError("boom at " + str(drop.step))
        """, r"ValueError: boom at (\d+)"),
    "bad-type": ("""
        class R:
            def choose(self, drop):
                return "the first one"
        """, r"choose returned str, expected a landmark id, \(id, score\) or one score per "
             r"candidate"),
    "bad-id": ("""
        class R:
            def choose(self, drop):
                return -7
        """, r"choose returned landmark -7, not a candidate of this drop"),
    "bad-nan": ("""
        class R:
            def choose(self, drop):
                return int(drop.candidates["id"][0]), math.nan
        """, r"choose gave landmark \d+ the score nan, not a finite number"),
    "bad-observe": ("""
        class R:
            def observe(self, seen):
                if seen.step == 3:
                    raise RuntimeError("seen " + str(seen.step))
            def choose(self, drop):
                return int(drop.candidates["id"][0])
        """, r"RuntimeError: seen (\d+)"),
    "bad-length": ("""
        class R:
            def choose(self, drop):
                return [1.0] * (len(drop.candidates["id"]) + 1)
        """, r"choose returned \d+ scores for \d+ candidates"),
}


class BadPluginsFailTheRun(unittest.TestCase):
    """Each bad behaviour ends the run failed (exit 1) with one line naming the plugin, the step
    and what went wrong; steps.csv and evictions.csv of the steps before stay; summary.json says
    why."""

    def test_each_bad_behaviour(self):
        with tempfile.TemporaryDirectory(prefix="test_plugins_bad_") as tmp:
            for name, (body, tail) in BAD.items():
                with self.subTest(plugin=name):
                    fname = name.replace("-", "_") + ".py"
                    path = plugin_file(tmp, fname, textwrap.dedent(body) +
                                       f"budget_slam.register_reducer({name!r}, R)\n")
                    out = os.path.join(tmp, name)
                    # Cap 30: the demo's first drop comes at step 9, so steps stand before it.
                    r = cli("run", "-c", CONFIG, "-i", DEMO, "--cap", "30", "--quiet", "--plugin",
                            path, "--reducer", name, "-o", out)
                    self.assertEqual(r.returncode, 1, r.stderr)
                    lines = r.stderr.splitlines()
                    self.assertEqual(len(lines), 1, r.stderr)
                    pattern = (rf"budget-slam: error: plugin reducer '{name}' \({re.escape(fname)}\): "
                               rf"step (\d+): {tail}")
                    m = re.fullmatch(pattern, lines[0])
                    self.assertIsNotNone(m, lines[0])
                    s = read_json(os.path.join(out, "summary.json"))
                    self.assertEqual(s["status"], "failed")
                    self.assertIn(f"plugin reducer '{name}' ({fname}): step {m.group(1)}: ", s["error"])
                    # The steps before the drop are kept; a run that ended in its first step
                    # wrote no result file (docs/OUTPUTS.md).
                    steps_csv = os.path.join(out, "steps.csv")
                    if int(m.group(1)) == 0:
                        self.assertFalse(os.path.exists(steps_csv))
                    else:
                        self.assertGreaterEqual(len(csv_rows(steps_csv)), int(m.group(1)))
                    if name in ("bad-raise", "bad-observe"):
                        self.assertEqual(m.group(1), m.group(2))  # the step the Drop said

    def test_a_class_without_choose(self):
        with tempfile.TemporaryDirectory(prefix="test_plugins_nochoose_") as tmp:
            path = plugin_file(tmp, "no_choose.py", "class R:\n    pass\n"
                               "budget_slam.register_reducer('no-choose', R)\n")
            out = os.path.join(tmp, "o")
            r = cli("run", "-c", CONFIG, "-i", DEMO, "--cap", "10", "--quiet", "--plugin", path,
                    "--reducer", "no-choose", "-o", out)
            self.assertEqual(r.returncode, 1, r.stderr)
            line = "plugin reducer 'no-choose' (no_choose.py): a R has no choose(drop) method"
            self.assertEqual(r.stderr, f"budget-slam: error: {line}\n")
            self.assertEqual(read_json(os.path.join(out, "summary.json"))["error"], line)

    def test_in_process_raises_error_with_the_line(self):
        class Raises:
            def choose(self, drop):
                raise KeyError("lost")
        budget_slam.register_reducer("bad-in-process", Raises)
        with self.assertRaises(budget_slam.Error) as e:
            budget_slam.run(CONFIG, DEMO, reducer="bad-in-process", cap=10)
        self.assertEqual(e.exception.exit_code, 1)
        self.assertRegex(str(e.exception),
                         r"^plugin reducer 'bad-in-process' \(test_plugins\.py\): step \d+: "
                         r"KeyError: 'lost'$")

    def test_a_file_that_raises_is_a_bad_command_line(self):
        with tempfile.TemporaryDirectory(prefix="test_plugins_file_") as tmp:
            path = plugin_file(tmp, "broken.py", "raise RuntimeError('not today')\n")
            r = cli("run", "-c", CONFIG, "-i", DEMO, "--plugin", path, "-o", os.path.join(tmp, "o"))
            self.assertEqual(r.returncode, 2, r.stderr)
            self.assertEqual(r.stderr, f"budget-slam: --plugin {path}: RuntimeError: not today\n")
            r = cli("run", "-c", CONFIG, "-i", DEMO, "--plugin", os.path.join(tmp, "none.py"))
            self.assertEqual(r.returncode, 2, r.stderr)
            self.assertIn("none.py: no such file", r.stderr)


class PluginSectionIsChecked(unittest.TestCase):
    """A plugin's options are its own ini section: values reach its constructor, a bad value or an
    unknown key is one line naming the key, before any step."""

    BODY = """
        class Knob:
            def __init__(self, knob, mode):
                self.knob, self.mode = knob, mode
            def choose(self, drop):
                return int(drop.candidates["id"][0]), float(self.knob)
        budget_slam.register_reducer("knob", Knob, options={"knob": (3, 0, 10, "a number"),
                                                             "mode": ("fast", "slow")})
        """

    def test_values_and_errors(self):
        with tempfile.TemporaryDirectory(prefix="test_plugins_ini_") as tmp:
            path = plugin_file(tmp, "knob.py", self.BODY)
            base = ["run", "-c", CONFIG, "-i", DEMO, "--cap", "10", "--quiet", "--plugin", path,
                    "--reducer", "knob"]
            ok = os.path.join(tmp, "ok")
            r = cli(*base, "--set", "KnobReducer.knob=7", "-o", ok)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual({float(e["score"]) for e in csv_rows(os.path.join(ok, "evictions.csv"))},
                             {7.0})
            with open(os.path.join(ok, "config_used.ini")) as f:
                self.assertIn("knob = 7", f.read())
            for sets, line in [
                    ("KnobReducer.knob=abc", "[KnobReducer] knob = 'abc': not an integer"),
                    ("KnobReducer.knob=11", "[KnobReducer] knob = 11: must be at most 10"),
                    ("KnobReducer.mode=medium", "[KnobReducer] mode = 'medium': must be one of fast, slow"),
                    ("KnobReducer.knb=1", "unknown key [KnobReducer] knb (did you mean knob?)")]:
                with self.subTest(sets=sets):
                    out = os.path.join(tmp, "bad")
                    r = cli(*base, "--set", sets, "-o", out, "--force")
                    self.assertEqual(r.returncode, 1, r.stderr)  # a config error: a failed run
                    self.assertEqual(r.stderr, f"budget-slam: error: --set '{sets}': {line}\n")
                    self.assertFalse(os.path.exists(os.path.join(out, "steps.csv")))

    def test_listed_with_its_options(self):
        r = cli("--list", "reducers", "--json", "--plugin", os.path.join(PLUGINS, "distinct_places.py"))
        self.assertEqual(r.returncode, 0, r.stderr)
        e = next(x for x in json.loads(r.stdout) if x["name"] == "distinct-places")
        self.assertEqual(e["summary"], "the landmark seen from the fewest distinct places (grid "
                                       "cells of the robot) goes")
        self.assertEqual([(o["section"], o["key"], o["default"]) for o in e["options"]],
                         [("DistinctPlacesReducer", "place_size", "2.0")])
        self.assertIn("localization-information", [x["name"] for x in json.loads(r.stdout)])


class ComparedBesideTheShippedReducers(unittest.TestCase):
    def test_compare_with_the_example(self):
        with tempfile.TemporaryDirectory(prefix="test_plugins_compare_") as tmp:
            out = os.path.join(tmp, "cmp")
            r = cli("compare", "-c", CONFIG, "-i", os.path.join(ROOT, "rawlogs", "rooms.rawlog"),
                    "--plugin", os.path.join(PLUGINS, "distinct_places.py"), "--reducers",
                    "distinct-places,localization-information", "--cap", "51",
                    "--threads", "2", "--quiet", "-o", out, *NO_SHADOWS)
            self.assertEqual(r.returncode, 0, r.stderr)
            rows = {x["run"]: x for x in csv_rows(os.path.join(out, "comparison.csv"))}
            self.assertEqual(rows["distinct-places"]["status"], "ok")
            self.assertEqual(rows["localization-information"]["status"], "ok")
            ev = csv_rows(os.path.join(out, "distinct-places", "evictions.csv"))
            self.assertGreater(len(ev), 0)
            self.assertEqual({e["reducer"] for e in ev}, {"distinct-places"})


class SweepsTakeThePlugin(unittest.TestCase):
    """[sweep] plugins: the reducers of the file are accepted, and every command line the sweep runs
    carries --plugin (tools/experiments/sweeplib.py)."""

    def test_a_sweep_with_a_plugin(self):
        sys.path.insert(0, os.path.join(ROOT, "tools", "experiments"))
        import sweeplib
        with tempfile.TemporaryDirectory(prefix="test_plugins_sweep_") as tmp:
            ini = os.path.join(tmp, "plugin.ini")
            with open(ini, "w") as f:
                f.write("[sweep]\nconfig = config.ini\nrawlogs = rawlogs/kf-slam_demo.rawlog\n"
                        "plugins = python/plugins/oldest.py\nreducers = py-oldest, oldest\n"
                        "caps = 10\nseeds = 1\n")
            plugin = os.path.join(PLUGINS, "oldest.py")
            exp = sweeplib.Experiment(ini, os.path.join(tmp, "out"), BUDGET_SLAM)
            self.assertEqual(exp.plugins, [plugin])
            cmd = exp.job_command(exp.jobs[0])  # one shell line
            self.assertIn(f"--plugin {plugin}", cmd)
            self.assertIn("--reducers py-oldest,oldest", cmd)
            exp, _, _ = sweeplib.run_experiment(ini, os.path.join(tmp, "run"), BUDGET_SLAM, None, 1,
                                                log=lambda *a, **k: None)
            runs = {r["run"]: r for r in csv_rows(os.path.join(exp.jobs[0].folder, "comparison.csv"))}
            self.assertEqual(runs["oldest"]["status"], "ok")
            self.assertEqual(runs["py-oldest"]["status"], "ok")
            self.assertEqual(runs["py-oldest"]["gt_trajectory_rmse_aligned_m"],
                             runs["oldest"]["gt_trajectory_rmse_aligned_m"])
            # Without the file the name is unknown, as any other.
            with open(ini, "w") as f:
                f.write("[sweep]\nconfig = config.ini\nrawlogs = rawlogs/kf-slam_demo.rawlog\n"
                        "reducers = py-oldest\ncaps = 10\n")
            with self.assertRaisesRegex(sweeplib.ExperimentError, "reducer 'py-oldest' is not one of"):
                sweeplib.Experiment(ini, os.path.join(tmp, "out2"), BUDGET_SLAM)


HANG = """
    class Hang:
        def choose(self, drop):
            open(os.environ["PLUGIN_MARK"], "w").close()
            while True:
                pass
    budget_slam.register_reducer("hang", Hang)
    """


class CtrlCDuringADrop(unittest.TestCase):
    """A plugin that never returns is stopped by Ctrl-C: the run ends interrupted (130)."""

    def interrupt(self, args, env, mark):
        proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                env=env)
        try:
            deadline = time.time() + 120
            while not os.path.exists(mark) and time.time() < deadline and proc.poll() is None:
                time.sleep(0.05)
            self.assertTrue(os.path.exists(mark), "the plugin was never asked")
            time.sleep(0.3)
            self.assertIsNone(proc.poll())  # still inside the plugin's loop
            sent = time.time()
            proc.send_signal(signal.SIGINT)
            out, err = proc.communicate(timeout=30)
            return proc.returncode, out, err, time.time() - sent
        finally:
            if proc.poll() is None:
                proc.kill()
                proc.wait()

    def test_command_line_run_and_compare(self):
        with tempfile.TemporaryDirectory(prefix="test_plugins_ctrlc_") as tmp:
            path = plugin_file(tmp, "hang.py", HANG)
            for command in ["run", "compare"]:
                with self.subTest(command=command):
                    mark = os.path.join(tmp, command + ".mark")
                    out = os.path.join(tmp, command)
                    pick = ["--reducer", "hang"] if command == "run" else ["--reducers", "hang,oldest", "--threads", "2"]
                    code, _, err, took = self.interrupt(
                        [BUDGET_SLAM, command, "-c", CONFIG, "-i", DEMO, "--cap", "10", "--quiet",
                         "--plugin", path, *pick, "-o", out],
                        dict(os.environ, PLUGIN_MARK=mark), mark)
                    self.assertEqual(code, 130, err)
                    self.assertLess(took, 5)
                    self.assertIn("interrupted by Ctrl-C", err)
                    folder = out if command == "run" else os.path.join(out, "hang")
                    self.assertEqual(read_json(os.path.join(folder, "summary.json"))["status"],
                                     "interrupted")

    def test_in_process(self):
        with tempfile.TemporaryDirectory(prefix="test_plugins_ctrlc_py_") as tmp:
            path = plugin_file(tmp, "hang.py", HANG)
            mark = os.path.join(tmp, "py.mark")
            script = (f"import sys, budget_slam\nbudget_slam.load_plugin({path!r})\n"
                      "try:\n"
                      f"    budget_slam.run({CONFIG!r}, {DEMO!r}, reducer='hang', cap=10, "
                      f"outdir={os.path.join(tmp, 'out')!r})\n"
                      "except KeyboardInterrupt as e:\n"
                      "    print('KeyboardInterrupt:', e); sys.exit(130)\n")
            code, out, err, took = self.interrupt(
                [sys.executable, "-c", script], dict(os.environ, PLUGIN_MARK=mark), mark)
            self.assertEqual(code, 130, err)
            self.assertTrue(out.startswith("KeyboardInterrupt: interrupted by Ctrl-C"), out)
            self.assertEqual(read_json(os.path.join(tmp, "out", "summary.json"))["status"],
                             "interrupted")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--budget-slam", default=os.path.join(ROOT, "build", "bin", "budget-slam"))
    a, rest = ap.parse_known_args()
    BUDGET_SLAM = os.path.abspath(a.budget_slam)
    unittest.main(argv=[sys.argv[0]] + rest)
