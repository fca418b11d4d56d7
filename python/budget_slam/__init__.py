"""budget-slam from Python: runs and comparisons in this process, results as numpy arrays, and any
registered reducer's scores on a Gaussian state (docs/PYTHON.md).

    PYTHONPATH=build/python /usr/bin/python3 -c 'import budget_slam'

    r = budget_slam.run("config.ini", "rawlogs/kf-slam_demo.rawlog", {"LandmarkBudget.seed": 3},
                        reducer="mi", cap=20)
    r["summary"]["counts"]["landmarks_final"], r["steps"]["x"], r["landmarks"]["id"]
    c = budget_slam.compare("config.ini", "rawlogs/kf-slam_demo.rawlog", reducers=["mi", "coverage"])
    c["comparison"]["gt_trajectory_rmse_aligned_m"], c["runs"]["mi"]["trajectory"]
    s = budget_slam.load_state("OUT/states/step_120.txt")
    budget_slam.reducer_scores("mi", s["mean"], s["cov"], s["ids"])["scores"]
    budget_slam.register_reducer("py-oldest", Oldest)   # a reducer written in Python

The runs are budget-slam's own (the run layer's runs::run and runs::compare in-process, from a
typed request, not a subprocess): the same options, checks, outputs and numbers as the command
line. A refused argument raises ConfigError, a failed run raises Error, both carrying the
application's one-line message; Ctrl-C ends the run cleanly and raises KeyboardInterrupt.
"""
import csv
import inspect
import json
import math
import numbers
import os
import runpy
import shutil
import tempfile
import warnings

import numpy as np

from . import _core

__all__ = ["run", "compare", "reducer_scores", "reducer_names", "load_state", "read_run", "Error",
           "ConfigError"]

# Columns of budget-slam's CSV files that hold text: they stay str even when every field is empty
# (an evictions.csv without a failed shadow, a relocalization.csv without an error).
_TEXT_COLUMNS = {"reducer", "reason", "shadow_choices", "shadow_errors", "run", "backend", "status",
                 "traversal", "error", "rawlog", "metric"}


class Error(Exception):
    """A run or comparison that failed: str(e) is the application's one-line message.
    `exit_code` is the command line's (1 failed, 2 refused); `outdir` the output folder (its files
    of the steps already done stay readable), or None."""

    def __init__(self, message, exit_code=1, outdir=None):
        super().__init__(message)
        self.exit_code = exit_code
        self.outdir = outdir


class ConfigError(Error, ValueError):
    """A refused argument, option value or name (the command line's exit code 2)."""

    def __init__(self, message, exit_code=2, outdir=None):
        super().__init__(message, exit_code, outdir)


def reducer_names():
    """Names of the registered reducers (`none` is the unreduced run)."""
    return list(_core.reducer_names())


def reducers():
    """Every registered reducer, as `budget-slam --list reducers --json` gives it: a list of dicts
    with name, summary and options (each a dict of section, key, default as ini text, doc)."""
    return _core.registry("reducers")


def backends():
    """Every registered backend, as `budget-slam --list backends --json` gives it (see reducers();
    the default of a key MRPT's kf-slam defines is None)."""
    return _core.registry("backends")


# ---- reading a run's files ----

def _number(text):
    if text == "":
        return math.nan
    return float(text)


def _column(values, name):
    if name not in _TEXT_COLUMNS:
        try:
            if all(v.lstrip("-").isdigit() for v in values):
                return np.array([int(v) for v in values], dtype=np.int64)
            return np.array([_number(v) for v in values], dtype=np.float64)
        except ValueError:
            pass
    return np.array(values, dtype=str)


