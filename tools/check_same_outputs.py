#!/usr/bin/python3
"""Check that two budget-slam binaries write the same outputs on every shipped rawlog.

    tools/check_same_outputs.py --before BUILD_DIR_OR_BIN --after BUILD_DIR_OR_BIN
        [--out DIR] [--rawlogs NAME,...] [--commands run,compare-ekf,compare-graph,localize,
        compare-reloc] [--quick] [-j N] [--max-steps N] [--source DIR]

For every rawlog of `rawlogs/*.rawlog` (its sidecar `.ini` and ground truth are found by
budget-slam itself) both binaries run the same command lines, from the source tree, into
`OUT/before/<rawlog>/<command>/` and `OUT/after/<rawlog>/<command>/`:

    run            budget-slam run -c config.ini -i rawlogs/R.rawlog -o DIR
    compare-ekf    budget-slam compare -c config.ini -i rawlogs/R.rawlog --backend ekf -o DIR
    compare-graph  budget-slam compare -c config.ini -i rawlogs/R.rawlog --backend graph -o DIR
    localize       budget-slam localize -c config.ini --map RUN_DIR -i rawlogs/R.rawlog -o DIR
                   (+ --reference-trajectory RUN_DIR/trajectory.tum without ground truth)
    compare-reloc  budget-slam compare -c config.ini -i rawlogs/R.rawlog --relocalize T,... -o DIR
                   (only where a second traversal T of R's world is shipped)

Then every file both sides wrote, each command's stdout and stderr and its exit code are
compared byte for byte after NORMALIZATION (below): the fields that differ between two runs of
one binary (timings, memory, the output folder's own path, progress lines), found by running one
binary twice. Exit 0 and "N files identical over M command lines" when everything matches; 1
with one line a differing file (its path, the first differing line, key or column); 2 on a bad
command line or a binary that cannot be run. docs/ARCHITECTURE.md, "Checking that a refactoring
changes no output".
"""
import argparse
import concurrent.futures
import csv
import io
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.dirname(HERE)
COMMANDS = ["run", "compare-ekf", "compare-graph", "localize", "compare-reloc"]
# --quick: every command on four small rawlogs (MRPT's demo, the paper's world, the README's
# simulated rooms, real MRCLAM data), and run and localize on one without ground truth
# (localize's --reference-trajectory path); whole rawlogs, no --max-steps cut.
QUICK = {"kf-slam_demo": COMMANDS, "paper_synthetic": COMMANDS, "rooms": COMMANDS,
         "mrclam7_robot1": COMMANDS, "victoria_park_from3500": ["run", "localize"]}
OUT_TOKEN = "<OUT>"
NORMALIZED = "<normalized>"

# ---- Normalization: exactly the fields that differ between two runs of the same binary. ----
# CSV columns (by file name) that measure the machine, not the estimate.
CSV_COLUMNS = {
    "steps.csv": {"step_ms", "step_cpu_ms", "rss_bytes"},  # run, compare's runs, localize
    "comparison.csv": {"time_s"},  # wall time of the SLAM steps
}
# Markdown table columns (by file name and header cell); compare prints comparison.md's tables on
# stdout too.
MD_COLUMNS = {"comparison.md": {"time (s)"}}
MD_COLUMNS.update({f"{c}.stdout": {"time (s)"} for c in ["compare-ekf", "compare-graph",
                                                         "compare-reloc"]})
# summary.json keys (dotted paths from the top) whose values are timings or memory.
JSON_KEYS = {"summary.json": ["timings"]}
# Lines of stdout / stderr: progress reports (every [Report] progress_every_s seconds) are
# dropped; the seconds of SLAM the closing line reports are replaced.
# core/Progress.cpp's ProgressReporter::line, e.g. "budget-slam: compare 61%, 5208 of 8502
# steps, 843 steps/s, elapsed 0:06, ETA 0:04 (2/6 runs done)".
PROGRESS_LINE = re.compile(r"^budget-slam: [a-z][a-z ]* \d+%, \d+( of \d+)? steps(, \d+ steps/s)?, "
                           r"elapsed \S+, ETA \S+( \(.*\))?$")
SECONDS_OF_SLAM = re.compile(r"\([0-9.]+ s of SLAM\)")


def norm_text(text, out_root):
    """Every text file: the side's own output folder (an absolute path) becomes <OUT>."""
    return text.replace(out_root, OUT_TOKEN)


