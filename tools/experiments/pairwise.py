"""Pairwise reducer comparisons of a sweep's tidy results (results.csv rows), paired by seed: for
each rawlog, backend, cap and metric, every two runs of the block (the unreduced `none` included)
compared with paired_stats. Written as OUT/pairwise.csv and as tables in report.md.
"""
import csv
import os
from collections import OrderedDict, defaultdict

import paired_stats

COLUMNS = ["rawlog", "backend", "cap", "metric", "reducer_a", "reducer_b", "n_pairs", "median_diff", "ci_low",
           "ci_high", "p_value", "significant"]
GROUND_TRUTH_METRIC = "gt_trajectory_rmse_aligned_m"
UNREDUCED_METRIC = "ref_ate_m"


def samples(rows):
    """{(rawlog, backend, reducer, cap, metric): {seed: value}} of the runs whose status is ok."""
    ok = {(r["rawlog"], r["backend"], r["reducer"], r["cap"], int(r["seed"]))
          for r in rows if r["metric"] == "status_ok" and float(r["value"]) == 1.0}
    out = defaultdict(dict)
    for r in rows:
        run = (r["rawlog"], r["backend"], r["reducer"], r["cap"], int(r["seed"]))
        if run in ok and r["metric"] != "status_ok":
            out[run[:4] + (r["metric"],)][run[4]] = float(r["value"])
    return out


def main_metric(smp, rawlog, backend):
    """The error a block is judged by: the aligned trajectory RMSE against ground truth where the
    rawlog has ground truth, else the ATE against the unreduced run."""
    has_gt = any(k[0] == rawlog and k[1] == backend and k[4] == GROUND_TRUTH_METRIC and v for k, v in smp.items())
    return GROUND_TRUTH_METRIC if has_gt else UNREDUCED_METRIC


def compare_block(smp, rawlog, backend, cap, metric, reducers):
    """[(reducer_a, reducer_b, Comparison)] for every two reducers that have values of the metric,
    a before b in the given order."""
    have = [r for r in reducers if smp.get((rawlog, backend, r, cap, metric))]
    out = []
    for i, a in enumerate(have):
        for b in have[i + 1:]:
            out.append((a, b, paired_stats.compare(smp[(rawlog, backend, a, cap, metric)],
                                                   smp[(rawlog, backend, b, cap, metric)])))
    return out


def pairwise_rows(rows, blocks, extra_metrics=()):
    """Tidy rows (COLUMNS) of every comparison. blocks: {(rawlog, backend): {"caps": [...],
    "reducers": [...]}} in report order; each block gets its main metric, then extra_metrics."""
    smp = samples(rows)
    out = []
    for (rawlog, backend), b in blocks.items():
        metrics = list(OrderedDict.fromkeys([main_metric(smp, rawlog, backend)] + list(extra_metrics)))
        for metric in metrics:
            for cap in b["caps"]:
                for ra, rb, c in compare_block(smp, rawlog, backend, cap, metric, b["reducers"]):
                    out.append(dict(rawlog=rawlog, backend=backend, cap=cap, metric=metric, reducer_a=ra,
                                    reducer_b=rb, n_pairs=c.n_pairs, median_diff=c.median_diff, ci_low=c.ci_low,
                                    ci_high=c.ci_high, p_value=c.p_value, significant=int(c.significant),
                                    lower={"a": ra, "b": rb}.get(c.lower())))
    return out


def _cell(v):
    return "" if v is None else repr(v) if isinstance(v, float) else str(v)


def write_csv(path, rows):
    """pairwise.csv: COLUMNS, empty fields where a value does not exist (no test with one pair)."""
    tmp = path + ".tmp"
    with open(tmp, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(COLUMNS)
        for r in rows:
            w.writerow([_cell(r[c]) for c in COLUMNS])
    os.replace(tmp, path)


def _num(v):
    return "–" if v is None else f"{v:.4g}"


def markdown(rows, rawlog, backend):
    """Markdown tables of one block's comparisons, one a metric."""
    lines = []
    mine = [r for r in rows if r["rawlog"] == rawlog and r["backend"] == backend]
    for metric in OrderedDict.fromkeys(r["metric"] for r in mine):
        lines += [f"**Pairwise, {metric}** (A − B paired by seed; mark only where Wilcoxon p < "
                  f"{paired_stats.ALPHA:g})", "",
                  "| cap | A | B | pairs | median A − B | 95% CI | p | |", "|---|---|---|---:|---:|---|---:|---|"]
        for r in (r for r in mine if r["metric"] == metric):
            ci = "–" if r["ci_low"] is None else f"[{_num(r['ci_low'])}, {_num(r['ci_high'])}]"
            mark = f"**{r['lower']} lower**" if r["lower"] else ""
            lines.append(f"| {r['cap']} | {r['reducer_a']} | {r['reducer_b']} | {r['n_pairs']} | "
                         f"{_num(r['median_diff'])} | {ci} | {paired_stats.fmt_p(r['p_value'])} | {mark} |")
        lines.append("")
    return lines
