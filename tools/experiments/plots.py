"""Plots of the experiment scripts (matplotlib, Agg backend), sized for a two-column paper: one
column (3.5 in) or both (7.16 in) wide, 7 pt type, PNG at 300 dpi and, on request, vector PDF and
SVG with the fonts embedded as TrueType (the Type 3 fonts matplotlib embeds by default are refused
by IEEE's checks)."""
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import sweeplib  # noqa: E402

DPI = 300
COLUMN_IN, PAGE_IN = 3.5, 7.16  # widths of one column and of both [in]
FORMATS = ["png"]  # set_formats(): the files each plot is written as
FORMAT_NAMES = ("png", "pdf", "svg")
plt.rcParams.update({"font.size": 7, "axes.titlesize": 7, "axes.labelsize": 7, "legend.fontsize": 6,
                     "xtick.labelsize": 6, "ytick.labelsize": 6, "lines.linewidth": 1.0,
                     "pdf.fonttype": 42, "ps.fonttype": 42, "svg.fonttype": "none",
                     "font.family": "DejaVu Sans"})


def set_formats(formats):
    """The formats every plot is written in (png, pdf, svg; each once, at least one)."""
    bad = [f for f in formats if f not in FORMAT_NAMES]
    if bad or not formats or len(set(formats)) != len(formats):
        raise ValueError(f"figure formats {','.join(formats)}: give png, pdf or svg, each once")
    FORMATS[:] = list(formats)


def parse_formats(text):
    return [f.strip() for f in text.replace(",", " ").split() if f.strip()]


def _color(name, i):
    return "black" if name.startswith("none") else f"C{i % 10}"


def _save(fig, path):
    """Writes `path` (named .png) in every format of FORMATS; returns the file the report shows
    (the PNG when there is one)."""
    fig.tight_layout()
    stem = os.path.splitext(path)[0]
    written = []
    for fmt in FORMATS:
        out = stem + "." + fmt
        tmp = out + ".tmp"
        fig.savefig(tmp, dpi=DPI, format=fmt)
        os.replace(tmp, out)
        written.append(out)
    plt.close(fig)
    return stem + ".png" if "png" in FORMATS else written[0]


def binned(x, y, bins, fn=np.median):
    """fn of y over `bins` consecutive blocks of equal size; returns (x at block centres, values)."""
    n = len(y)
    if n <= bins:
        return x, y
    edges = np.linspace(0, n, bins + 1).astype(int)
    xs = np.array([x[(a + b) // 2] for a, b in zip(edges[:-1], edges[1:])])
    return xs, np.array([fn(y[a:b]) for a, b in zip(edges[:-1], edges[1:])])


def cap_positions(caps, landmarks):
    """Where each cap goes on a numeric axis: its number of landmarks (a percentage cap: the number
    it resolved to, `landmarks[cap]`); `none` to the right of the largest. Returns (x, labels)."""
    x, labels = [], []
    for c in caps:
        n = landmarks.get(c)
        if c == "none":
            x.append(None)
            labels.append("none")
        elif c.endswith("%"):
            x.append(n)
            labels.append(c if n is None else f"{c}\n(={n:.0f})")
        else:
            x.append(float(c))
            labels.append(c)
    known = [v for v in x if v is not None]
    top = max(known) if known else 1.0
    span = (top - min(known)) if len(known) > 1 else top
    x = [top + max(0.15 * span, 1.0) if v is None else v for v in x]
    return np.array(x, dtype=float), labels


def error_vs_cap(path, title, caps, series, metrics, cap_landmarks=None):
    """series: {reducer: {metric: [(mean, std) per cap]}}; metrics: [(metric, axis label)];
    cap_landmarks: {cap: number of landmarks} (percentage caps resolved), so that the caps sit on a
    numeric axis at their number of landmarks."""
    fig, axes = plt.subplots(1, len(metrics), figsize=(PAGE_IN if len(metrics) > 1 else COLUMN_IN, 2.4),
                             squeeze=False)
    x, labels = cap_positions(caps, cap_landmarks or {})
    order = np.argsort(x, kind="stable")
    for ax, (metric, label) in zip(axes[0], metrics):
        for i, (reducer, by_metric) in enumerate(series.items()):
            vals = by_metric.get(metric)
            if not vals or all(v is None for v in vals):
                continue
            m = np.array([np.nan if v is None else v[0] for v in vals])[order]
            s = np.array([np.nan if v is None else v[1] for v in vals])[order]
            style = dict(color=_color(reducer, i), label=reducer)
            if reducer.startswith("none"):
                ax.plot(x[order], m, "--", **style)
            else:
                ax.errorbar(x[order], m, yerr=s, marker="o", ms=2.5, capsize=1.5, **style)
        ax.set_xticks(x[order])
        ax.set_xticklabels([labels[k] for k in order])
        ax.set_xlabel("cap [landmarks]")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[0][0].legend()
    fig.suptitle(title, fontsize=7)
    return _save(fig, path)


def landmarks_over_time(path, title, runs):
    """runs: [(name, run folder)]."""
    fig, ax = plt.subplots(figsize=(COLUMN_IN, 2.4))
    for i, (name, folder) in enumerate(runs):
        s = sweeplib.read_steps(folder)
        # Widest first, each next narrower: runs at the cap lie on one another and all show.
        ax.plot(s["step"], s["n_landmarks"], lw=max(0.8, 2.8 - 0.4 * i), color=_color(name, i), label=name,
                ls="--" if name.startswith("none") else "-", zorder=10 if name.startswith("none") else 2 + i)
    ax.set_xlabel("step")
    ax.set_ylabel("landmarks in the map")
    ax.grid(alpha=0.3)
    ax.legend()
    ax.set_title(title)
    return _save(fig, path)


def error_over_time(path, title, runs):
    """Like Hochdorfer & Schlegel's Fig. 8: position error against ground truth with the filter's
    2-sigma band, 2*sqrt(var_x + var_y) from steps.csv; one panel a run. None without ground truth."""
    data = [(n, sweeplib.position_error(f)) for n, f in runs]
    data = [(n, d) for n, d in data if d is not None]
    if not data:
        return None
    fig, axes = plt.subplots(len(data), 1, figsize=(COLUMN_IN, 1.0 + 0.8 * len(data)), sharex=True, sharey=True,
                             squeeze=False)
    for i, (ax, (name, (step, err, sigma))) in enumerate(zip(axes[:, 0], data)):
        ax.fill_between(step, 0, 2 * sigma, color="C1", alpha=0.35, lw=0, label="2σ")
        ax.plot(step, err, lw=0.8, color=_color(name, i), label="|error|")
        ax.set_ylabel(name)
        ax.grid(alpha=0.3)

    axes[0, 0].legend(loc="upper left")
    axes[-1, 0].set_xlabel("step")
    axes[0, 0].set_title(title + "\nposition error vs ground truth [m], band 2·sqrt(var_x+var_y)")
    return _save(fig, path)


def step_time_over_time(path, title, runs, bins=100):
    fig, ax = plt.subplots(figsize=(COLUMN_IN, 2.4))
    for i, (name, folder) in enumerate(runs):
        s = sweeplib.read_steps(folder)
        ax.plot(*binned(s["step"], s["step_ms"], bins), lw=1, color=_color(name, i), label=name)
    ax.set_xlabel("step")
    ax.set_ylabel(f"time per step [ms]\n(median of {bins} blocks)")
    ax.set_yscale("log")
    ax.grid(alpha=0.3, which="both")
    ax.legend()
    ax.set_title(title)
    return _save(fig, path)
