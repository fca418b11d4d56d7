#!/usr/bin/python3
"""The budget_slam Python module under hostile input (issue 36 case 9, issue 35 case 15): each
call below returned a result, read without bound or scored a matrix that is no covariance; each now
raises with one line.

    PYTHONPATH=build/python test_hostile_input.py
"""
import os
import tempfile
import unittest

import numpy as np

import budget_slam

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
CONFIG = os.path.join(ROOT, "config.ini")
DEMO = os.path.join(ROOT, "rawlogs", "kf-slam_demo.rawlog")


class StateDumps(unittest.TestCase):
    def test_a_device_or_a_file_that_is_no_dump_is_one_line(self):
        with self.assertRaises(budget_slam.Error) as ctx:
            budget_slam.load_state("/dev/zero")
        self.assertEqual(str(ctx.exception), "/dev/zero: line 1 is longer than 1048576 bytes: "
                                             "not a state dump of budget-slam")
        with tempfile.NamedTemporaryFile(suffix=".txt") as f:
            f.write(b"\xff\xfe not text\n")
            f.flush()
            with self.assertRaises(budget_slam.Error) as ctx:
                budget_slam.load_state(f.name)
            self.assertIn("line 1 is not UTF-8 text", str(ctx.exception))


class ReducerScores(unittest.TestCase):
    mean, ids = np.zeros(7), [4, 9]

    def test_a_config_that_is_no_reducer_ini_is_refused(self):
        for config, said in [("x", "config: line 1:"),
                             ("[Foo]\na = 1\n", "config: unknown section [Foo]"),
                             ({"LocalizationInformationReducer": {"max_places": 0}},
                              "max_places")]:
            with self.assertRaises(budget_slam.ConfigError) as ctx:
                budget_slam.reducer_scores("mi", self.mean, np.eye(7), self.ids, config=config)
            self.assertIn(said, str(ctx.exception))
            self.assertNotIn("\n", str(ctx.exception))

    def test_a_matrix_that_is_no_covariance_is_refused(self):
        for name in ("mi", "info-content", "localization-information"):
            with self.assertRaises(budget_slam.ConfigError) as ctx:
                budget_slam.reducer_scores(name, self.mean, -np.eye(7), self.ids)
            self.assertEqual(str(ctx.exception),
                             "cov: not positive semi-definite (its least eigenvalue is -1)")
        # A real one still scores.
        r = budget_slam.reducer_scores("mi", self.mean, np.eye(7), self.ids)
        self.assertEqual(list(r["ids"]), self.ids)


class RunAndLocalize(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="test_python_hostile_")
        cls.map = os.path.join(cls.tmp.name, "map")
        budget_slam.run(CONFIG, DEMO, outdir=cls.map, cap=15, reducer="oldest")

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_wake_up_keys_are_checked_without_a_wake_up(self):
        with self.assertRaises(budget_slam.Error) as ctx:  # a failed localize, as the CLI's exit 1
            budget_slam.localize({"WakeUp": {"max_steps": "nan"}}, DEMO, self.map,
                                 start_pose=(0, 0, 0))
        self.assertEqual(str(ctx.exception), "config: [WakeUp] max_steps = 'nan': not an integer")
        with self.assertRaises(budget_slam.Error) as ctx:
            budget_slam.run(CONFIG, DEMO, {"WakeUp.max_hypotheses": 0}, reducer="oldest", cap=15)
        self.assertEqual(str(ctx.exception), "--set 'WakeUp.max_hypotheses=0': [WakeUp] "
                                             "max_hypotheses = 0: must be at least 1")

    def test_skip_steps_beyond_the_rawlog_raises(self):
        with self.assertRaises(budget_slam.ConfigError) as ctx:
            budget_slam.run(CONFIG, DEMO, reducer="oldest", cap=15, resume=self.map,
                            skip_steps=2**64 - 1)
        self.assertIn("more steps than a rawlog can hold", str(ctx.exception))
        with self.assertRaises(budget_slam.Error) as ctx:
            budget_slam.run(CONFIG, DEMO, reducer="oldest", cap=15, resume=self.map,
                            skip_steps=100000)
        self.assertIn("none is left to run", str(ctx.exception))


if __name__ == "__main__":
    unittest.main()