def norm_csv(text, columns):
    """The columns' cells replaced, line by line. A line that Python's csv module would not write
    back byte for byte (other quoting, a cell over two lines) is kept as it is, so that no
    difference of quoting is hidden."""
    lines = text.split("\n")
    header = next(csv.reader([lines[0]]), [])
    idx = {i for i, name in enumerate(header) if name in columns}
    if not idx:
        return text
    for n, line in enumerate(lines[1:], start=1):
        row = next(csv.reader([line]), None)
        if row is None or write_csv_row(row) != line:
            continue
        lines[n] = write_csv_row([NORMALIZED if i in idx else v for i, v in enumerate(row)])
    return "\n".join(lines)


def write_csv_row(row):
    out = io.StringIO()
    csv.writer(out, lineterminator="").writerow(row)
    return out.getvalue()


def norm_md(text, columns):
    lines, cols = text.split("\n"), set()
    for n, line in enumerate(lines):
        if not line.startswith("|"):
            cols = set()
            continue
        cells = line.split("|")
        if not cols and n + 1 < len(lines) and lines[n + 1].startswith("|---"):
            cols = {i for i, c in enumerate(cells) if c.strip() in columns}
            continue
        if cols and not line.startswith("|---"):
            lines[n] = "|".join(NORMALIZED if i in cols else c for i, c in enumerate(cells))
    return "\n".join(lines)


def norm_json(text, keys):
    """Each key's object or value replaced in the text itself: key order, spacing and every
    other value stay as written (a flat object or a scalar; no key of JSON_KEYS holds more)."""
    for key in keys:
        text = re.sub(r'("' + re.escape(key) + r'":\s*)(\{[^{}]*\}|[^,{}\[\]\n]+)',
                      lambda m: m.group(1) + '"' + NORMALIZED + '"', text)
    return text


def norm_stream(text, progress=True, seconds=True):
    lines = [l for l in text.split("\n") if not (progress and PROGRESS_LINE.match(l))]
    if seconds:
        lines = [SECONDS_OF_SLAM.sub("(<normalized> s of SLAM)", l) for l in lines]
    return "\n".join(lines)


RULES = ["output_path", "csv_columns", "md_columns", "json_keys", "progress_lines",
         "seconds_of_slam"]


def normalized(path, rel, out_root, off=()):
    """The file's content as compared: bytes for binary files, normalized text else (`off`:
    rules of RULES left out, to show what each one hides)."""
    with open(path, "rb") as f:
        data = f.read()
    name = os.path.basename(rel)
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        return data
    if "output_path" not in off:
        text = norm_text(text, out_root)
    if name in CSV_COLUMNS and "csv_columns" not in off:
        text = norm_csv(text, CSV_COLUMNS[name])
    if name in MD_COLUMNS and "md_columns" not in off:
        text = norm_md(text, MD_COLUMNS[name])
    if name in JSON_KEYS and "json_keys" not in off:
        text = norm_json(text, JSON_KEYS[name])
    if name.endswith((".stdout", ".stderr")):
        text = norm_stream(text, "progress_lines" not in off, "seconds_of_slam" not in off)
    return text


def first_difference(a, b, rel=".json"):
    """Where two normalized contents of file `rel` first differ, as a short phrase."""
    if rel.endswith(".json"):
        try:
            return "key " + json_difference(json.loads(a), json.loads(b))
        except (TypeError, ValueError):
            pass  # not JSON, or the same values written differently: the first line differing
    if isinstance(a, bytes) or isinstance(b, bytes):
        a = a if isinstance(a, bytes) else a.encode()
        b = b if isinstance(b, bytes) else b.encode()
        n = next((i for i, (x, y) in enumerate(zip(a, b)) if x != y), min(len(a), len(b)))
        return f"byte {n} ({len(a)} bytes before, {len(b)} after)"
    la, lb = a.split("\n"), b.split("\n")
    for n, (x, y) in enumerate(zip(la, lb), start=1):
        if x != y:
            c = next((i for i, (p, q) in enumerate(zip(x, y)) if p != q), min(len(x), len(y)))
            lo = max(0, c - 30)
            return f"line {n} col {c + 1}: {x[lo:c + 40]!r} != {y[lo:c + 40]!r}"
    return f"{len(la)} lines before, {len(lb)} after"


