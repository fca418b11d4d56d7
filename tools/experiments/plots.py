"""Plots of the experiment scripts (matplotlib, Agg backend, small PNGs)."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import sweeplib  # noqa: E402

DPI = 80


def _color(name, i):
    return "black" if name.startswith("none") else f"C{i % 10}"


def _save(fig, path):
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    return path


def binned(x, y, bins, fn=np.median):
    """fn of y over `bins` consecutive blocks of equal size; returns (x at block centres, values)."""
    n = len(y)
    if n <= bins:
        return x, y
    edges = np.linspace(0, n, bins + 1).astype(int)
    xs = np.array([x[(a + b) // 2] for a, b in zip(edges[:-1], edges[1:])])
    return xs, np.array([fn(y[a:b]) for a, b in zip(edges[:-1], edges[1:])])


def error_vs_cap(path, title, caps, series, metrics):
    """series: {reducer: {metric: [(mean, std) per cap]}}; metrics: [(metric, axis label)]."""
    fig, axes = plt.subplots(1, len(metrics), figsize=(4.2 * len(metrics), 3.2), squeeze=False)
    x = np.arange(len(caps))
    for ax, (metric, label) in zip(axes[0], metrics):
        for i, (reducer, by_metric) in enumerate(series.items()):
            vals = by_metric.get(metric)
            if not vals or all(v is None for v in vals):
                continue
            m = np.array([np.nan if v is None else v[0] for v in vals])
            s = np.array([np.nan if v is None else v[1] for v in vals])
            style = dict(color=_color(reducer, i), label=reducer)
            if reducer.startswith("none"):
                ax.plot(x, m, "--", **style)
            else:
                ax.errorbar(x, m, yerr=s, marker="o", ms=3, capsize=2, **style)
        ax.set_xticks(x)
        ax.set_xticklabels(caps)
        ax.set_xlabel("cap")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[0][0].legend(fontsize=7)
    fig.suptitle(title, fontsize=9)
    return _save(fig, path)


def landmarks_over_time(path, title, runs):
    """runs: [(name, run folder)]."""
    fig, ax = plt.subplots(figsize=(6, 3.2))
    for i, (name, folder) in enumerate(runs):
        s = sweeplib.read_steps(folder)
        ax.plot(s["step"], s["n_landmarks"], lw=1, color=_color(name, i), label=name)
    ax.set_xlabel("step")
    ax.set_ylabel("landmarks in the map")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    ax.set_title(title, fontsize=9)
    return _save(fig, path)


def error_over_time(path, title, runs):
    """Like Hochdorfer & Schlegel's Fig. 8: position error against ground truth with the filter's
    2-sigma band, 2*sqrt(var_x + var_y) from steps.csv; one panel a run. None without ground truth."""
    data = [(n, sweeplib.position_error(f)) for n, f in runs]
    data = [(n, d) for n, d in data if d is not None]
    if not data:
        return None
    fig, axes = plt.subplots(len(data), 1, figsize=(6, 1.3 + 1.1 * len(data)), sharex=True, sharey=True,
                             squeeze=False)
    for i, (ax, (name, (step, err, sigma))) in enumerate(zip(axes[:, 0], data)):
        ax.fill_between(step, 0, 2 * sigma, color="C1", alpha=0.35, lw=0, label="2σ")
        ax.plot(step, err, lw=0.8, color=_color(name, i), label="|error|")
        ax.set_ylabel(name, fontsize=7)
        ax.grid(alpha=0.3)
        ax.tick_params(labelsize=7)
    axes[0, 0].legend(fontsize=7, loc="upper left")
    axes[-1, 0].set_xlabel("step")
    axes[0, 0].set_title(title + "\nposition error vs ground truth [m], band 2·sqrt(var_x+var_y)", fontsize=8)
    return _save(fig, path)


def step_time_over_time(path, title, runs, bins=100):
    fig, ax = plt.subplots(figsize=(6, 3.2))
    for i, (name, folder) in enumerate(runs):
        s = sweeplib.read_steps(folder)
        ax.plot(*binned(s["step"], s["step_ms"], bins), lw=1, color=_color(name, i), label=name)
    ax.set_xlabel("step")
    ax.set_ylabel(f"time per step [ms]\n(median of {bins} blocks)", fontsize=8)
    ax.set_yscale("log")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)
    ax.set_title(title, fontsize=9)
    return _save(fig, path)
