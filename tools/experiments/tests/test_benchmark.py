#!/usr/bin/python3
"""Tests of tools/experiments/benchmark: the verdicts against `random` and the default rule on
hand-made results (known answers), the bounds' rows, and the --quick grid through the real binaries
(rooms at cap 1/5 on two seeds, MRCLAM 7 with two random maps, and the bounds; about a minute),
resumed without running anything.

    test_benchmark.py --budget-slam build/bin/budget-slam --budget-simulate build/bin/budget-simulate
"""
import csv
import os
import subprocess
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import scripttest  # noqa: E402

ROOT = scripttest.ROOT
SCRIPT = os.path.join(scripttest.EXP, "benchmark")
BUDGET_SLAM = BUDGET_SIMULATE = None
bm = scripttest.load_script("benchmark")

CAP = "20%"


def rows_of(rawlog, reducer, seeds, rmse, ratio=None, ok=True, success=50.0, lost=1.0):
    """results.csv rows of one reducer on one rawlog and cap: rmse(seed) -> value."""
    out = []
    for s in seeds:
        base = dict(rawlog=rawlog, backend="ekf", reducer=reducer, cap=CAP, seed=str(s))
        out.append(dict(base, metric="status_ok", value="1" if ok else "0"))
        if ok:
            v = rmse(s)
            out += [dict(base, metric="reloc_rmse_m", value=repr(v)),
                    dict(base, metric="reloc_rmse_ratio", value=repr(ratio(s) if ratio else v)),
                    dict(base, metric="reloc_success_pct", value=repr(success)),
                    dict(base, metric="reloc_lost_pct", value=repr(lost))]
    return out


class Verdicts(unittest.TestCase):
    """Known answers: on a simulated world (20 seeds) a reducer lower than random on every seed
    wins (p = 2/2^20), one equal to it ties, one higher loses; on a real dataset a map better than
    19 of 20 random maps wins, better than 10 ties, worse than 19 loses; a failed run loses."""

    @classmethod
    def setUpClass(cls):
        seeds = range(1, 21)
        sim, real = "sim:rooms", "mrclam7_robot1"
        rows = rows_of(sim, "none", seeds, lambda s: 0.1)
        rows += rows_of(sim, "random", seeds, lambda s: 1.0 + 0.01 * s)
        rows += rows_of(sim, "good", seeds, lambda s: 0.2 + 0.001 * s, ratio=lambda s: 2.0)
        rows += rows_of(sim, "same", seeds, lambda s: 1.0 + 0.01 * s)
        rows += rows_of(sim, "bad", seeds, lambda s: 3.0 + 0.001 * s)
        rows += rows_of(sim, "broken", seeds[:19], lambda s: 0.2) + rows_of(sim, "broken", [20], None, ok=False)
        rows += rows_of(real, "none", seeds, lambda s: 0.1)
        rows += rows_of(real, "random", seeds, lambda s: 0.1 * s)  # 0.1 .. 2.0
        rows += rows_of(real, "good", [1], lambda s: 0.15, ratio=lambda s: 1.5)  # beats 19 of 20
        rows += rows_of(real, "same", [1], lambda s: 1.05)  # beats 10
        rows += rows_of(real, "bad", [1], lambda s: 5.0)  # beaten by all
        rows += rows_of(real, "broken", [1], lambda s: 0.15)
        cls.labels = ["random", "good", "same", "bad", "broken"]
        cls.table = bm.cells(rows, cls.labels, [CAP])

    def test_simulated_cells(self):
        t = self.table
        self.assertEqual(t[("rooms", CAP, "good")].verdict, "win")
        self.assertAlmostEqual(t[("rooms", CAP, "good")].p, 2 / 2 ** 20)
        self.assertEqual(t[("rooms", CAP, "same")].verdict, "tie")
        self.assertEqual(t[("rooms", CAP, "same")].p, 1.0)
        self.assertEqual(t[("rooms", CAP, "bad")].verdict, "loss")
        self.assertEqual(t[("rooms", CAP, "broken")].verdict, "loss")  # wins its 19 pairs, but one run failed
        self.assertEqual(t[("rooms", CAP, "broken")].failed, 1)
        self.assertAlmostEqual(t[("rooms", CAP, "good")].ratio, 2.0)
        self.assertEqual(t[("rooms", CAP, "random")].verdict, "–")

    def test_real_cells(self):
        t = self.table
        self.assertEqual((t[("mrclam7", CAP, "good")].verdict, t[("mrclam7", CAP, "good")].beats), ("win", 19))
        self.assertEqual((t[("mrclam7", CAP, "same")].verdict, t[("mrclam7", CAP, "same")].beats), ("tie", 10))
        self.assertEqual((t[("mrclam7", CAP, "bad")].verdict, t[("mrclam7", CAP, "bad")].beats), ("loss", 0))
        self.assertEqual(t[("mrclam7", CAP, "random")].n, 20)

    def test_the_rule(self):
        default, qualified, summary = bm.choose_default(self.table, self.labels, ["rooms", "mrclam7"], [CAP])
        self.assertEqual(qualified, ["good"])  # broken wins both cells' tests but failed a run
        self.assertEqual(default, "good")
        self.assertEqual(summary["good"][:2], (2, 2.0))  # two wins, worst ratio 2.0 (rooms)
        # Without a qualifying candidate: the most wins, then the lowest worst ratio.
        no_good = [r for r in self.labels if r != "good"]
        default, qualified, _ = bm.choose_default(self.table, no_good, ["rooms", "mrclam7"], [CAP])
        self.assertEqual(qualified, [])
        self.assertEqual(default, "broken")  # one win (mrclam7), the others none