def json_difference(a, b, path=""):
    """The first key path (a.b[2].c) at which two parsed JSON documents differ, or None."""
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            sub = f"{path}.{k}" if path else k
            if k not in a or k not in b:
                return f"{sub} only {'after' if k not in a else 'before'}"
            d = json_difference(a[k], b[k], sub)
            if d:
                return d
        return None
    if isinstance(a, list) and isinstance(b, list):
        for i, (x, y) in enumerate(zip(a, b)):
            d = json_difference(x, y, f"{path}[{i}]")
            if d:
                return d
        return None if len(a) == len(b) else f"{path}: {len(a)} items before, {len(b)} after"
    return None if a == b else f"{path}: {json.dumps(a)[:60]} != {json.dumps(b)[:60]}"


# ---- The command lines. ----
def has_ground_truth(source, stem):
    return os.path.exists(os.path.join(source, "rawlogs", stem + "_ground_truth_robot_path.txt"))


def traversals(source, stem):
    """The shipped second traversals of a rawlog's world (docs/DATASETS.md): R_revisit, and
    robots 2-5 of MRCLAM 7 for robot 1 (its world frame); Victoria Park's second half has no
    ground truth and would need a reference trajectory, so it is left out."""
    have = lambda t: os.path.exists(os.path.join(source, "rawlogs", t + ".rawlog"))
    if have(stem + "_revisit"):
        return [stem + "_revisit"]
    if stem == "mrclam7_robot1":
        return [t for t in (f"mrclam7_robot{i}" for i in range(2, 6)) if have(t)]
    return []


def command_line(binary, command, stem, side_dir, source, max_steps, extra):
    rawlog = f"rawlogs/{stem}.rawlog"
    out = os.path.join(side_dir, stem, command)
    if command == "run":
        args = ["run", "-c", "config.ini", "-i", rawlog, "-o", out]
    elif command == "compare-reloc":
        args = ["compare", "-c", "config.ini", "-i", rawlog, "--relocalize",
                ",".join(f"rawlogs/{t}.rawlog" for t in traversals(source, stem)), "-o", out]
    elif command.startswith("compare-"):
        args = ["compare", "-c", "config.ini", "-i", rawlog, "--backend",
                command[len("compare-"):], "-o", out]
    elif command == "localize":
        run_dir = os.path.join(side_dir, stem, "run")
        args = ["localize", "-c", "config.ini", "--map", run_dir, "-i", rawlog, "-o", out]
        if not has_ground_truth(source, stem):
            args += ["--reference-trajectory", os.path.join(run_dir, "trajectory.tum")]
    else:
        raise ValueError(command)
    if max_steps:
        args += ["--max-steps", str(max_steps)]
    return [binary] + args + extra


def run_one(cmd, log_base, source):
    """Runs one command line (niced) with its stdout, stderr and exit code beside its folder, and
    the line itself (`.cmd`, the binary named budget-slam), so that the lines are compared too."""
    with open(log_base + ".cmd", "w") as f:
        f.write(" ".join(["budget-slam"] + cmd[1:]) + "\n")
    with open(log_base + ".stdout", "wb") as o, open(log_base + ".stderr", "wb") as e:
        p = subprocess.Popen(["nice", "-n", "10"] + cmd, cwd=source, stdout=o, stderr=e,
                             stdin=subprocess.DEVNULL)
        _, status, usage = os.wait4(p.pid, 0)
        p.returncode = os.waitstatus_to_exitcode(status)
    with open(log_base + ".exit", "w") as f:
        f.write(f"{p.returncode}\n")
    return p.returncode, usage.ru_utime + usage.ru_stime


# Rough cost of a command line, to start the longest first (the graph backend's compare runs
# every reducer with a factorization a step; Victoria Park is the longest rawlog).
COST = {"compare-graph": 100, "compare-reloc": 15, "compare-ekf": 10, "run": 2, "localize": 1}


def chains_of(sides, plan, source, max_steps):
    """Independent chains of (side, name, command line, log base); localize follows its run."""
    chains = []
    for stem, commands in plan.items():
        size = os.path.getsize(os.path.join(source, "rawlogs", stem + ".rawlog"))
        for side, (binary, side_dir, extra) in sides.items():
            os.makedirs(os.path.join(side_dir, stem), exist_ok=True)

            def link(c):
                return (side, f"{stem} {c}",
                        command_line(binary, c, stem, side_dir, source, max_steps, extra),
                        os.path.join(side_dir, stem, c))

            for c in commands:
                if c == "localize":
                    continue  # after its run
                chain = [link(c)] + ([link("localize")] if c == "run" and "localize" in commands
                                     else [])
                chains.append((size * sum(COST[x[1].split()[1]] for x in chain), chain))
    return [c for _, c in sorted(chains, key=lambda x: -x[0])]


