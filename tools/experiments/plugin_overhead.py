#!/usr/bin/python3
"""What a reducer written in Python costs (docs/PERFORMANCE.md "A reducer in Python"): the
built-in `oldest` against python/plugins/oldest.py (the same decisions) on one rawlog and cap,
runs alternated, shadows off. Prints one line a run and the medians: the run's wall time and
the process's CPU time (user + system: what a loaded machine distorts least), the SLAM steps' CPU
time (steps.csv step_cpu_ms summed: the step loop's thread, the plugin's calls included), the
drops, the ratios Python / built-in, and the extra CPU time a drop.

    tools/experiments/plugin_overhead.py [--rawlog rawlogs/victoria_park.rawlog] [--cap 50]
        [--repeats 3] [--backend ekf] [--budget-slam build/bin/budget-slam]
"""
import argparse
import json
import csv
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))


def one_run(binary, rawlog, cap, backend, plugin, out):
    cmd = [binary, "run", "-c", os.path.join(ROOT, "config.ini"), "-i", rawlog, "--cap", str(cap),
           "--backend", backend, "--set", "LandmarkBudget.shadow_reducers=", "--quiet", "--force",
           "-o", out]
    cmd += ["--plugin", os.path.join(ROOT, "python", "plugins", "oldest.py"), "--reducer",
            "py-oldest"] if plugin else ["--reducer", "oldest"]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if p.returncode != 0:
        sys.exit(f"plugin_overhead: {' '.join(cmd)}: exit {p.returncode}: {p.stderr.strip()}")
    with open(os.path.join(out, "steps.csv"), newline="") as f:
        steps_cpu = sum(float(r["step_cpu_ms"]) for r in csv.DictReader(f)) / 1000
    with open(os.path.join(out, "evictions.csv")) as f:
        drops = sum(1 for _ in f) - 1
    return wall, cpu, steps_cpu, drops


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rawlog", default=os.path.join(ROOT, "rawlogs", "victoria_park.rawlog"))
    ap.add_argument("--cap", type=int, default=50)
    ap.add_argument("--backend", default="ekf")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--budget-slam", default=os.path.join(ROOT, "build", "bin", "budget-slam"))
    a = ap.parse_args()
    res = {False: [], True: []}
    with tempfile.TemporaryDirectory(prefix="plugin_overhead_") as tmp:
        for k in range(a.repeats):
            for plugin in (False, True):
                r = one_run(a.budget_slam, a.rawlog, a.cap, a.backend, plugin,
                            os.path.join(tmp, f"{k}_{int(plugin)}"))
                res[plugin].append(r)
                print(f"{'python ' if plugin else 'builtin'} run {k + 1}: wall {r[0]:.2f} s, "
                      f"CPU {r[1]:.2f} s, steps' CPU {r[2]:.3f} s, {r[3]} drops", flush=True)
    med = {p: [statistics.median(x[i] for x in res[p]) for i in range(4)] for p in res}
    b, p = med[False], med[True]
    if b[3] != p[3]:
        sys.exit(f"plugin_overhead: {b[3]} drops built-in, {p[3]} in Python: not the same decisions")
    print(f"median wall: built-in {b[0]:.2f} s, Python {p[0]:.2f} s, ratio {p[0] / b[0]:.2f}")
    print(f"median CPU: built-in {b[1]:.2f} s, Python {p[1]:.2f} s, ratio {p[1] / b[1]:.2f}")
    print(f"median steps' CPU: built-in {b[2]:.3f} s, Python {p[2]:.3f} s, ratio {p[2] / b[2]:.2f}")
    print(f"drops: {b[3]}; extra CPU a drop (steps): {(p[2] - b[2]) / b[3] * 1e6:.0f} us; "
          f"extra CPU a run (Python's start included): {p[1] - b[1]:.2f} s")


if __name__ == "__main__":
    main()
