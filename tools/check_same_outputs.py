#!/usr/bin/python3
"""Check that two `budget-slam compare` folders hold the same results.

    tools/check_same_outputs.py BEFORE_DIR AFTER_DIR

Compares comparison.csv and, for every run folder listed in it, landmarks.csv and steps.csv,
byte for byte after dropping the columns that measure the machine rather than the estimate
(wall and CPU time, resident memory). A refactoring that must not change behaviour passes this
check on every shipped rawlog. Exit code 0 when everything matches, 1 with one line per
difference otherwise, 2 on bad arguments or a missing file.
"""
import csv
import io
import os
import sys

# Columns whose values depend on the machine and its load, not on the run's arithmetic.
MACHINE_COLUMNS = {"time_s", "step_ms", "step_cpu_ms", "rss_bytes"}


def stripped(path):
    """The CSV at `path` with the machine columns removed, as text."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        return ""
    keep = [i for i, name in enumerate(rows[0]) if name not in MACHINE_COLUMNS]
    out = io.StringIO()
    w = csv.writer(out, lineterminator="\n")
    for row in rows:
        w.writerow([row[i] for i in keep if i < len(row)])
    return out.getvalue()


def first_difference(a, b):
    for n, (la, lb) in enumerate(zip(a.splitlines(), b.splitlines()), start=1):
        if la != lb:
            return f"line {n}: {la!r} != {lb!r}"
    return f"{len(a.splitlines())} lines != {len(b.splitlines())} lines"


def run_folders(comparison_csv):
    with open(comparison_csv, newline="") as f:
        return [row["run"] for row in csv.DictReader(f)]


def main(argv):
    if len(argv) != 3:
        print("usage: check_same_outputs.py BEFORE_DIR AFTER_DIR", file=sys.stderr)
        return 2
    before, after = argv[1], argv[2]
    files = ["comparison.csv"]
    try:
        for run in run_folders(os.path.join(before, "comparison.csv")):
            files += [os.path.join(run, "landmarks.csv"), os.path.join(run, "steps.csv")]
        differences = []
        for rel in files:
            a = stripped(os.path.join(before, rel))
            b = stripped(os.path.join(after, rel))
            if a != b:
                differences.append(f"{rel}: {first_difference(a, b)}")
    except (OSError, KeyError) as e:
        print(f"check_same_outputs: {e}", file=sys.stderr)
        return 2
    for d in differences:
        print(d)
    print(f"{len(files)} files compared, {len(differences)} differ")
    return 1 if differences else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