class Bounds(unittest.TestCase):
    """The bounds' rows land in their cell (remap_bounds), each reducer's ratio to the hindsight
    bound is the mean over seeds of the per-seed ratio, and the bounds are no candidates."""

    def test_bound_rows_and_ratios(self):
        seeds = range(1, 21)
        sim = "sim:rooms"
        rows = rows_of(sim, "none", seeds, lambda s: 0.1)
        rows += rows_of(sim, "random", seeds, lambda s: 1.0 + 0.01 * s)
        rows += rows_of(sim, "good", seeds, lambda s: 0.4 * (1 + s % 2))
        # The bounds' own compares: cap none, labelled; their reference runs are left out.
        for r in rows_of(sim, "hindsight:bound-hindsight-1of5", seeds, lambda s: 0.2) + \
                rows_of(sim, "none:bound-hindsight-1of5", seeds, lambda s: 99.0) + \
                rows_of(sim, "hindsight:bound-ceiling-1of5", seeds, lambda s: 0.15) + \
                rows_of(sim, "known-set:bound-known-set-1of5", seeds, lambda s: 0.3):
            rows.append(dict(r, cap="none"))
        remapped = bm.remap_bounds(rows, [(CAP, "1/5", 0.2)])
        self.assertFalse([r for r in remapped if r["reducer"].startswith("none:")])
        labels = ["random", "good"] + bm.BOUND_LABELS
        t = bm.cells(remapped, labels, [CAP])
        self.assertEqual(t[("rooms", CAP, "hindsight")].verdict, "win")
        self.assertAlmostEqual(t[("rooms", CAP, "hindsight")].rmse, 0.2)
        self.assertAlmostEqual(t[("rooms", CAP, "ceiling")].to_hindsight, 0.75)
        self.assertAlmostEqual(t[("rooms", CAP, "known-set")].to_hindsight, 1.5)
        self.assertAlmostEqual(t[("rooms", CAP, "good")].to_hindsight, 3.0)  # 2 and 4, ten seeds each
        self.assertAlmostEqual(t[("rooms", CAP, "hindsight")].to_hindsight, 1.0)
        default, qualified, summary = bm.choose_default(t, labels, ["rooms"], [CAP])
        self.assertEqual(set(summary), {"good"})
        text, _ = bm.markdown(t, labels, ["rooms"], [CAP], {CAP: "1/5"}, "cmd", "1-20", "0:01")
        self.assertIn("| ceiling | 0.15 win", text)
        self.assertIn("| good **(default)** | 3.00 |", text)


