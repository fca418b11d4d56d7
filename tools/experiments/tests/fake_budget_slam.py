#!/usr/bin/python3
"""A stand-in for budget-slam (and, run as budget-simulate, for budget-simulate) that writes the
files the experiment scripts read, with numbers designed so that the statistics have a known
answer. `value()` is the design; the tests import it to compute what the tables must say.

- `run ... -o DIR`: DIR/summary.json (status ok, 40 landmarks kept by the unreduced run) and a
  one-pose DIR/trajectory.tum.
- `compare ... -o DIR [--relocalize A,B]`: DIR/comparison.csv (the app's columns, the
  relocalization ones included with --relocalize; some fields empty or `nan` as the app writes
  where a metric does not apply), DIR/<run>/summary.json, and with --relocalize
  DIR/relocalization.csv (run, traversal (the file's stem), status, rmse_m, max_m, lost_pct,
  coverage_pct, nees_mean), the app's columns.
- `--list reducers|backends --json`: the reducers of QUALITY and backends ekf and graph, as the
  app lists them; unless FAKE_NO_RELOCALIZE is set in the environment (a budget-slam older than
  --list and compare --relocalize: a bad command line).
- FAKE_REFERENCE_FAILS=<rawlog>:<seed> (e.g. park:7): that compare's unreduced run ends `failed`
  (the EKF diverged, as the real park seed 7 does); its reducers' runs stay ok.
- As budget-simulate (argv[0] ends in budget-simulate): writes the -o rawlog (a stub) and a
  sidecar; `--help` lists --route.
Every command line is appended to $FAKE_LOG when that is set.
"""
import json
import os
import sys
import zlib

# Quality of each reducer's map: lower is a better map (smaller errors, more coverage).
QUALITY = {"none": 0, "coverage": 1, "coverage-mi": 2, "mi": 3, "info-content": 4, "random": 5, "oldest": 5,
           "place-coverage": 6}


def noise(*key):
    """Deterministic noise in [-0.5, 0.5) from the key."""
    return (zlib.crc32(repr(key).encode()) % 10007) / 10007.0 - 0.5


def value(rawlog, reducer, seed, metric):
    """The designed number of a run. `random` and `oldest` are the same map on every seed (a tie
    with p = 1), and so are `coverage` and `coverage-mi` on the lost share; the others differ by
    constant steps plus noise smaller than a step, so every other pair differs on every seed in
    the same direction (p < 0.01 with 20 seeds)."""
    if reducer == "oldest":
        reducer = "random"
    if reducer == "coverage-mi" and metric == "reloc_lost_pct":  # the best lost share is a tie
        reducer = "coverage"
    q = QUALITY[reducer]
    base = 1.0 + len(rawlog) % 3
    e = 0.004 * noise(rawlog, reducer, seed, metric)
    s = 0.01 * seed
    return {
        "gt_trajectory_rmse_aligned_m": base * 0.1 + 0.05 * q + s + e,
        "ref_ate_m": 0.0 if q == 0 else 0.2 * q + s + e,
        "reloc_coverage_pct": 100.0 - 8.0 * q - s + e,
        "reloc_mean_landmarks": 6.0 - 0.5 * q + e,
        "reloc_rmse_m": base * 0.2 + 0.1 * q + s + e,
        "reloc_max_m": base * 0.5 + 0.3 * q + s + e,
        "reloc_lost_pct": 2.0 + 5.0 * q + s + e,
        "reloc_traversal_coverage_pct": 95.0 - 7.0 * q - s + e,
    }[metric]


def ratio(rawlog, reducer, seed, metric):
    return value(rawlog, reducer, seed, metric) / value(rawlog, "none", seed, metric)


def arg(args, name, default=None):
    return args[args.index(name) + 1] if name in args else default


def write(path, text):
    with open(path + ".tmp", "w") as f:
        f.write(text)
    os.replace(path + ".tmp", path)


def simulate(args):
    if "--help" in args:
        print("budget-simulate -o <out.rawlog> [--route <revisit>] [--seed <S>] -s <scenario>")
        return 0
    out = arg(args, "-o")
    os.makedirs(os.path.dirname(out), exist_ok=True)
    write(out, "stub rawlog\n")
    write(out[:-len(".rawlog")] + ".ini", "[sidecar]\n")
    return 0


def list_registry(args):
    if os.environ.get("FAKE_NO_RELOCALIZE") or args[1:] != ["--json"]:
        print("budget-slam: unknown command '--list'", file=sys.stderr)
        return 2
    names = {"reducers": sorted(QUALITY), "backends": ["ekf", "graph"]}[args[0]]
    role = {"none": "reference"} if args[0] == "reducers" else {}
    print(json.dumps([dict({"name": n, "summary": n, "options": []},
                           **({"role": role.get(n, "rule")} if args[0] == "reducers" else {}))
                      for n in names]))
    return 0


