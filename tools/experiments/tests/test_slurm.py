#!/usr/bin/python3
"""The tiny sweep on a real SLURM scheduler: tools/slurm/local-cluster.sh starts a one-node cluster
in a temporary folder, `sweep --slurm` submits the jobs as a job array (once returning the job id
and collected afterwards with --collect-only, once with --wait), and results.csv must hold the
local sweep's rows, values equal except the timings. The cluster is stopped at the end and no
slurm or munge process started by the test may be left.

Exits 77 (CTest: skipped) with one line when slurm-wlm/munge or root privileges are missing.

    test_slurm.py --budget-slam build/bin/budget-slam [unittest options]
"""
import argparse
import csv
import os
import subprocess
import sys
import tempfile
import time
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
EXP = os.path.dirname(HERE)
ROOT = os.path.dirname(os.path.dirname(EXP))
SWEEP = os.path.join(EXP, "sweep")
TINY = os.path.join(EXP, "experiments", "tiny.ini")
CLUSTER = os.path.join(ROOT, "tools", "slurm", "local-cluster.sh")
SKIP = 77

TIMING_METRICS = {"time_s", "step_ms_mean", "step_ms_max", "peak_rss_bytes"}
DAEMONS = {"/usr/sbin/slurmctld", "/usr/sbin/slurmd", "/usr/sbin/slurmstepd", "/usr/sbin/munged",
           "/usr/bin/srun"}
BUDGET_SLAM = None


def belongs_to(pid, cluster_dir):
    """Whether a process was started for the cluster in cluster_dir (its command line or
    environment names the folder), so clusters of other test runs on the machine are not counted."""
    for part in ("cmdline", "environ"):
        try:
            with open(f"/proc/{pid}/{part}", "rb") as f:
                if cluster_dir.encode() in f.read():
                    return True
        except OSError:
            pass
    return False


def daemon_pids(cluster_dir=None):
    """{pid: exe} of every slurm/munge process on the machine (of cluster_dir's cluster only,
    when given)."""
    out = {}
    for p in os.listdir("/proc"):
        if p.isdigit():
            try:
                exe = os.readlink(f"/proc/{p}/exe")
            except OSError:
                continue
            if exe in DAEMONS and (cluster_dir is None or belongs_to(p, cluster_dir)):
                out[int(p)] = exe
    return out


