"""What the experiments on worlds with ground truth share (changing_world, life): reading the
ground-truth files budget-simulate and budget-convert write, a map's rigid alignment to the truth,
and running one binary with its output in a log file.
"""
import csv
import math
import shlex
import subprocess

MATCH_RADIUS_M = 0.5


def read_truth(path):
    """{id: (x, y)} of a ground-truth landmarks file (x y in columns 0-1, id in column 6)."""
    out = {}
    with open(path) as f:
        for line in f:
            c = line.split()
            if len(c) >= 7 and not line.startswith("%"):
                out[int(float(c[6]))] = (float(c[0]), float(c[1]))
    return out


def read_path(path):
    """Rows (x, y, yaw) of a ground-truth robot path (`x y z yaw pitch roll`, `%` comments): row 0
    is the pose before the first step, row k + 1 the pose after step k."""
    rows = []
    with open(path) as f:
        for line in f:
            c = line.split()
            if len(c) >= 4 and not line.startswith("%"):
                rows.append((float(c[0]), float(c[1]), float(c[3])))
    return rows


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def rigid_fit(src, dst):
    """(R, t) minimizing sum |R src_i + t - dst_i|^2 (Kabsch, 2D); src, dst: n x 2 arrays."""
    import numpy as np
    cs, cd = src.mean(axis=0), dst.mean(axis=0)
    u, _, vt = np.linalg.svd((src - cs).T @ (dst - cd))
    d = np.sign(np.linalg.det(vt.T @ u.T))
    r = vt.T @ np.diag([1.0, d]) @ u.T
    return r, cd - r @ cs


def align_map(kept, truth, radius=MATCH_RADIUS_M):
    """The rigid alignment of a map (rows of landmarks.csv) to the truth ({id: (x, y)}), fitted on
    the common ids, then again on those within 3 x radius of the truth (a landmark that moved since
    it was mapped is left out of the second fit). Returns (R, t, errors of the common landmarks,
    their rows), or None with fewer than two common ids."""
    import numpy as np
    common = [r for r in kept if int(r["id"]) in truth]
    if len(common) < 2:
        return None
    est = np.array([[float(r["x"]), float(r["y"])] for r in common])
    tru = np.array([truth[int(r["id"])] for r in common])
    rot, t = rigid_fit(est, tru)
    err = np.linalg.norm(est @ rot.T + t - tru, axis=1)
    inliers = err <= 3 * radius
    if 2 <= inliers.sum() < len(common):
        rot, t = rigid_fit(est[inliers], tru[inliers])
        err = np.linalg.norm(est @ rot.T + t - tru, axis=1)
    return rot, t, err, common


def existing(kept, truth, radius=MATCH_RADIUS_M):
    """Kept landmarks (rows of landmarks.csv) whose id the truth has within `radius` of the
    estimate after align_map (the drift of the map is not what is measured, a landmark that moved
    1 m is)."""
    import numpy as np
    common = [r for r in kept if int(r["id"]) in truth]
    if not common:
        return 0
    fit = align_map(kept, truth, radius)
    if fit is None:
        est = np.array([[float(r["x"]), float(r["y"])] for r in common])
        err = np.linalg.norm(est - np.array([truth[int(r["id"])] for r in common]), axis=1)
    else:
        err = fit[2]
    return int((err <= radius).sum())


def pose_to_map(rot, t, pose):
    """A truth pose (x, y, yaw) in the map's frame, for the alignment map -> truth (rot, t)."""
    import numpy as np
    p = rot.T @ (np.array(pose[:2]) - t)
    return float(p[0]), float(p[1]), pose[2] - math.atan2(rot[1, 0], rot[0, 0])


def write_tum(path, rows):
    """A TUM trajectory file from (t, x, y, yaw) rows (z, qx, qy = 0)."""
    with open(path, "w") as f:
        for t, x, y, yaw in rows:
            f.write(f"{t:.9f} {x:.9f} {y:.9f} 0 0 0 {math.sin(yaw / 2):.12f} {math.cos(yaw / 2):.12f}\n")


def run_logged(cmd, log_file, what):
    """Runs cmd with its output in log_file (the command line first); a failure ends the script
    with one line naming the command and the log."""
    rc = call_logged(cmd, log_file)
    if rc != 0:
        raise SystemExit(f"{what}: '{shlex.join(cmd)}' failed (exit {rc}); see {log_file}")


def call_logged(cmd, log_file):
    """Runs cmd with its output in log_file (the command line first); returns the exit code."""
    with open(log_file, "w") as lf:
        lf.write(shlex.join(cmd) + "\n")
        lf.flush()
        return subprocess.call(cmd, stdout=lf, stderr=subprocess.STDOUT)