def read_csv(path):
    """A CSV file of budget-slam as a numpy structured array: integer columns as int64, numbers as
    float64 (an empty field or `nan` as NaN), text as str."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        raise Error(f"{path}: empty file")
    header, body = rows[0], rows[1:]
    for k, r in enumerate(body):
        if len(r) != len(header):
            raise Error(f"{path}: row {k + 1} has {len(r)} fields, the header {len(header)}")
    columns = [_column([r[i] for r in body], name) for i, name in enumerate(header)]
    dtype = [(name, c.dtype if len(body) else (np.str_ if name in _TEXT_COLUMNS else np.float64))
             for name, c in zip(header, columns)]
    out = np.empty(len(body), dtype=dtype)
    for name, c in zip(header, columns):
        if len(body):
            out[name] = c
    return out


def _table(columns):
    """A table the run layer handed back typed (a list of (name, kind, values), kind text, integer
    or number) as a numpy structured array: integer columns int64, numbers float64 (NaN where the
    file's field is empty), text str — a column's type is the table's, not guessed from its
    values."""
    dtypes = {"text": str, "integer": np.int64, "number": np.float64}
    arrays = [(name, np.array(values, dtype=dtypes[kind])) for name, kind, values in columns]
    n = len(arrays[0][1]) if arrays else 0
    out = np.empty(n, dtype=[(name, a.dtype) for name, a in arrays])
    for name, a in arrays:
        out[name] = a
    return out


def read_tum(path):
    """trajectory.tum / ground_truth.tum as a structured array of t [s], x, y [m], yaw [rad]."""
    data = np.loadtxt(path, comments="#", ndmin=2)
    out = np.empty(len(data), dtype=[("t", np.float64), ("x", np.float64), ("y", np.float64),
                                      ("yaw", np.float64)])
    if len(data):
        out["t"], out["x"], out["y"] = data[:, 0], data[:, 1], data[:, 2]
        out["yaw"] = 2 * np.arctan2(data[:, 6], data[:, 7])
        out["yaw"] = (out["yaw"] + np.pi) % (2 * np.pi) - np.pi
    return out


def read_run(folder, summary=None):
    """The outputs of one run folder (docs/OUTPUTS.md) as a dict: summary (dict of summary.json),
    steps, trajectory, ground_truth (or None), landmarks, evictions (structured arrays), outdir.
    summary: the run's summary as the run layer handed it back in memory (run(), localize()),
    instead of its summary.json read back."""
    def opt(name, reader):
        p = os.path.join(folder, name)
        return reader(p) if os.path.isfile(p) else None
    if summary is None:
        with open(os.path.join(folder, "summary.json")) as f:
            summary = json.load(f)
    return {"summary": summary,
            "steps": opt("steps.csv", read_csv),
            "trajectory": opt("trajectory.tum", read_tum),
            "ground_truth": opt("ground_truth.tum", read_tum),
            "landmarks": opt("landmarks.csv", read_csv),
            "evictions": opt("evictions.csv", read_csv),
            "outdir": folder}


# A state dump's bounds: a line of at most 1 MiB (a covariance row of 40,000 numbers) and 1 GiB in
# all (the covariance of about 3,000 landmarks; the largest shipped map holds 576).
_STATE_MAX_LINE = 1 << 20
_STATE_MAX_BYTES = 1 << 30


def _bounded_lines(path):
    """The lines of a text file, read with a bound on each line and on their bytes (a device
    such as /dev/zero, or a file that is no dump, is an Error of one line, never a MemoryError)."""
    lines = []
    total = 0
    try:
        with open(path, "rb") as f:
            while True:
                line = f.readline(_STATE_MAX_LINE + 1)
                if not line:
                    break
                if len(line) > _STATE_MAX_LINE:
                    raise Error(f"{path}: line {len(lines) + 1} is longer than {_STATE_MAX_LINE} "
                                "bytes: not a state dump of budget-slam")
                total += len(line)
                if total > _STATE_MAX_BYTES:
                    raise Error(f"{path}: larger than {_STATE_MAX_BYTES} bytes: not a state dump "
                                "of budget-slam")
                lines.append(line.decode("utf-8").rstrip("\r\n"))
    except UnicodeDecodeError:
        raise Error(f"{path}: line {len(lines) + 1} is not UTF-8 text: not a state dump of "
                    "budget-slam") from None
    except OSError as e:
        raise Error(f"{path}: {e.strerror or e}") from None
    return lines


def load_state(path):
    """states/step_<k>.txt (written with [LandmarkBudget] dump_states = true) as a dict: step,
    backend, ids (int64), mean (robot x, y, yaw then x, y of each landmark), cov."""
    lines = _bounded_lines(path)
    try:
        head = lines[0].split()
        step = int(head[head.index("step") + 1])
        backend = lines[0].rsplit("backend ", 1)[1].rstrip(")")
        ids_line = next(l for l in lines if l.startswith("# ids:"))
        ids = np.array([int(v) for v in ids_line[len("# ids:"):].split()], dtype=np.int64)
        mean = np.array(lines[lines.index("# mean") + 1].split(), dtype=np.float64)
        start = lines.index("# covariance") + 1
        cov = np.array([l.split() for l in lines[start:start + len(mean)]], dtype=np.float64)
    except (ValueError, IndexError, StopIteration) as e:
        raise Error(f"{path}: not a state dump of budget-slam ({e})") from None
    if mean.shape != (3 + 2 * len(ids),) or cov.shape != (len(mean), len(mean)):
        raise Error(f"{path}: {len(ids)} ids, {len(mean)} mean values, a {cov.shape} covariance")
    return {"step": step, "backend": backend, "ids": ids, "mean": mean, "cov": cov}


# ---- running the application ----

def _ini_text(config):
    """A dict {section: {key: value}} as ini text."""
    lines = []
    for section, keys in config.items():
        if not isinstance(keys, dict):
            raise TypeError(f"config: section '{section}' must map keys to values")
        lines.append(f"[{section}]")
        lines += [f"{k} = {_value(v)}" for k, v in keys.items()]
    return "\n".join(lines) + "\n"


def _value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (list, tuple)):
        return ",".join(_value(x) for x in v)
    return str(v)


def _sets(overrides):
    """{"Section.key": value} or {"Section": {"key": value}} as --set values."""
    if overrides is None:
        return []
    if not isinstance(overrides, dict):
        raise TypeError("overrides: expected a dict like {'LandmarkBudget.seed': 3}")
    sets = []
    for k, v in overrides.items():
        if isinstance(v, dict):
            sets += [f"{k}.{kk}={_value(vv)}" for kk, vv in v.items()]
        else:
            sets.append(f"{k}={_value(v)}")
    return sets


def _cap(cap):
    """cap of run() and compare(): a whole number of landmarks >= 1, or "none" (no cap)."""
    if cap is None:
        return None
    if isinstance(cap, str):
        if cap == "none":
            return "none"
        raise ConfigError(f"cap={cap!r}: a number of landmarks or 'none'")
    if isinstance(cap, bool) or not isinstance(cap, numbers.Integral):
        raise TypeError(f"cap={cap!r}: expected a whole number of landmarks (int) or 'none'")
    return str(int(cap))


def _count(name, value):
    """An argument taking a whole number (max_steps, skip_steps, threads, a seed)."""
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name}={value!r}: expected an int")
    return int(value)


def _invoke(command, config, rawlog, overrides, outdir, force, request, progress=None):
    """Runs `command` (run, compare) through the run layer with the typed request the arguments
    fill (python/src/RunBindings.cpp run_request); returns the output folder, whether it is a
    temporary one, and the typed outcome (its summary in memory)."""
    params = None
    if isinstance(config, dict):
        params = _ini_text(config) if config else "[MappingApplication]\n"
    elif config is not None:
        request["config"] = os.fspath(config)
    else:
        raise TypeError("config: give an ini file path or a dict {section: {key: value}}")
    if rawlog is not None:
        request["rawlog"] = os.fspath(rawlog)
    temporary = outdir is None
    folder = tempfile.mkdtemp(prefix="budget_slam_") if temporary else os.fspath(outdir)
    request.update(outdir=folder, force=bool(force), sets=_sets(overrides))
    try:
        if progress is not None and not callable(progress):
            raise TypeError("progress: expected a callable taking one dict")
        try:
            outcome = _core.run_request(command, request, params, progress)
        except _core.ConfigError as e:
            raise ConfigError(str(e)) from None
        for line in outcome.warnings:
            warnings.warn(line, RuntimeWarning, stacklevel=3)
        if outcome.exit_code == 130:
            raise KeyboardInterrupt(outcome.message or "interrupted")
        if outcome.exit_code != 0:
            kind = ConfigError if outcome.exit_code == 2 else Error
            raise kind(outcome.message or f"exit code {outcome.exit_code}", outcome.exit_code,
                        None if temporary else folder)
        return folder, temporary, outcome
    except BaseException:
        if temporary:
            shutil.rmtree(folder, ignore_errors=True)
        raise


def run(config, rawlog=None, overrides=None, outdir=None, *, reducer=None, cap=None, backend=None,
        max_steps=None, force=False, progress=None, resume=None, skip_steps=None, wake_up=False):
    """`budget-slam run` in this process. config: an ini file path, or a dict
    {section: {key: value}} used as the in-memory ini; rawlog: -i (default: the ini's rawlog_file);
    overrides: {"Section.key": value} or {"Section": {"key": value}} (--set); reducer, backend,
    max_steps: the flags; cap: an int >= 1 or "none". outdir: the output folder (kept; refused if not
    empty unless force), None: a temporary one removed after reading. progress: called with a dict
    (task, fraction, steps_done, steps_total, elapsed_s, steps_per_s, eta_s, detail, finished) at most
    5 times a second and once at the end. Returns read_run() of the folder (outdir None if
    temporary). Raises ConfigError / Error with the application's message, KeyboardInterrupt on
    Ctrl-C, and whatever progress raised (which stops the run as Ctrl-C does).
    resume: a run folder whose session_state.txt this run continues (--resume); skip_steps: leave
    the rawlog's first N steps unread (--skip-steps); wake_up: with resume, find the robot on the
    saved map from its first readings (--wake-up). docs/OUTPUTS.md "Session state"."""
    request = {"cap": _cap(cap), "max_steps": _count("max_steps", max_steps),
               "skip_steps": _count("skip_steps", skip_steps), "wake_up": bool(wake_up)}
    if resume is not None:
        request["resume"] = os.fspath(resume)
    if reducer is not None:
        request["reducer"] = str(reducer)
    if backend is not None:
        request["backend"] = str(backend)
    folder, temporary, outcome = _invoke("run", config, rawlog, overrides, outdir, force, request,
                                         progress)
    try:
        result = read_run(folder, outcome.summary)
    finally:
        if temporary:
            shutil.rmtree(folder, ignore_errors=True)
    if temporary:
        result["outdir"] = None
    return result


def compare(config, rawlog=None, reducers=None, overrides=None, outdir=None, *, cap=None,
            backend=None, threads=0, seeds=None, max_steps=None, force=False, progress=None):
    """`budget-slam compare` in this process: the unreduced reference and each reducer (default:
    all registered) on one rawlog. Same arguments as run(); seeds: --seeds, "A:B" or a list of
    ints (a run a reducer and seed, named "<reducer>/seed<S>"). Returns a dict: summary (the
    comparison's summary.json), comparison (comparison.csv as a structured array), runs
    ({"reference": ..., reducer: ...}, each as run() returns it), outdir. The summaries and the
    table are what the run layer handed back in memory (runs::CompareReport), not its files."""
    request = {"cap": _cap(cap), "max_steps": _count("max_steps", max_steps)}
    if reducers is not None:
        request["reducers"] = [reducers] if isinstance(reducers, str) else [str(r) for r in reducers]
    if backend is not None:
        request["backend"] = str(backend)
    if threads:
        request["threads"] = _count("threads", threads)
    if seeds is not None:
        request["seeds"] = seeds if isinstance(seeds, str) else ",".join(
            str(_count("seeds", x)) for x in seeds)
    folder, temporary, outcome = _invoke("compare", config, rawlog, overrides, outdir, force,
                                         request, progress)
    # The comparison's summary.json, comparison.csv and each run's summary.json as the run layer
    # handed them back in memory; each run's per-step files are read as run() reads them.
    summary = outcome.summary
    table = _table(outcome.comparison)
    try:
        runs = {name: read_run(os.path.join(folder, name), run_summary)
                for name, run_summary in outcome.runs}
    finally:
        if temporary:
            shutil.rmtree(folder, ignore_errors=True)
    if temporary:
        for r in runs.values():
            r["outdir"] = None
    return {"summary": summary, "comparison": table, "runs": runs,
            "outdir": None if temporary else folder}


def reducer_scores(name, mean, cov, ids, *, n_obs=None, obs_mean=None, first_step=None,
                   last_step=None, step=0, seed=1, config=None, candidates=None):
    """Scores a Gaussian state with reducer `name` (any of reducer_names() but `none`).

    mean: robot x, y, yaw then x, y of each landmark (3 + 2N), cov: its (3 + 2N) square
    covariance, ids: the N landmark ids — the layout of states/step_<k>.txt (load_state). What the
    reducers also read, when given: n_obs, obs_mean (N x 2 mean observation positions, for the
    coverage clusters; default: each landmark's own position), first_step (oldest), last_step.
    config: the reducers' ini sections as a dict or ini text (e.g. {"CoverageReducer":
    {"cluster_ratio": 0.5}}); seed: [LandmarkBudget] seed.

    Returns a dict: ids; scores, the score the reducer gives each landmark when it is the only
    candidate (its unit: bits for mi and coverage-mi, 1/m^2 for info-content and coverage, the first
    step for oldest, 0 for random) — the `score` evictions.csv logs for a dropped landmark; choice,
    the landmark it drops among `candidates` (default: all), and choice_score.
    """
    if isinstance(config, dict):
        config = _ini_text(config)
    try:
        return _core.reducer_scores(
            name, np.asarray(mean, dtype=np.float64), np.asarray(cov, dtype=np.float64),
            [int(i) for i in ids], None if n_obs is None else [int(v) for v in n_obs],
            None if obs_mean is None else np.asarray(obs_mean, dtype=np.float64),
            None if first_step is None else [int(v) for v in first_step],
            None if last_step is None else [int(v) for v in last_step], int(step), int(seed),
            config or "", None if candidates is None else [int(c) for c in candidates])
    except (_core.ConfigError, _core.Error) as e:
        raise ConfigError(str(e)) from None


# ---- localize: the run layer's runs::localize, called with a typed specification ----

class NotFound(Error):
    """localize() woke up on the map (wake_up=True, or no start pose to be had) and found the robot
    nowhere: str(e) is the command line's one line ("wake-up: the robot was not found ..."),
    `exit_code` 3, `outdir` the output folder (None if temporary) and `summary` its summary.json
    (status not_found, its wake_up block saying why)."""

    def __init__(self, message, exit_code=3, outdir=None, summary=None):
        super().__init__(message, exit_code, outdir)
        self.summary = summary


def _start_pose_text(start_pose):
    """start_pose as --start-pose text: "x,y,yaw" as given, or (x, y, yaw_deg) numbers."""
    if start_pose is None or isinstance(start_pose, str):
        return start_pose
    try:
        values = list(start_pose)
    except TypeError:
        values = None
    if values is None or len(values) != 3 or not all(
            isinstance(v, numbers.Real) and not isinstance(v, bool) for v in values):
        raise TypeError(f"start_pose={start_pose!r}: expected (x, y, yaw_deg) numbers or 'x,y,yaw'")
    return ",".join(repr(float(v)) for v in values)  # repr: the shortest text of the same double


def localize(config, rawlog=None, map=None, overrides=None, outdir=None, *, start_pose=None,
             wake_up=False, reference_trajectory=None, max_steps=None, force=False, progress=None):
    """`budget-slam localize` in this process, through the run layer (runs::localize; no command
    line): rawlog (-i, default the ini's rawlog_file) localized in the final map of the run folder
    `map` (--map). config, overrides, outdir, force, progress: as run(). start_pose: (x, y,
    yaw_deg) in the map's frame or "x,y,yaw" (--start-pose); wake_up: find the robot on the map
    from the first steps' readings (--wake-up); reference_trajectory: a trajectory.tum to measure
    a traversal without ground truth against; max_steps: the first N steps (0: all).

    Returns read_run() of the folder (summary, steps, trajectory, ground_truth, landmarks; no
    evictions) plus reference (reference.tum, or None). Raises ConfigError with the command line's
    text for what it refuses (exit code 2), Error for a failed localization (exit code 1: a bad
    value, an unreadable map folder or rawlog), NotFound when the wake-up found the robot nowhere
    (exit code 3), KeyboardInterrupt on Ctrl-C, and whatever progress raised."""
    if map is None:
        raise TypeError("map: give the output folder of the run whose map is used")
    params, path = None, None
    if isinstance(config, dict):
        params = _ini_text(config) if config else "[MappingApplication]\n"
    elif config is not None:
        path = os.fspath(config)
    else:
        raise TypeError("config: give an ini file path or a dict {section: {key: value}}")
    if progress is not None and not callable(progress):
        raise TypeError("progress: expected a callable taking one dict")
    pose = _start_pose_text(start_pose)
    steps = _count("max_steps", max_steps)
    sets = _sets(overrides)
    temporary = outdir is None
    folder = tempfile.mkdtemp(prefix="budget_slam_") if temporary else os.fspath(outdir)
    try:
        try:
            r = _core.localize(path, params, None if rawlog is None else os.fspath(rawlog),
                               os.fspath(map), folder, sets, pose, bool(wake_up),
                               None if reference_trajectory is None else os.fspath(reference_trajectory),
                               None if steps is None else str(steps), bool(force), progress)
        except _core.ConfigError as e:
            raise ConfigError(str(e)) from None
        for line in r["warnings"]:  # what the CLI warns of on stderr
            warnings.warn(line, RuntimeWarning, stacklevel=2)
        kept = None if temporary else folder
        if r["status"] == "interrupted":
            raise KeyboardInterrupt(r["line"] or "interrupted")
        if r["status"] == "not_found":
            raise NotFound(r["line"], r["exit_code"], kept, r["summary"])
        if r["status"] != "ok" or r["line"]:
            kind = ConfigError if r["exit_code"] == 2 else Error
            raise kind(r["line"] or f"exit code {r['exit_code']}", r["exit_code"], kept)
        result = read_run(folder, r["summary"])
        ref = os.path.join(folder, "reference.tum")
        result["reference"] = read_tum(ref) if os.path.isfile(ref) else None
    finally:
        if temporary:
            shutil.rmtree(folder, ignore_errors=True)
    if temporary:
        result["outdir"] = None
    return result


__all__ += ["localize", "NotFound"]


# ---- reducers written in Python (docs/PYTHON.md "A reducer in Python") ----

class _FunctionReducer:
    """A plain function registered as a reducer: its choose()."""

    def __init__(self, choose):
        self.choose = choose


def _origin(obj):
    """Where `obj` is defined, for error lines: its file's name, else its module's."""
    try:
        path = inspect.getsourcefile(obj) or inspect.getfile(obj)
        return os.path.basename(path)
    except (TypeError, OSError):
        return getattr(obj, "__module__", None) or type(obj).__name__


def _section_name(name):
    """The default ini section of reducer `name`: "distinct-places" -> "DistinctPlacesReducer"."""
    words = "".join(c if c.isalnum() else " " for c in name).split()
    return "".join(w[:1].upper() + w[1:] for w in words) + "Reducer"


def _option_spec(key, spec):
    """An entry of register_reducer's options as (key, kind, default text, choices, lo, hi, doc):
    a bool, int, float or str default; a tuple of words (a choice, the first the default); or
    (default, lo, hi) or (default, lo, hi, doc) for a number with its range."""
    if not isinstance(key, str) or not key or any(c in key for c in " \t=[]#;"):
        raise ConfigError(f"register_reducer: option key {key!r}: a word of the ini")
    lo, hi, doc, choices = -math.inf, math.inf, "", []
    if isinstance(spec, tuple) and spec and all(isinstance(w, str) for w in spec):
        choices = list(spec)
        return (key, "choice", choices[0], choices, lo, hi, doc)
    if isinstance(spec, tuple):
        if len(spec) not in (3, 4) or (len(spec) == 4 and not isinstance(spec[3], str)):
            raise ConfigError(f"register_reducer: option {key}={spec!r}: a tuple is either words "
                              "(a choice) or (default, lo, hi[, doc])")
        spec, lo, hi, doc = (spec + ("",))[:4]
        if not all(isinstance(v, numbers.Real) and not isinstance(v, bool) for v in (spec, lo, hi)):
            raise ConfigError(f"register_reducer: option {key}: (default, lo, hi) must be numbers")
        if not lo <= spec <= hi:
            raise ConfigError(f"register_reducer: option {key}: the default {spec!r} is not within "
                              f"[{lo!r}, {hi!r}]")
    if isinstance(spec, bool):
        return (key, "bool", "true" if spec else "false", [], lo, hi, doc)
    if isinstance(spec, numbers.Integral):
        return (key, "int", str(int(spec)), [], float(lo), float(hi), doc)
    if isinstance(spec, numbers.Real):
        if not math.isfinite(spec):
            raise ConfigError(f"register_reducer: option {key}={spec!r}: not a finite number")
        return (key, "float", repr(float(spec)), [], float(lo), float(hi), doc)
    if isinstance(spec, str):
        return (key, "text", spec, [], lo, hi, doc)
    raise ConfigError(f"register_reducer: option {key}={spec!r}: give a bool, int, float or str "
                      "default, a tuple of words, or (default, lo, hi)")


def register_reducer(name, reducer, *, options=None, section=None, summary=None):
    """Registers a reducer written in Python under `name`: from then on run(), compare() (beside
    the shipped reducers), reducer_scores(), reducers() and the ini checks know it as any other
    (the command line: `budget-slam run --plugin FILE.py --reducer NAME`).

    reducer: a class, built once a run with its section's values as keyword arguments, whose
    choose(drop) returns the landmark to drop: an id of drop.candidates["id"] (score 0), a tuple
    (id, score), or one score per candidate, in drop.candidates order (the lowest goes, ties to
    the lowest id); score lower = less useful, logged in evictions.csv. Optional: observe(seen),
    called every step with what the robot observed, and forget(id), called when a landmark leaves
    the map. A plain function is taken as choose (no options, no memory).
    options: {key: default} of its ini section: a bool, int, float or str; a tuple of words (a
    choice, the first the default); or (default, lo, hi[, doc]) for a number with its range.
    section: the ini section (default: "distinct-places" -> [DistinctPlacesReducer]); summary:
    --list's line (default: the docstring's first line). A name stays taken for the life of the
    process. Raises ConfigError for a name or options that cannot be registered."""
    if not isinstance(name, str):
        raise TypeError(f"name={name!r}: expected a str")
    if inspect.isclass(reducer):
        factory = reducer
    elif callable(reducer):
        if options:
            raise ConfigError(f"register_reducer: '{name}': a function takes no options; give a "
                              "class whose constructor takes them as keyword arguments")
        factory = lambda: _FunctionReducer(reducer)  # noqa: E731
    else:
        raise TypeError(f"reducer={reducer!r}: expected a class with choose(drop), or a function")
    if options is not None and not isinstance(options, dict):
        raise TypeError("options: expected a dict {key: default}")
    doc = (inspect.getdoc(reducer) or "").strip().splitlines()
    origin = _origin(reducer)
    line = summary if summary is not None else (doc[0] if doc else "")
    line = line or f"a reducer written in Python ({origin})"
    specs = [_option_spec(k, v) for k, v in (options or {}).items()]
    try:
        _core.register_reducer(name, factory, section or _section_name(name), str(line), origin,
                               specs)
    except (_core.ConfigError, _core.Error) as e:
        raise ConfigError(str(e)) from None


def load_plugin(path):
    """Runs a plugin file, whose register_reducer() calls register its reducers (what
    `budget-slam --plugin FILE.py` does before the command runs)."""
    runpy.run_path(os.fspath(path), run_name="__budget_slam_plugin__")


__all__ += ["register_reducer", "load_plugin"]