def results(path):
    """{(rawlog, backend, reducer, cap, seed, metric): value} without the timing metrics."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    keyed = {(r["rawlog"], r["backend"], r["reducer"], r["cap"], r["seed"], r["metric"]): r["value"]
             for r in rows if r["metric"] not in TIMING_METRICS}
    return rows, keyed


class SweepOnSlurm(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="test_slurm_")
        cls.env = dict(os.environ, BUDGET_SLAM_SLURM_DIR=os.path.join(cls.tmp.name, "cluster"))
        cls.env["SLURM_CONF"] = os.path.join(cls.env["BUDGET_SLAM_SLURM_DIR"], "slurm.conf")
        cls.before = daemon_pids()
        p = subprocess.run([CLUSTER, "start"], env=cls.env, capture_output=True, text=True, timeout=120)
        cls.started = p.returncode == 0
        if not cls.started:
            subprocess.run([CLUSTER, "stop"], env=cls.env, capture_output=True, timeout=120)
            raise RuntimeError(f"local-cluster.sh start failed ({p.returncode}): {p.stderr}")
        cls.local = os.path.join(cls.tmp.name, "local")
        p = cls.sweep(cls.local, "-j", "2")
        assert p.returncode == 0, p.stderr

    @classmethod
    def tearDownClass(cls):
        p = subprocess.run([CLUSTER, "stop"], env=cls.env, capture_output=True, text=True, timeout=120)
        left = {pid: exe for pid, exe in daemon_pids(cls.env["BUDGET_SLAM_SLURM_DIR"]).items()
                if pid not in cls.before}
        cls.tmp.cleanup()
        # Reported as an error of the class when the cluster did not go away cleanly.
        assert p.returncode == 0, p.stderr
        assert not left, f"processes left after local-cluster.sh stop: {left}"

    @classmethod
    def sweep(cls, out, *extra):
        return subprocess.run(["/usr/bin/python3", SWEEP, TINY, "-o", out, "--budget-slam", BUDGET_SLAM,
                               "--no-plots", *extra], env=cls.env, capture_output=True, text=True, timeout=600)

    def assertSameResults(self, out):
        local_rows, local = results(os.path.join(self.local, "results.csv"))
        rows, slurm = results(os.path.join(out, "results.csv"))
        self.assertEqual(len(rows), len(local_rows))
        self.assertEqual(len(rows), 2 * (28 + 2 * 29))  # as test_sweep.py: every row there
        self.assertEqual(slurm, local)

    def test_submit_returns_the_job_id_then_collect_only_gathers_the_results(self):
        out = os.path.join(self.tmp.name, "submitted")
        p = self.sweep(out, "--slurm", "--partition", "local", "--array-throttle", "1", "--cpus-per-task", "1")
        self.assertEqual(p.returncode, 0, p.stderr)
        job_id = p.stdout.strip()
        self.assertRegex(job_id, r"^\d+$")
        self.assertIn(f"submitted job array {job_id}: 2 task(s), lines 1-2 of {out}/jobs.txt", p.stderr)
        self.assertIn("--collect-only", p.stderr)
        shown = subprocess.run(["scontrol", "show", "job", job_id], env=self.env, capture_output=True, text=True)
        self.assertIn("Partition=local", shown.stdout)
        self.assertIn("ArrayTaskThrottle=1", shown.stdout)

        # A second submission while the first is queued or running is refused.
        again = self.sweep(out, "--slurm", "--cpus-per-task", "1")
        if again.returncode != 0:
            self.assertIn(f"job array {job_id} of this sweep is still queued or running", again.stderr)
        else:  # the array had already ended: then nothing is left to submit
            self.assertIn("2 already done, 0 to submit", again.stderr)

        deadline = time.time() + 300
        while time.time() < deadline:
            q = subprocess.run(["squeue", "-h", "-j", job_id, "-o", "%i"], env=self.env, capture_output=True, text=True)
            if q.returncode == 0 and not q.stdout.strip():
                break
            time.sleep(0.5)
        p = self.sweep(out, "--collect-only")
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertSameResults(out)
        for task in (1, 2):
            self.assertTrue(os.path.isfile(os.path.join(out, "logs", f"slurm-{job_id}_{task}.out")))

    def test_wait_submits_waits_and_collects_like_a_local_sweep(self):
        out = os.path.join(self.tmp.name, "waited")
        p = self.sweep(out, "--slurm", "--wait", "--cpus-per-task", "1", "--array-throttle", "2")
        self.assertEqual(p.returncode, 0, p.stderr)
        job_id = p.stdout.strip()
        self.assertRegex(job_id, r"^\d+$")
        self.assertIn(f"[slurm {job_id}] 2 task(s) ended, 0 running, 0 waiting", p.stderr)
        self.assertIn("results.csv: 172 rows", p.stderr)
        self.assertSameResults(out)
        with open(os.path.join(out, "slurm_jobs.txt")) as f:
            self.assertEqual(f.read(), f"{job_id} 1-2%2\n")

        # Everything done: nothing is submitted, the results are collected again.
        p = self.sweep(out, "--slurm", "--wait", "--cpus-per-task", "1")
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertEqual(p.stdout, "")
        self.assertIn("2 already done, 0 to submit", p.stderr)
        self.assertSameResults(out)

    def test_a_task_that_can_never_run_is_cancelled_with_one_line(self):
        # More CPUs a task than the node has: SLURM keeps it pending (PartitionConfig) for ever.
        out = os.path.join(self.tmp.name, "too-big")
        p = self.sweep(out, "--slurm", "--wait", "--cpus-per-task", "4096")
        self.assertEqual(p.returncode, 1, p.stderr)
        last = p.stderr.strip().splitlines()[-1]
        self.assertRegex(last, r"^sweep: job array \d+ cannot run \(squeue reason PartitionConfig: .*cancelled it$")
        job_id = last.split()[3]
        q = subprocess.run(["squeue", "-h", "-j", job_id, "-o", "%T"], env=self.env, capture_output=True, text=True)
        self.assertNotIn("PENDING", q.stdout)

    def test_sbatch_refusal_is_one_line(self):
        # A partition the cluster does not have: sbatch refuses, the sweep says so and exits 1.
        out = os.path.join(self.tmp.name, "refused")
        p = self.sweep(out, "--slurm", "--partition", "nosuch", "--cpus-per-task", "1")
        self.assertEqual(p.returncode, 1, p.stderr)
        last = p.stderr.strip().splitlines()[-1]
        self.assertTrue(last.startswith("sweep: sbatch refused the array: "), last)
        self.assertIn("invalid partition", last.lower())
        self.assertFalse(os.path.exists(os.path.join(out, "slurm_jobs.txt")))


def skip_reason():
    for tool in ("slurmctld", "slurmd", "munged", "sbatch"):
        if not any(os.access(os.path.join(d, tool), os.X_OK) for d in ("/usr/sbin", "/usr/bin")):
            return f"{tool} not installed (Debian packages slurm-wlm and munge)"
    if os.geteuid() != 0:
        return "the local SLURM cluster needs root (slurmd starts the jobs' processes)"
    return None


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--budget-slam", default=os.path.join(ROOT, "build", "bin", "budget-slam"))
    ap.add_argument("--budget-simulate", default=os.path.join(ROOT, "build", "bin", "budget-simulate"))
    args, rest = ap.parse_known_args()
    BUDGET_SLAM = os.path.abspath(args.budget_slam)
    reason = skip_reason()
    if reason:
        print(f"SKIPPED test_slurm: {reason}")
        sys.exit(SKIP)
    unittest.main(argv=[sys.argv[0]] + rest)
