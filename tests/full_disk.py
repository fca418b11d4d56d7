#!/usr/bin/python3
"""budget-slam on a full disk: a small tmpfs mounted in a private mount namespace (unshare).

run: for each disk size, the run must exit 1 with one line naming the file it could not write
("cannot write '<file>' (No space left on device)"), summary.json must be valid JSON saying
status failed and why, and no output may be torn: steps.csv ends with a whole line, its rows agree
with trajectory.tum and with summary.json's step count. The largest size holds every output: the
run must succeed there.

Tiny disks and the other commands (issue 23, case 5): run on 4 to 24 KiB, compare and localize on
100 KiB, and localize on 30 to 60 KiB, where steps.csv and summary.json must agree on the steps. Each exits 1 with one line (compare: one a run and one for its own files), and every
folder made holds a valid summary.json, or the line says why it could not be written.

Exits 77 (skipped) where a tmpfs cannot be mounted (no privileges): tests/test_limits.cpp runs the
same cases on a simulated disk (DiskSpaceForTests), which needs no privileges.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

SKIP = 77


def run_on_tmpfs(budget_slam, args, size_kib, work):
    """Runs budget-slam with its output folder on a fresh tmpfs of size_kib; returns
    (exit code, stderr, copy of the output folder)."""
    mnt = os.path.join(work, "mnt")
    keep = os.path.join(work, "out_%d" % size_kib)
    os.makedirs(mnt, exist_ok=True)
    shutil.rmtree(keep, ignore_errors=True)
    script = (
        'mount -t tmpfs -o size={size}k tmpfs "$1" || exit 90\n'
        'shift; keep="$1"; shift\n'
        '"$@" 2>"$keep.err"; echo $? >"$keep.rc"\n'
        'cp -a "$MNT/out" "$keep" 2>/dev/null || mkdir -p "$keep"\n'
    ).format(size=size_kib)
    cmd = ["unshare", "-m", "--propagation", "private", "sh", "-c", script, "sh", mnt, keep,
           budget_slam] + args + ["-o", os.path.join(mnt, "out")]
    env = dict(os.environ, MNT=mnt)
    p = subprocess.run(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode == 90 or not os.path.exists(keep + ".rc"):
        return None
    with open(keep + ".rc") as f:
        rc = int(f.read())
    with open(keep + ".err", "rb") as f:
        err = f.read().decode("utf-8")
    return rc, err, keep


def whole_lines(path):
    with open(path, "rb") as f:
        data = f.read()
    assert data == b"" or data.endswith(b"\n"), "%s ends inside a line: %r" % (path, data[-40:])
    return data.count(b"\n")


def check_failed(rc, err, out, size_kib):
    where = "tmpfs of %d KiB" % size_kib
    assert rc == 1, "%s: exit %d, stderr %r" % (where, rc, err)
    lines = err.splitlines()
    assert len(lines) == 1, "%s: stderr is not one line: %r" % (where, err)
    prefix = "budget-slam: error: cannot write '"
    assert lines[0].startswith(prefix), "%s: %r" % (where, lines[0])
    assert lines[0].endswith("' (No space left on device)"), "%s: %r" % (where, lines[0])
    named = lines[0][len(prefix):lines[0].rindex("' (")]
    with open(os.path.join(out, "summary.json"), "rb") as f:
        summary = json.loads(f.read().decode("utf-8"))  # valid UTF-8 JSON
    assert summary["status"] == "failed", "%s: %r" % (where, summary)
    assert summary["error"] == lines[0][len("budget-slam: error: "):], "%s: %r" % (where, summary)
    assert os.path.basename(named) in summary.get("files_not_written", []) or \
        summary.get("counts") is None, "%s: %r" % (where, summary)
    # Nothing torn: whole lines, and the files that exist agree on the steps done.
    steps_csv = os.path.join(out, "steps.csv")
    if os.path.exists(steps_csv) and "counts" in summary:
        rows = whole_lines(steps_csv) - 1
        assert rows == summary["counts"]["steps"], "%s: %d rows, summary %r" % (
            where, rows, summary["counts"])
        tum = os.path.join(out, "trajectory.tum")
        if os.path.exists(tum):
            assert whole_lines(tum) == rows, "%s: trajectory.tum and steps.csv differ" % where
    for name in os.listdir(out):
        assert not name.endswith(".tmp") or name == "summary.json.tmp", \
            "%s: temporary file %s left" % (where, name)
    return os.path.basename(named)


def check_small(rc, err, out, where, max_lines=1):
    """Exit 1, at most max_lines lines of budget-slam's, and a valid summary.json in every folder
    made (or the line saying why none could be written)."""
    assert rc == 1, "%s: exit %d, stderr %r" % (where, rc, err)
    lines = err.splitlines()
    assert 1 <= len(lines) <= max_lines, "%s: %d lines: %r" % (where, len(lines), err)
    for line in lines:
        assert line.startswith("budget-slam: error: "), "%s: %r" % (where, line)
    assert "No space left on device" in err, "%s: %r" % (where, err)
    folders = [d for d, _, files in os.walk(out) if "config_used.ini" in files] or [out]
    for folder in folders:
        summary = os.path.join(folder, "summary.json")
        if os.path.exists(summary):
            with open(summary, "rb") as f:
                j = json.loads(f.read().decode("utf-8"))
            assert j["status"] == "failed", "%s: %s: %r" % (where, summary, j)
        else:
            assert "summary.json" in err, "%s: no %s and the line does not say why: %r" % (
                where, summary, err)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--budget-slam", required=True)
    ap.add_argument("--source", required=True)
    a = ap.parse_args()
    if shutil.which("unshare") is None:
        print("SKIP: no unshare(1) to mount a private tmpfs")
        return SKIP
    args = ["run", "-c", os.path.join(a.source, "tests/data/EKF-SLAM_test_2d.ini"), "-i",
            os.path.join(a.source, "rawlogs/kf-slam_demo.rawlog"), "--quiet", "--reducer",
            "oldest", "--cap", "10"]
    work = tempfile.mkdtemp(prefix="budget_slam_full_disk_")
    try:
        # A roomy disk first: every output fits, the run succeeds (and says how much it writes).
        roomy = run_on_tmpfs(a.budget_slam, args, 4096, work)
        if roomy is None:
            print("SKIP: cannot mount a tmpfs in a private mount namespace here")
            return SKIP
        rc, err, out = roomy
        assert rc == 0, "4 MiB tmpfs: exit %d, %r" % (rc, err)
        used = sum(os.path.getsize(os.path.join(d, f)) for d, _, fs in os.walk(out) for f in fs)
        print("a full run writes %d bytes" % used)
        named = set()
        # Smaller and smaller disks: the space runs out in different files.
        for size in (290, 200, 120, 80, 56, 48, 40):
            rc, err, out = run_on_tmpfs(a.budget_slam, args, size, work)
            name = check_failed(rc, err, out, size)
            print("tmpfs %d KiB: exit 1, %s" % (size, err.strip()))
            named.add(name)
        assert len(named) >= 2, "every size failed on the same file: %r" % named

        # Tiny disks: the space set aside for summary.json is all there is.
        for size in (4, 8, 16, 24):
            rc, err, out = run_on_tmpfs(a.budget_slam, args, size, work)
            check_small(rc, err, out, "run on a tmpfs of %d KiB" % size)
            print("run, tmpfs %d KiB: exit 1, %s" % (size, err.strip()))
        # compare and localize on 100 KiB.
        ini = os.path.join(a.source, "tests/data/EKF-SLAM_test_2d.ini")
        demo = os.path.join(a.source, "rawlogs/kf-slam_demo.rawlog")
        compare = ["compare", "-c", ini, "-i", demo, "--quiet", "--reducers", "mi,oldest", "--cap",
                   "10"]
        rc, err, out = run_on_tmpfs(a.budget_slam, compare, 100, work)
        check_small(rc, err, out, "compare on a tmpfs of 100 KiB", max_lines=4)
        print("compare, tmpfs 100 KiB: exit 1, %d line(s)" % len(err.splitlines()))
        mapdir = os.path.join(work, "map")
        p = subprocess.run([a.budget_slam] + args + ["-o", mapdir], capture_output=True, text=True)
        assert p.returncode == 0, p.stderr
        localize = ["localize", "-c", ini, "-i", demo, "--quiet", "--map", mapdir]
        rc, err, out = run_on_tmpfs(a.budget_slam, localize, 100, work)
        check_small(rc, err, out, "localize on a tmpfs of 100 KiB")
        print("localize, tmpfs 100 KiB: exit 1, %s" % err.strip())
        # localize's steps.csv and summary.json agree on the steps done (issue 35: on 30 KiB,
        # 93 rows and 94 steps, every time).
        for size in (30, 40, 60):
            rc, err, out = run_on_tmpfs(a.budget_slam, localize, size, work)
            where = "localize on a tmpfs of %d KiB" % size
            check_small(rc, err, out, where)
            steps_csv, summary = os.path.join(out, "steps.csv"), os.path.join(out, "summary.json")
            if os.path.exists(steps_csv) and os.path.exists(summary):
                with open(summary, "rb") as f:
                    counts = json.loads(f.read().decode("utf-8")).get("counts")
                if counts is not None:
                    rows = whole_lines(steps_csv) - 1
                    assert rows == counts["steps"], "%s: steps.csv %d rows, summary.json %d steps" % (
                        where, rows, counts["steps"])
            print("%s: exit 1, steps.csv and summary.json agree" % where)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print("ok")
    return 0


if __name__ == "__main__":
    sys.exit(main())