def all_files(root, plan):
    """The files of the plan's command lines under one side's folder, relative to it."""
    found = set()
    for stem, commands in plan.items():
        for c in commands:
            found |= {f"{stem}/{c}{ext}" for ext in (".cmd", ".stdout", ".stderr", ".exit")
                      if os.path.exists(os.path.join(root, stem, c + ext))}
            for d, _, files in os.walk(os.path.join(root, stem, c)):
                found |= {os.path.relpath(os.path.join(d, f), root) for f in files}
    return found


def compare_trees(before, after, plan, off=()):
    """(number of files compared, [one line a differing file])."""
    fa, fb = all_files(before, plan), all_files(after, plan)
    lines = [f"{rel}: only before" for rel in sorted(fa - fb)]
    lines += [f"{rel}: only after" for rel in sorted(fb - fa)]
    for rel in sorted(fa & fb):
        a = normalized(os.path.join(before, rel), rel, before, off)
        b = normalized(os.path.join(after, rel), rel, after, off)
        if a != b:
            lines.append(f"{rel}: {first_difference(a, b, rel)}")
    return len(fa | fb), lines


def has_outputs(side_dir, plan, what):
    """True when every command line of the plan ran into `side_dir`, else one error line."""
    missing = [f"{s}/{c}" for s, cs in plan.items() for c in cs
               if not os.path.isfile(os.path.join(side_dir, s, c + ".exit"))]
    if missing:
        print(f"check_same_outputs: {what}: no outputs of {', '.join(missing[:3])}"
              f"{' ...' if len(missing) > 3 else ''} in {side_dir}", file=sys.stderr)
    return not missing


