#!/usr/bin/python3
"""Waking up place by place, on the map (docs/RESULTS.md "Waking up on a saved map"): the kept
landmarks of a map a `budget-slam run` made (RUN_DIR/landmarks.csv), its mapping path
(RUN_DIR/trajectory.tum), and every start place of `bench_wakeup_places --csv` coloured by what
the wake-up said there: found (within --found-xy m and --found-yaw-deg deg of the truth), found
at a wrong place (beyond that), ambiguous, not found (too few landmarks; too uncertain; other).

    wakeup_map.py --map RUN_DIR --places PLACES.csv --out FIG.png [--title T]
                  [--found-xy 0.25] [--found-yaw-deg 5] [--formats png,pdf,svg]

Prints one line: the count of each class. Reads only; writes FIG (and its other formats) through
a temporary file, never over a file it did not write: an existing FIG is replaced only with
--force."""
import argparse
import csv
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plots  # noqa: E402

plt = plots.plt

# (key, label, colour, marker): drawing order, the rarest and worst last (on top).
CLASSES = [
    ("too_few", "not found: < 2 kept landmarks agree", "0.65", "x"),
    ("too_uncertain", "not found: too uncertain", "tab:orange", "x"),
    ("not_found", "not found: other", "tab:brown", "x"),
    ("ambiguous", "ambiguous", "tab:purple", "s"),
    ("found", "found", "tab:green", "o"),
    ("off", "found, off by more than the bound", "gold", "D"),
    ("wrong", "found at a wrong place (> 4x the bound)", "tab:red", "D"),
]
GROSS = 4  # a found pose beyond GROSS x (found_xy, found_yaw_deg) is at another place
MAX_ROWS = 1_000_000  # a places file longer than this is not one the bench writes


def read_landmarks(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return [(float(r["x"]), float(r["y"])) for r in rows[:MAX_ROWS]]


def read_path(path):
    if not os.path.exists(path):
        return []
    out = []
    with open(path) as f:
        for line in f:
            cells = line.split()
            if len(cells) >= 3 and not line.startswith("#"):
                out.append((float(cells[1]), float(cells[2])))
            if len(out) > MAX_ROWS:
                break
    return out


def save(fig, path):
    """plots._save with the legend outside the axes kept in the picture (bbox tight)."""
    stem = os.path.splitext(path)[0]
    written = []
    for fmt in plots.FORMATS:
        out = stem + "." + fmt
        tmp = out + ".tmp"
        fig.savefig(tmp, dpi=plots.DPI, format=fmt, bbox_inches="tight")
        os.replace(tmp, out)
        written.append(out)
    plt.close(fig)
    return stem + ".png" if "png" in plots.FORMATS else written[0]


def classify(row, found_xy, found_yaw_deg):
    status, reason = row["status"], row["reason"]
    if status == "found":
        exy, eyaw = float(row["error_xy"]), float(row["error_yaw_deg"])
        if exy <= found_xy and eyaw <= found_yaw_deg:
            return "found"
        return "off" if exy <= GROSS * found_xy and eyaw <= GROSS * found_yaw_deg else "wrong"
    if status == "ambiguous":
        return "ambiguous"
    if reason == "too_few_landmarks":
        return "too_few"
    if reason == "too_uncertain":
        return "too_uncertain"
    return "not_found"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--map", required=True, help="the run's output folder")
    ap.add_argument("--places", required=True, help="bench_wakeup_places --csv file")
    ap.add_argument("--out", required=True, help="figure (.png)")
    ap.add_argument("--title", default="")
    ap.add_argument("--found-xy", type=float, default=0.25)
    ap.add_argument("--found-yaw-deg", type=float, default=5.0)
    ap.add_argument("--formats", default="png")
    ap.add_argument("--force", action="store_true", help="replace an existing figure")
    a = ap.parse_args()
    if not a.out.endswith(".png"):
        sys.exit(f"wakeup_map.py: --out {a.out}: name the figure .png (other formats follow it)")
    plots.set_formats(plots.parse_formats(a.formats))
    stem = os.path.splitext(a.out)[0]
    for fmt in plots.FORMATS:
        if os.path.exists(stem + "." + fmt) and not a.force:
            sys.exit(f"wakeup_map.py: {stem}.{fmt} exists; give --force to replace it")

    landmarks = read_landmarks(os.path.join(a.map, "landmarks.csv"))
    path = read_path(os.path.join(a.map, "trajectory.tum"))
    with open(a.places, newline="") as f:
        places = list(csv.DictReader(f))[:MAX_ROWS]
    by_class = {k: [] for k, *_ in CLASSES}
    outside = 0  # places outside the mapped area (bench column in_mapped_area = 0): drawn faded
    for r in places:
        inside = r.get("in_mapped_area", "1") != "0"
        outside += not inside
        by_class[classify(r, a.found_xy, a.found_yaw_deg)].append(
            (float(r["x"]), float(r["y"]), inside))

    fig, ax = plt.subplots(figsize=(plots.COLUMN_IN, plots.COLUMN_IN * 0.8))
    if path:
        ax.plot([p[0] for p in path], [p[1] for p in path], color="tab:blue", lw=0.5, alpha=0.6,
                label="mapping path", zorder=1)
    ax.scatter([p[0] for p in landmarks], [p[1] for p in landmarks], marker="^", s=14,
               facecolors="none", edgecolors="black", linewidths=0.6,
               label=f"kept landmarks ({len(landmarks)})", zorder=3)
    n = max(1, len(places))
    for key, label, colour, marker in CLASSES:
        pts = by_class[key]
        if not pts:
            continue
        for inside in (True, False):
            sub = [p for p in pts if p[2] == inside]
            if not sub:
                continue
            ax.scatter([p[0] for p in sub], [p[1] for p in sub], marker=marker, s=7, color=colour,
                       linewidths=0.6, alpha=1.0 if inside else 0.3,
                       label=f"{label}: {len(pts)} ({100 * len(pts) / n:.1f}%)" if inside or
                       len(sub) == len(pts) else None,
                       zorder=4 if key in ("found", "off", "wrong") else 2)
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(a.title or os.path.basename(os.path.normpath(a.map)))
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), ncol=1, frameon=False)
    note = f"found: within {a.found_xy:g} m and {a.found_yaw_deg:g} deg"
    if outside:
        note += f"; faded: {outside} places outside the mapped area"
    ax.set_title(ax.get_title() + f"\n({note})")
    written = save(fig, a.out)
    print(f"{written}: {len(places)} places ({outside} outside the mapped area), "
          + ", ".join(f"{k} {len(by_class[k])}" for k, *_ in CLASSES))


if __name__ == "__main__":
    main()