def compare(args):
    out, rawlog_file = arg(args, "-o"), arg(args, "-i")
    rawlog = os.path.basename(rawlog_file)[:-len(".rawlog")].split("-seed")[0]
    seed = int(next(s.split("=")[1] for s in args if s.startswith("LandmarkBudget.seed=")))
    reducers = arg(args, "--reducers").split(",")
    traversals = arg(args, "--relocalize", "")
    traversals = [t for t in traversals.split(",") if t]
    # the app writes every reloc_* column; those of --relocalize stay empty without it
    reloc = ["reloc_coverage_pct", "reloc_mean_landmarks", "reloc_rmse_m", "reloc_max_m", "reloc_lost_pct",
             "reloc_traversal_coverage_pct", "reloc_rmse_ratio", "reloc_lost_ratio"]
    header = ["run", "reducer", "backend", "status", "cap", "landmarks", "landmarks_reduction_pct", "poses",
              "poses_reduction_pct", "evictions", "ref_ate_m", "ref_ale_m", "ref_are_deg", "ref_ud_pct", "ref_eig_min", "ref_eig_max",
              "gt_trajectory_rmse_m", "gt_trajectory_max_m", "gt_landmark_rmse_m", "nees_mean", "time_s"] + reloc
    os.makedirs(out, exist_ok=True)
    lines, per_traversal = [",".join(header)], ["run,traversal,status,rmse_m,max_m,lost_pct,coverage_pct,nees_mean"]
    fails = os.environ.get("FAKE_REFERENCE_FAILS", "") == f"{rawlog.removeprefix('sim-')}:{seed}"
    for run, red in [("reference", "none")] + [(r, r) for r in reducers]:
        failed = fails and red == "none"
        row = dict(run=run, reducer=red, backend="ekf", status="failed" if failed else "ok", cap="" if red == "none" else arg(args, "--cap"),
                   landmarks=40 if red == "none" else arg(args, "--cap"), landmarks_reduction_pct=0, poses=1,
                   poses_reduction_pct=0, evictions=0, ref_ate_m=value(rawlog, red, seed, "ref_ate_m"), ref_ale_m="",
                   ref_are_deg="nan", ref_ud_pct="", ref_eig_min="nan", ref_eig_max="nan", gt_trajectory_rmse_m=0.5,
                   gt_trajectory_max_m=1.0, gt_landmark_rmse_m=0.3, nees_mean="", time_s=0.1)
        for m in reloc:
            if not traversals and m not in ("reloc_coverage_pct", "reloc_mean_landmarks"):
                row[m] = ""
            elif m.endswith("_ratio"):
                row[m] = ratio(rawlog, red, seed, m.replace("_ratio", "_m" if "rmse" in m else "_pct"))
            else:
                row[m] = value(rawlog, red, seed, m)
        if failed:  # the app leaves a failed run's metrics empty
            row.update({m: "" for m in reloc + ["ref_ate_m"]})
        lines.append(",".join(str(row[h]) for h in header))
        os.makedirs(os.path.join(out, run), exist_ok=True)
        write(os.path.join(out, run, "summary.json"), json.dumps({
            "status": "failed" if failed else "ok",
            **({"error": "step 12: the ekf estimate diverged"} if failed else {}), "counts": {"steps": 100, "landmarks_final": row["landmarks"]},
            "ground_truth": {"trajectory_rmse_aligned_m": value(rawlog, red, seed, "gt_trajectory_rmse_aligned_m"),
                             "landmark_rmse_aligned_m": None},
            "timings": {"step_ms_mean": 1.0, "step_ms_max": 2.0, "peak_rss_bytes": 1000000}}))
        for t in traversals:  # named by the file's stem, as the app names them
            stem = os.path.basename(t)[:-len(".rawlog")] if t.endswith(".rawlog") else os.path.basename(t)
            per_traversal.append(f"{run},{stem},ok,{value(rawlog, red, seed, 'reloc_rmse_m')},"
                                 f"{value(rawlog, red, seed, 'reloc_max_m')},{value(rawlog, red, seed, 'reloc_lost_pct')},"
                                 f"{value(rawlog, red, seed, 'reloc_traversal_coverage_pct')},")
    if traversals:
        write(os.path.join(out, "relocalization.csv"), "\n".join(per_traversal) + "\n")
    write(os.path.join(out, "comparison.csv"), "\n".join(lines) + "\n")
    return 0


def run(args):
    out = arg(args, "-o")
    os.makedirs(out, exist_ok=True)
    write(os.path.join(out, "summary.json"), json.dumps({"status": "ok", "counts": {"landmarks_final": 40}}))
    write(os.path.join(out, "trajectory.tum"), "1 0 0 0 0 0 0 1\n")
    return 0


def main(args):
    if os.environ.get("FAKE_LOG"):
        with open(os.environ["FAKE_LOG"], "a") as f:
            f.write(" ".join([os.path.basename(sys.argv[0])] + args) + "\n")
    if os.path.basename(sys.argv[0]).endswith("budget-simulate"):
        return simulate(args)
    return {"compare": compare, "run": run, "--list": list_registry}[args[0]](args[1:])


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