def binary_of(path):
    p = os.path.join(path, "bin", "budget-slam") if os.path.isdir(path) else path
    if not (os.path.isfile(p) and os.access(p, os.X_OK)):
        raise ValueError(f"{path}: no budget-slam executable (a build folder or the binary)")
    return os.path.abspath(p)


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--before", help="build folder (its bin/budget-slam) or binary")
    ap.add_argument("--after", help="build folder (its bin/budget-slam) or binary")
    ap.add_argument("--out", help="a new or empty folder for both sides' outputs "
                    "(default: a temporary one, removed when everything matches)")
    ap.add_argument("--rawlogs",
                    help="comma-separated rawlog names (default: every rawlogs/*.rawlog)")
    ap.add_argument("--commands", default=",".join(COMMANDS),
                    help="comma-separated, of " + ",".join(COMMANDS) + " (default: all)")
    ap.add_argument("--quick", action="store_true",
                    help="a subset: every command on kf-slam_demo, paper_synthetic, rooms and "
                    "mrclam7_robot1; run and localize on victoria_park_from3500")
    ap.add_argument("-j", "--jobs", type=int, default=2, help="command lines at once (default 2)")
    ap.add_argument("--max-steps", type=int, default=0, help="--max-steps N for every command")
    ap.add_argument("--source", default=SOURCE,
                    help="tree holding config.ini and rawlogs/ (default: this tool's)")
    ap.add_argument("--reuse-before", metavar="DIR",
                    help="the --out folder of an earlier check with the same rawlogs, commands and "
                    "--max-steps: its before/ side is compared again instead of being rerun "
                    "(--before is then only a label)")
    ap.add_argument("--compare-only", metavar="DIR",
                    help="run nothing: compare DIR/before with DIR/after (an earlier --out)")
    ap.add_argument("--leave-out", default="", metavar="RULE,...",
                    help="normalization rules not applied (" + ",".join(RULES) + ", or all): "
                    "shows what each one hides")
    ap.add_argument("--after-set", action="append", default=[], metavar="Section.key=value",
                    help="an extra --set for the after side only: a change the check must catch "
                    "(the checker's own test)")
    a = ap.parse_args(argv[1:])
    off = RULES if a.leave_out == "all" else [r for r in a.leave_out.split(",") if r]
    try:
        for bad in [r for r in off if r not in RULES]:
            raise ValueError(f"--leave-out: unknown rule '{bad}' (one of {','.join(RULES)})")
        if not a.compare_only and not (a.after and (a.before or a.reuse_before)):
            raise ValueError("--after and --before (or --reuse-before) are needed")
        before_bin = binary_of(a.before) if a.before and not a.compare_only else None
        after_bin = binary_of(a.after) if not a.compare_only else None
    except ValueError as e:
        print(f"check_same_outputs: {e}", file=sys.stderr)
        return 2
    source = os.path.abspath(a.source)
    available = sorted(f[:-len(".rawlog")] for f in os.listdir(os.path.join(source, "rawlogs"))
                       if f.endswith(".rawlog"))
    stems = a.rawlogs.split(",") if a.rawlogs else (list(QUICK) if a.quick else available)
    commands = a.commands.split(",")
    for bad in [s for s in stems if s not in available]:
        print(f"check_same_outputs: --rawlogs: no rawlogs/{bad}.rawlog", file=sys.stderr)
        return 2
    for bad in [c for c in commands if c not in COMMANDS]:
        print(f"check_same_outputs: --commands: unknown '{bad}' (one of {','.join(COMMANDS)})",
              file=sys.stderr)
        return 2
    if "localize" in commands and "run" not in commands:
        print("check_same_outputs: --commands: localize needs run (its map)", file=sys.stderr)
        return 2
    # rawlog -> its command lines; --quick's own lists unless --rawlogs or --commands says
    plan = {st: [c for c in (QUICK.get(st, COMMANDS) if a.quick else COMMANDS)
                 if c in commands and (c != "compare-reloc" or traversals(source, st))]
            for st in stems}
    if not any(plan.values()):
        print("check_same_outputs: no command line to run (compare-reloc needs a rawlog with a "
              "second traversal)", file=sys.stderr)
        return 2
    if a.compare_only:
        root = os.path.abspath(a.compare_only)
        for side in ("before", "after"):
            if not has_outputs(os.path.join(root, side), plan, f"--compare-only {a.compare_only}"):
                return 2
        n_files, diffs = compare_trees(os.path.join(root, "before"), os.path.join(root, "after"),
                                       plan, off)
        n_lines = sum(len(cs) for cs in plan.values())
        for d in diffs:
            print(d)
        print(f"{len(diffs)} of {n_files} files differ over {n_lines} command lines" if diffs else
              f"{n_files} files identical over {n_lines} command lines")
        return 1 if diffs else 0
    old_before = a.reuse_before and os.path.join(os.path.abspath(a.reuse_before), "before")
    if old_before and not has_outputs(old_before, plan, f"--reuse-before {a.reuse_before}"):
        return 2
    if a.out:
        out = os.path.abspath(a.out)
        if os.path.exists(out) and os.listdir(out):
            print(f"check_same_outputs: --out {a.out}: not empty", file=sys.stderr)
            return 2
        os.makedirs(out, exist_ok=True)
    else:
        out = tempfile.mkdtemp(prefix="check_same_outputs.")
    extra_after = [x for s in a.after_set for x in ("--set", s)]
    sides = {"before": (before_bin, os.path.join(out, "before"), []),
             "after": (after_bin, os.path.join(out, "after"), extra_after)}
    reuse = set()
    if a.reuse_before:
        sides["before"] = (before_bin, old_before, [])
        reuse.add("before")
    start = time.monotonic()
    chains = chains_of({k: v for k, v in sides.items() if k not in reuse}, plan, source,
                       a.max_steps)
    n_lines = sum(len(cs) for cs in plan.values())
    total, done, cpu = sum(len(c) for c in chains), [0], [0.0]
    lock = threading.Lock()

    def run_chain(chain):
        for side, what, cmd, base in chain:
            t0 = time.monotonic()
            rc, seconds = run_one(cmd, base, source)
            with lock:
                done[0] += 1
                cpu[0] += seconds
                print(f"check_same_outputs: [{done[0]}/{total}] {side} {what}: exit {rc}, "
                      f"{time.monotonic() - t0:.0f} s, {seconds:.0f} s CPU", file=sys.stderr,
                      flush=True)

    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as pool:
        for f in [pool.submit(run_chain, c) for c in chains]:
            f.result()
    n_files, diffs = compare_trees(sides["before"][1], sides["after"][1], plan, off)
    elapsed = time.monotonic() - start
    took = f"{elapsed:.0f} s, {cpu[0]:.0f} s CPU"
    for d in diffs:
        print(d)
    if diffs:
        print(f"{len(diffs)} of {n_files} files differ over {n_lines} command lines "
              f"({took}); outputs in {out}")
        return 1
    print(f"{n_files} files identical over {n_lines} command lines ({took})")
    if not a.out:
        shutil.rmtree(out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