class QuickRun(unittest.TestCase):
    def test_quick_grid_through_the_binaries_and_resume(self):
        with tempfile.TemporaryDirectory(prefix="test_benchmark_") as tmp:
            out = os.path.join(tmp, "out")
            md = os.path.join(tmp, "RESULTS.md")
            with open(md, "w") as f:
                f.write("# Results\n\nbefore\n\n<!-- benchmark begin -->\nold\n<!-- benchmark end -->\n\nafter\n")
            cmd = [SCRIPT, "--quick", "-o", out, "--budget-slam", BUDGET_SLAM, "--budget-simulate", BUDGET_SIMULATE,
                   "--results-md", md]
            p = subprocess.run(cmd, capture_output=True, text=True)
            self.assertEqual(p.returncode, 0, p.stderr[-3000:])
            with open(os.path.join(out, "benchmark.csv")) as f:
                rows = list(csv.DictReader(f))
            cells = {(r["world"], r["reducer"]): r for r in rows}
            self.assertEqual(set(cells), {(w, r) for w in ("rooms", "mrclam7")
                                          for r in ("random", "localization-information", "hindsight", "ceiling",
                                                    "known-set")})
            self.assertEqual(cells[("rooms", "localization-information")]["n"], "2")  # two seeds paired
            self.assertEqual(cells[("mrclam7", "random")]["n"], "2")  # two random maps
            self.assertIn(cells[("mrclam7", "localization-information")]["random_maps_beaten"], ("0", "1", "2"))
            self.assertEqual(cells[("rooms", "random")]["distinct_maps"], "2")  # two worlds
            self.assertIn(cells[("mrclam7", "random")]["distinct_maps"], ("1", "2"))
            for w in ("rooms", "mrclam7"):
                self.assertAlmostEqual(float(cells[(w, "hindsight")]["to_hindsight"]), 1.0)
            for r in rows:
                self.assertEqual(r["failed"], "0")
                self.assertGreater(float(r["ratio"]), 0)
                self.assertGreater(float(r["to_hindsight"]), 0)
                self.assertTrue(0 <= float(r["success_pct"]) <= 100)
            self.assertTrue(os.path.getsize(os.path.join(out, "ratio_vs_cap.png")) > 1000)
            with open(md) as f:
                text = f.read()
            self.assertTrue(text.startswith("# Results\n\nbefore\n\n<!-- benchmark begin -->\n"))
            self.assertTrue(text.endswith("<!-- benchmark end -->\n\nafter\n"))
            self.assertIn("| localization-information", text)
            self.assertIn("**rooms**", text)
            self.assertIn("**mrclam7**", text)
            # Where the default loses to the hindsight bound, from the same folder (bound_gap).
            p = subprocess.run([os.path.join(scripttest.EXP, "bound_gap"), out, "--world", "rooms", "--cap", "1/5"],
                               capture_output=True, text=True)
            self.assertEqual(p.returncode, 0, p.stderr[-3000:])
            for seed in (1, 2):
                self.assertRegex(p.stdout, rf"\n\| {seed} \| \d+ of 31 \| \d+ of \d+ \| \d+ \| \d+ \|\n")
            self.assertIn("Decisive drops:", p.stdout)
            # Resumed: nothing runs again.
            p = subprocess.run(cmd, capture_output=True, text=True)
            self.assertEqual(p.returncode, 0, p.stderr[-3000:])
            # 4 jobs of the reducers, 9 of the bounds (rooms: hindsight, ceiling and known-set on 2 seeds;
            # MRCLAM 7: one each).
            self.assertIn("13 job(s): 13 already done, 0 to run", p.stderr)

    def test_a_bad_world_is_one_line(self):
        p = subprocess.run([SCRIPT, "-o", "/nonexistent/x", "--worlds", "moon"], capture_output=True, text=True)
        self.assertEqual(p.returncode, 2)
        self.assertIn("--worlds: 'moon' is not one of rooms, park, corridors, clusters", p.stderr)


if __name__ == "__main__":
    BUDGET_SLAM, BUDGET_SIMULATE, argv = scripttest.parse_binaries(__doc__)
    unittest.main(argv=argv)
