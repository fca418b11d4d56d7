"""Shared code of the experiment scripts (sweep, paper_tables, lifelong).

An experiment file lists rawlogs x backends x reducers x caps x seeds (docs/EXPERIMENTS.md).
One job is one `budget-slam compare` (all reducers of the job share one rawlog parse and one
reference run). Every job writes into `<folder>.part` and renames it to `<folder>` when its
comparison.csv is complete, so a killed sweep re-run does only what is missing.
"""
import configparser
import csv
import fcntl
import json
import math
import os
import re
import shlex
import shutil
import subprocess
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor

from reportlib import write_atomic

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))

GLOBAL_KEYS = {"name", "config", "budget_slam", "budget_simulate", "jobs", "metrics", "figure_format", "plugins"}
GROUP_KEYS = {"rawlogs", "backends", "reducers", "caps", "seeds", "set", "label", "config", "relocalize",
              "reference_trajectory"}


class ExperimentError(Exception):
    pass


class FolderInUse(Exception):
    """The output folder is locked by another process (a sweep or a budget-slam run)."""


LOCK_NAME = ".budget-slam.lock"


class FolderLock:
    """The advisory lock budget-slam takes on an output folder while it writes it
    (modules/report/include/budget_slam/report/FolderLock.h): flock(2) on <folder>/.budget-slam.lock,
    which holds the holder's process id. A second sweep into the same folder, or a budget-slam run
    into it, is refused with one line naming the process. Released (and the file removed) by
    release() or at exit; the kernel releases it when the process ends however it ends."""

    def __init__(self, folder):
        os.makedirs(folder, exist_ok=True)
        self.path = os.path.join(folder, LOCK_NAME)
        self.file = None
        for _ in range(100):
            f = open(self.path, "a+")
            try:
                fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                holder = self._holder(f)
                f.close()
                raise FolderInUse(f"output folder '{folder}' is in use by {holder} (it holds {self.path}); "
                                  "wait for it to end or give another output folder") from None
            try:
                same = os.fstat(f.fileno()).st_ino == os.stat(self.path).st_ino
            except FileNotFoundError:
                same = False
            if same:  # not a file its previous holder removed meanwhile
                f.truncate(0)
                f.write(f"{os.getpid()}\n")
                f.flush()
                self.file = f
                return
            f.close()
        raise FolderInUse(f"output folder '{folder}': cannot lock {self.path}")

    @staticmethod
    def _holder(f):
        for _ in range(50):
            f.seek(0)
            text = f.read().strip()
            if text.isdigit():
                return f"process {text}"
            time.sleep(0.01)
        return "another process"

    def release(self):
        if self.file is not None:
            try:
                os.unlink(self.path)  # while still held: the next holder locks a fresh file
            except OSError:
                pass
            self.file.close()
            self.file = None


def default_binary(name):
    """BUDGET_SLAM / BUDGET_SIMULATE from the environment, else build/bin/<name>."""
    return os.environ.get(name.upper().replace("-", "_")) or os.path.join(ROOT, "build", "bin", name)


def resolve_path(path, base_dirs):
    """A relative path is tried against each base folder in turn (first existing one wins)."""
    if os.path.isabs(path):
        return path
    for base in base_dirs:
        cand = os.path.abspath(os.path.join(base, path))
        if os.path.exists(cand):
            return cand
    return os.path.abspath(os.path.join(base_dirs[0], path))


def split_list(text):
    return [t for t in re.split(r"[,\s]+", text.strip()) if t]


def parse_seeds(text):
    seeds = []
    for item in split_list(text):
        m = re.fullmatch(r"(\d+)(?:-(\d+))?", item)
        if not m:
            raise ExperimentError(f"seeds: '{item}' is not a number or a range like 1-5")
        lo, hi = int(m.group(1)), int(m.group(2) or m.group(1))
        if hi < lo:
            raise ExperimentError(f"seeds: empty range '{item}'")
        seeds.extend(range(lo, hi + 1))
    return seeds


def parse_caps(text):
    caps = []
    for item in split_list(text):
        if not re.fullmatch(r"\d+(\.\d+)?%|\d+|none", item):
            raise ExperimentError(f"caps: '{item}' is neither a number of landmarks, a percentage like 25%, nor none")
        if (item.endswith("%") and not 0 < float(item[:-1]) <= 100) or item == "0":
            raise ExperimentError(f"caps: '{item}' is out of range")
        caps.append(item)
    return caps


def parse_metrics(text, where):
    """Metric names (results.csv's metric column) to compare pairwise besides the main error."""
    metrics = split_list(text)
    for m in metrics:
        if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", m):
            raise ExperimentError(f"{where} metrics: '{m}' is not a metric name like reloc_coverage_pct")
    return metrics


def cap_label(cap):
    return cap[:-1] + "pct" if cap.endswith("%") else cap


def resolve_cap(cap, unreduced_landmarks):
    """'25%' of the landmarks the unreduced run keeps (rounded half up, at least 1); '40' is 40;
    'none' (no cap: mi's objective and incremental modes decide the map size) stays 'none'."""
    if cap == "none":
        return cap
    if not cap.endswith("%"):
        return int(cap)
    return max(1, int(math.floor(float(cap[:-1]) / 100.0 * unreduced_landmarks + 0.5)))


class Rawlog:
    """A shipped rawlog file, or `sim:<scenario>[:laps]` simulated once per seed."""

    def __init__(self, spec, base_dirs):
        self.spec = spec
        if spec.startswith("sim:"):
            parts = spec.split(":")
            if len(parts) not in (2, 3) or not parts[1] or (len(parts) == 3 and not parts[2].isdigit()):
                raise ExperimentError(f"rawlogs: '{spec}' is not sim:<scenario> or sim:<scenario>:<laps>")
            self.scenario = parts[1]
            self.laps = int(parts[2]) if len(parts) == 3 else None
            self.name = "sim-" + self.scenario + (f"-{self.laps}laps" if self.laps else "")
            self.label = spec
            self.path = None
        else:
            self.scenario = None
            self.path = resolve_path(spec, base_dirs)
            if not os.path.isfile(self.path):
                raise ExperimentError(f"rawlogs: '{spec}' not found (looked for {self.path})")
            self.name = re.sub(r"\.rawlog$", "", os.path.basename(self.path))
            self.label = self.name

    @property
    def simulated(self):
        return self.scenario is not None

    def file_for_seed(self, outdir, seed, route=None):
        """The rawlog file of a seed; with a route, the simulation of the same world along that
        route (`budget-simulate --route`), which only a simulated rawlog has."""
        if not self.simulated:
            return self.path
        return os.path.join(outdir, "rawlogs", f"{self.name}{'-' + route if route else ''}-seed{seed}.rawlog")


class Traversal:
    """One entry of a group's `relocalize` key: a rawlog file that every run's final map
    localizes, or `route:<name>`, the group's simulated rawlog simulated again with the job's seed
    along another route (`budget-simulate --route <name>`: same world, another path)."""

    def __init__(self, spec, base_dirs, where):
        self.spec = spec
        m = re.fullmatch(r"route:([A-Za-z0-9_-]+)", spec)
        if m:
            self.route, self.path = m.group(1), None
        elif spec.startswith("route:"):
            raise ExperimentError(f"{where} relocalize: '{spec}' is not route:<name> (letters, digits, _ -)")
        else:
            self.route = None
            self.path = resolve_path(spec, base_dirs)
            if not os.path.isfile(self.path):
                raise ExperimentError(f"{where} relocalize: '{spec}' not found (looked for {self.path})")
            if "," in self.path:
                raise ExperimentError(f"{where} relocalize: '{self.path}' has a comma, which "
                                      "--relocalize takes as a separator")

    def label(self, rawlog):
        """Name of the traversal in the results: the file's stem, or sim:<scenario>[:laps]:<route>."""
        if self.route:
            return f"{rawlog.label}:{self.route}"
        return re.sub(r"\.rawlog$", "", os.path.basename(self.path))

    def file(self, rawlog, outdir, seed):
        return rawlog.file_for_seed(outdir, seed, self.route) if self.route else self.path


class Job:
    """One `budget-slam compare`: a rawlog (file), backend, cap and seed, with all reducers."""

    def __init__(self, group, rawlog, backend, reducers, cap, seed, sets, config, outdir):
        self.group, self.rawlog, self.backend, self.reducers = group, rawlog, backend, reducers
        self.cap, self.seed, self.sets, self.config = cap, seed, sets, config
        self.rawlog_file = rawlog.file_for_seed(outdir, seed)
        # [(label, rawlog file)] that every final map of the job localizes (compare --relocalize)
        self.traversals = [(t.label(rawlog), t.file(rawlog, outdir, seed)) for t in group.get("relocalize", [])]
        self.rel = os.path.join("runs", group["name"], rawlog.name, backend, "cap" + cap_label(cap), f"seed{seed}")
        self.folder = os.path.join(outdir, self.rel)
        self.cap_landmarks = None  # resolved before the job runs
        self.baseline = None       # Baseline needed to resolve a percentage cap

    def reducer_label(self, reducer):
        return f"{reducer}:{self.group['label']}" if self.group.get("label") else reducer


class Baseline:
    """The unreduced run (`budget-slam run --reducer none`) that a percentage cap refers to."""

    def __init__(self, group, rawlog_file, rawlog_name, backend, sets, config, outdir):
        self.rawlog_file, self.backend, self.sets, self.config = rawlog_file, backend, sets, config
        self.folder = os.path.join(outdir, "baselines", group["name"], rawlog_name, backend)

    def landmarks(self):
        with open(os.path.join(self.folder, "summary.json")) as f:
            return int(json.load(f)["counts"]["landmarks_final"])


class Experiment:
    """An experiment file read and expanded into simulations, baselines and jobs."""

    def __init__(self, path, outdir, budget_slam=None, budget_simulate=None):
        self.path = os.path.abspath(path)
        self.outdir = os.path.abspath(outdir)
        ini = configparser.ConfigParser(inline_comment_prefixes=("#", ";"), interpolation=None)
        ini.optionxform = str
        if not ini.read(self.path):
            raise ExperimentError(f"{path}: cannot read")
        if "sweep" not in ini:
            raise ExperimentError(f"{path}: no [sweep] section")
        base_dirs = [os.getcwd(), ROOT, os.path.dirname(self.path)]
        top = ini["sweep"]
        for key in top:
            if key not in GLOBAL_KEYS | GROUP_KEYS:
                raise ExperimentError(f"{path}: [sweep] unknown key '{key}'")
        self.name = top.get("name", os.path.splitext(os.path.basename(path))[0])
        self.budget_slam = os.path.abspath(budget_slam or top.get("budget_slam") and resolve_path(top["budget_slam"], base_dirs) or default_binary("budget-slam"))
        self.budget_simulate = os.path.abspath(budget_simulate or top.get("budget_simulate") and resolve_path(top["budget_simulate"], base_dirs) or default_binary("budget-simulate"))
        self.default_jobs = int(top.get("jobs", "0") or 0)
        # Reducers written in Python (docs/PYTHON.md): every budget-slam command line gets --plugin FILE.
        self.plugins = [resolve_path(f, base_dirs) for f in split_list(top.get("plugins", ""))]
        for f in self.plugins:
            if not os.path.isfile(f):
                raise ExperimentError(f"{path}: [sweep] plugins: no file '{f}'")
        self.plugin_args = [a for f in self.plugins for a in ("--plugin", f)]
        self.metrics = parse_metrics(top.get("metrics", ""), f"{path}: [sweep]")
        self.figure_format = top.get("figure_format", "png")
        group_sections = [s for s in ini.sections() if s.startswith("group ")]
        for s in ini.sections():
            if s != "sweep" and not s.startswith("group "):
                raise ExperimentError(f"{path}: unknown section [{s}] (use [sweep] and [group NAME])")
        self.groups = []
        for sec in group_sections or ["sweep"]:
            g = {k: top[k] for k in top if k in GROUP_KEYS}
            if sec != "sweep":
                for key in ini[sec]:
                    if key not in GROUP_KEYS:
                        raise ExperimentError(f"{path}: [{sec}] unknown key '{key}'")
                g.update(dict(ini[sec]))
                g["name"] = sec.split(None, 1)[1].strip()
            else:
                g["name"] = "main"
            if not re.fullmatch(r"[A-Za-z0-9_.-]+", g["name"]):
                raise ExperimentError(f"{path}: group name '{g['name']}' must be letters, digits, _ . -")
            for key in ("rawlogs", "reducers", "caps"):
                if not g.get(key, "").strip():
                    raise ExperimentError(f"{path}: [{sec}] needs '{key}'")
            g["rawlogs"] = [Rawlog(s, base_dirs) for s in split_list(g["rawlogs"])]
            g["backends"] = split_list(g.get("backends", "ekf"))
            backends = registry_names(self.budget_slam, "backends", self.plugin_args)
            for b in g["backends"] if backends is not None else []:
                if b not in backends:
                    raise ExperimentError(f"{path}: [{sec}] backend '{b}' is not one of {', '.join(backends)}")
            g["reducers"] = [r for r in split_list(g["reducers"]) if r != "none"]
            reducers = registry_names(self.budget_slam, "reducers", self.plugin_args)
            for r in g["reducers"] if reducers is not None else []:
                if r not in reducers:
                    raise ExperimentError(f"{path}: [{sec}] reducer '{r}' is not one of {', '.join(reducers)}")
            g["caps"] = parse_caps(g["caps"])
            g["seeds"] = parse_seeds(g.get("seeds", "1"))
            g["set"] = [s.strip() for s in g.get("set", "").splitlines() if s.strip()]
            for s in g["set"]:
                if not re.fullmatch(r"[A-Za-z_][\w]*\.[\w]+=.*", s):
                    raise ExperimentError(f"{path}: [{sec}] set '{s}' is not Section.key=value")
            g["relocalize"] = [Traversal(s, base_dirs, f"{path}: [{sec}]") for s in split_list(g.get("relocalize", ""))]
            for t in g["relocalize"]:
                for raw in g["rawlogs"] if t.route else []:
                    if not raw.simulated:
                        raise ExperimentError(f"{path}: [{sec}] relocalize '{t.spec}' needs sim: rawlogs, "
                                              f"and '{raw.spec}' is a file (give its traversals as files)")
            # traversals without ground truth are measured against this trajectory (a TUM file)
            ref = g.get("reference_trajectory", "").strip()
            if ref:
                if not g["relocalize"]:
                    raise ExperimentError(f"{path}: [{sec}] reference_trajectory needs 'relocalize'")
                ref = resolve_path(ref, base_dirs)
                if not os.path.isfile(ref):
                    raise ExperimentError(f"{path}: [{sec}] reference_trajectory '{ref}' not found")
                if "," in ref or not ref.strip() == ref:
                    raise ExperimentError(f"{path}: [{sec}] reference_trajectory '{ref}' has a comma or blank")
            g["reference_trajectory"] = ref
            g["config"] = resolve_path(g.get("config", "config.ini"), base_dirs)
            if not os.path.isfile(g["config"]):
                raise ExperimentError(f"{path}: config '{g['config']}' not found")
            self.groups.append(g)
        self._expand()

    def _expand(self):
        self.simulations = {}  # rawlog file -> (Rawlog, seed, route or None)
        self.baselines = {}
        self.jobs = []
        seen = set()
        for g in self.groups:
            for raw in g["rawlogs"]:
                for backend in g["backends"]:
                    for cap in g["caps"]:
                        for seed in g["seeds"]:
                            job = Job(g, raw, backend, g["reducers"], cap, seed, g["set"], g["config"], self.outdir)
                            key = (raw.label, backend, cap, seed, g.get("label", ""))
                            if key in seen:
                                raise ExperimentError(
                                    f"{self.path}: two groups give {raw.label} {backend} cap {cap} seed {seed}; "
                                    "give one of them a label")
                            seen.add(key)
                            if raw.simulated:
                                self.simulations[job.rawlog_file] = (raw, seed, None)
                                for t in g["relocalize"]:
                                    if t.route:
                                        self.simulations[t.file(raw, self.outdir, seed)] = (raw, seed, t.route)
                            if cap.endswith("%"):
                                bkey = (g["name"], job.rawlog_file, backend)
                                if bkey not in self.baselines:
                                    name = raw.name + (f"-seed{seed}" if raw.simulated else "")
                                    self.baselines[bkey] = Baseline(g, job.rawlog_file, name, backend,
                                                                    g["set"], g["config"], self.outdir)
                                job.baseline = self.baselines[bkey]
                            else:
                                job.cap_landmarks = resolve_cap(cap, None)
                            self.jobs.append(job)

    # ---- command lines (the same lines are run here and written to prepare.txt / jobs.txt) ----

    def simulation_command(self, rawlog_file):
        raw, seed, route = self.simulations[rawlog_file]
        return simulation_line(self.budget_simulate, raw.scenario, seed, raw.laps, rawlog_file, route)

    @property
    def relocalizes(self):
        return any(j.traversals for j in self.jobs)

    def baseline_command(self, b):
        cmd = [self.budget_slam, "run", "-c", b.config, "-i", b.rawlog_file, "-o", b.folder + ".part",
               "--reducer", "none", "--backend", b.backend, "--quiet", "--force"] + self.plugin_args
        for s in b.sets:
            cmd += ["--set", s]
        return wrap_atomic(cmd, b.folder, "summary.json")

    def job_command(self, job):
        cmd = [self.budget_slam, "compare", "-c", job.config, "-i", job.rawlog_file, "-o", job.folder + ".part",
               "--reducers", ",".join(job.reducers), "--cap", str(job.cap_landmarks), "--backend", job.backend,
               "--set", f"LandmarkBudget.seed={job.seed}"] + self.plugin_args
        if job.traversals:
            cmd += ["--relocalize", ",".join(f for _, f in job.traversals)]
        if job.group.get("reference_trajectory"):
            cmd += ["--reference-trajectory", job.group["reference_trajectory"]]
        for s in job.sets:
            cmd += ["--set", s]
        cmd += ["--quiet", "--force"]
        return wrap_atomic(cmd, job.folder, "comparison.csv")

    # ---- completeness ----

    def simulation_done(self, rawlog_file):
        return os.path.isfile(rawlog_file)

    @staticmethod
    def baseline_done(b):
        try:
            with open(os.path.join(b.folder, "summary.json")) as f:
                return json.load(f).get("status") in ("ok", "failed")
        except (OSError, ValueError):
            return False

    @staticmethod
    def job_done(job):
        rows = read_comparison(job.folder)
        if rows is None:
            return False
        runs = {r["run"]: r for r in rows}
        needed = ["reference"] + list(job.reducers)
        return all(n in runs and runs[n]["status"] in ("ok", "failed") for n in needed)


def simulation_line(budget_simulate, scenario, seed, laps, rawlog_file, route=None):
    """Shell line: `budget-simulate` into a temporary folder beside rawlog_file, then its files
    (ground truth, sidecar) moved beside rawlog_file, the rawlog last: its presence means the
    simulation is complete."""
    tmp = os.path.join(os.path.dirname(rawlog_file), ".tmp-" + os.path.basename(rawlog_file)[:-len(".rawlog")])
    stem = os.path.basename(rawlog_file)[:-len(".rawlog")]
    cmd = [budget_simulate, "--scenario", scenario, "--seed", str(seed)]
    if laps:
        cmd += ["--laps", str(laps)]
    if route:
        cmd += ["--route", route]
    cmd += ["-o", os.path.join(tmp, stem + ".rawlog")]
    q = shlex.quote
    return (f"rm -rf {q(tmp)} && mkdir -p {q(tmp)} && {shlex.join(cmd)} >/dev/null && "
            f"for f in {q(tmp)}/*; do case \"$f\" in *.rawlog) ;; *) mv -f \"$f\" {q(os.path.dirname(rawlog_file))}/ ;; esac; done && "
            f"mv -f {q(os.path.join(tmp, stem + '.rawlog'))} {q(rawlog_file)} && rmdir {q(tmp)}")


_REGISTRIES = {}


def registry(binary, kind, plugin_args=()):
    """What `binary --list KIND --json` says (KIND: reducers or backends): a list of dicts with
    name, summary and options, from the binary's own registry (the one list of them, with the
    reducers of `plugin_args`' --plugin files); None when the binary cannot list it (not a
    budget-slam, or one older than --list, which also lacks compare --relocalize)."""
    key = (binary, kind, tuple(plugin_args))
    if key not in _REGISTRIES:
        try:
            p = subprocess.run([binary, "--list", kind, "--json", *plugin_args], capture_output=True, text=True,
                               timeout=60)
            _REGISTRIES[key] = json.loads(p.stdout) if p.returncode == 0 else None
        except (OSError, subprocess.TimeoutExpired, ValueError):
            _REGISTRIES[key] = None
    return _REGISTRIES[key]


def registry_names(binary, kind, plugin_args=(), role=None):
    """The names of registry(binary, kind, plugin_args), or None; with `role`, only the reducers
    listed with that role ("rule": the candidates of an experiment; "reference": none; "bound":
    the instruments of the benchmark's bounds; core/ReducerRegistry.h, ReducerRole)."""
    entries = registry(binary, kind, plugin_args)
    if not isinstance(entries, list):
        return None
    return [e["name"] for e in entries if role is None or e.get("role") == role]


def help_mentions(binary, args, option):
    """Whether `binary args --help` lists the option (an older build lacks newer options)."""
    try:
        p = subprocess.run([binary] + args + ["--help"], capture_output=True, text=True, timeout=60)
    except (OSError, subprocess.TimeoutExpired):
        return False
    return option in p.stdout + p.stderr


def check_relocalization_support(exp):
    """One clear line when the experiment relocalizes and the binaries cannot."""
    if not exp.relocalizes:
        return
    if registry_names(exp.budget_slam, "reducers") is None:
        raise ExperimentError(f"{exp.budget_slam}: this budget-slam has no 'compare --relocalize', which the "
                              "experiment's relocalize key needs (build a budget-slam with relocalization)")
    if any(route for _, _, route in exp.simulations.values()) and \
            not help_mentions(exp.budget_simulate, [], "--route"):
        raise ExperimentError(f"{exp.budget_simulate}: this budget-simulate has no '--route', which a "
                              "relocalize route:<name> needs (build a budget-simulate with routes)")


def wrap_atomic(cmd, folder, marker):
    """Shell line: run cmd into <folder>.part, rename to <folder> when <marker> was written and the
    run was not interrupted (exit status 0 = ok, 1 = a run failed; 130 = Ctrl-C, 2 = bad command)."""
    q = shlex.quote
    part = folder + ".part"
    return (f"mkdir -p {q(os.path.dirname(folder))} && rm -rf {q(part)} && {shlex.join(cmd)}; rc=$?; "
            f"if [ $rc -le 1 ] && [ -s {q(os.path.join(part, marker))} ]; then mv -T {q(part)} {q(folder)}; fi; exit $rc")


def read_comparison(folder):
    path = os.path.join(folder, "comparison.csv")
    try:
        with open(path, newline="") as f:
            return list(csv.DictReader(f))
    except OSError:
        return None


def mrpt_ini_value(path, section, key):
    """The value of `key` in `[section]` of an MRPT-style ini (`key = value  // comment`), or None."""
    current = None
    with open(path) as f:
        for line in f:
            line = line.split("//", 1)[0].split("#", 1)[0].strip()
            if line.startswith("[") and line.endswith("]"):
                current = line[1:-1].strip()
            elif current == section and "=" in line:
                k, v = line.split("=", 1)
                if k.strip() == key:
                    return v.strip()
    return None


def read_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return {}


def fmt_duration(s):
    s = int(round(s))
    return f"{s // 3600}:{s % 3600 // 60:02d}:{s % 60:02d}" if s >= 3600 else f"{s // 60}:{s % 60:02d}"


class Runner:
    """Runs shell lines in parallel (-j), one log file each, with a progress line per finished task.
    Children share the process group, so Ctrl-C reaches budget-slam, which ends its runs cleanly."""

    def __init__(self, jobs, logdir, quiet=False):
        self.jobs = max(1, jobs)
        self.logdir = logdir
        self.quiet = quiet
        self.lock = threading.Lock()

    def run(self, title, tasks):
        """tasks: list of (name, shell line, is_done callable). Returns {name: exit status}."""
        os.makedirs(self.logdir, exist_ok=True)
        total, results, start, finished = len(tasks), {}, time.time(), [0]
        if not total:
            return results

        def one(task):
            name, line, _ = task
            log = os.path.join(self.logdir, re.sub(r"[^\w.-]+", "_", name) + ".log")
            t0 = time.time()
            with open(log, "w") as lf:
                lf.write(line + "\n")
                lf.flush()
                rc = subprocess.call(["bash", "-c", line], stdout=lf, stderr=subprocess.STDOUT)
            with self.lock:
                finished[0] += 1
                results[name] = rc
                if not self.quiet:
                    el = time.time() - start
                    left = el / finished[0] * (total - finished[0])
                    state = "ok" if rc == 0 else f"exit {rc} (see {os.path.relpath(log)})"
                    print(f"[{title} {finished[0]}/{total}] {name}  {time.time() - t0:.1f} s  {state}  "
                          f"(elapsed {fmt_duration(el)}, ~{fmt_duration(left)} left)", file=sys.stderr, flush=True)
            return rc

        pool = ThreadPoolExecutor(max_workers=self.jobs)
        futures = [pool.submit(one, t) for t in tasks]
        try:
            for fu in futures:
                fu.result()
        except KeyboardInterrupt:
            for fu in futures:
                fu.cancel()
            pool.shutdown(wait=True)
            raise
        pool.shutdown(wait=True)
        return results


def prepare(exp, runner, log=print):
    """Simulations, then the unreduced baselines that resolve percentage caps. Writes prepare.txt."""
    check_relocalization_support(exp)
    os.makedirs(exp.outdir, exist_ok=True)
    sims = [(os.path.basename(f), exp.simulation_command(f), f) for f in exp.simulations]
    bases = [(os.path.relpath(b.folder, exp.outdir), exp.baseline_command(b), b) for b in exp.baselines.values()]
    write_atomic(os.path.join(exp.outdir, "prepare.txt"),
                 "".join(line + "\n" for _, line, _ in sims) + "".join(line + "\n" for _, line, _ in bases))
    todo = [(n, l, None) for n, l, f in sims if not exp.simulation_done(f)]
    if todo:
        log(f"simulating {len(todo)} rawlog(s)")
        runner.run("simulate", todo)
    missing = [n for n, _, f in sims if not exp.simulation_done(f)]
    if missing:
        raise ExperimentError("simulation failed: " + ", ".join(missing) + f" (logs in {runner.logdir})")
    todo = [(n, l, None) for n, l, b in bases if not exp.baseline_done(b)]
    if todo:
        log(f"running {len(todo)} unreduced baseline run(s) for the percentage caps")
        runner.run("baseline", todo)
    for n, _, b in bases:
        if not exp.baseline_done(b):
            raise ExperimentError(f"baseline {n} did not finish (logs in {runner.logdir})")
    for job in exp.jobs:
        if job.baseline is not None:
            job.cap_landmarks = resolve_cap(job.cap, job.baseline.landmarks())


def write_jobs(exp):
    lines = [exp.job_command(j) for j in exp.jobs]
    write_atomic(os.path.join(exp.outdir, "jobs.txt"), "".join(l + "\n" for l in lines))
    return lines


def run_jobs(exp, runner, retry_failed=False, log=print):
    lines = write_jobs(exp)
    todo = []
    for job, line in zip(exp.jobs, lines):
        done = exp.job_done(job)
        if done and retry_failed and any(r["status"] == "failed" for r in read_comparison(job.folder)):
            done = False
            os.rename(job.folder, job.folder + ".failed-" + time.strftime("%Y%m%d%H%M%S"))
        if not done:
            todo.append((job.rel, line, None))
    log(f"{len(exp.jobs)} job(s): {len(exp.jobs) - len(todo)} already done, {len(todo)} to run with -j {runner.jobs}")
    runner.run("job", todo)
    return len(todo)


# ---- results ----

SUMMARY_METRICS = [
    ("gt_trajectory_rmse_aligned_m", ("ground_truth", "trajectory_rmse_aligned_m")),
    ("gt_landmark_rmse_aligned_m", ("ground_truth", "landmark_rmse_aligned_m")),
    ("step_ms_mean", ("timings", "step_ms_mean")),
    ("step_ms_max", ("timings", "step_ms_max")),
    ("peak_rss_bytes", ("timings", "peak_rss_bytes")),
    ("steps", ("counts", "steps")),
]
NON_METRIC_COLUMNS = {"run", "reducer", "backend", "status", "cap", "seed"}
# comparison.csv of budget-slam before the reference metrics got their ref_ prefix.
LEGACY_COLUMNS = {c: "ref_" + c for c in ("ate_m", "ale_m", "are_deg", "ud_pct", "eig_min", "eig_max")}
RESULT_COLUMNS = ["rawlog", "backend", "reducer", "cap", "seed", "metric", "value"]


def as_number(v):
    try:
        x = float(v)
    except (TypeError, ValueError):
        return None
    return x if math.isfinite(x) else None


def job_rows(job):
    """Tidy rows of one finished job: one a (run, metric) with a finite value."""
    rows = []
    for r in read_comparison(job.folder) or []:
        reducer = "none" if r["run"] == "reference" else r["run"]
        key = dict(rawlog=job.rawlog.label, backend=job.backend, reducer=job.reducer_label(reducer),
                   cap=job.cap, seed=job.seed)
        metrics = [("status_ok", 1.0 if r["status"] == "ok" else 0.0)]
        if reducer != "none" and job.cap_landmarks != "none":
            metrics.append(("cap_landmarks", float(job.cap_landmarks)))
        metrics += [(LEGACY_COLUMNS.get(c, c), as_number(r[c])) for c in r if c not in NON_METRIC_COLUMNS]
        summary = read_json(os.path.join(job.folder, r["run"], "summary.json"))
        in_table = {m for m, _ in metrics}
        for name, (a, b) in SUMMARY_METRICS:
            if name not in in_table:  # comparison.csv carries the aligned ATE too: one row
                metrics.append((name, as_number(summary.get(a, {}).get(b))))
        for m, v in metrics:
            if v is not None:
                rows.append(dict(key, metric=m, value=fmt_value(v)))
    return rows


def fmt_value(v):
    """A finite number as results.csv writes it: integers without a decimal point."""
    return repr(v) if v != int(v) or abs(v) > 1e15 else str(int(v))


def write_tidy(path, columns, rows):
    tmp = path + ".tmp"
    with open(tmp, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=columns, lineterminator="\n")
        w.writeheader()
        w.writerows(rows)
    os.replace(tmp, path)


def collect(exp, path):
    """results.csv of every finished job; also relocalization.csv beside it when a job relocalized."""
    rows, reloc = [], []
    for job in exp.jobs:
        if exp.job_done(job):
            rows += job_rows(job)
            reloc += relocalization_rows(job)
    write_tidy(path, RESULT_COLUMNS, rows)
    if reloc or exp.relocalizes:
        write_tidy(os.path.join(os.path.dirname(path), "relocalization.csv"), RELOCALIZATION_COLUMNS, reloc)
    return rows


RELOCALIZATION_COLUMNS = ["rawlog", "backend", "reducer", "cap", "seed", "traversal", "metric", "value"]


def relocalization_rows(job):
    """Tidy rows of a job's relocalization.csv (one a run and traversal): every numeric column a
    metric, the traversal named as in the experiment (the file's stem, or sim:<scenario>:<route>)."""
    path = os.path.join(job.folder, "relocalization.csv")
    try:
        with open(path, newline="") as f:
            table = list(csv.DictReader(f))
    except OSError:
        return []
    names = {}
    for label, file in job.traversals:
        names[file] = names[os.path.basename(file)] = names[re.sub(r"\.rawlog$", "", os.path.basename(file))] = label
    rows = []
    for r in table:
        reducer = "none" if r.get("run") == "reference" else r.get("run", "")
        t = r.get("traversal", "")
        key = dict(rawlog=job.rawlog.label, backend=job.backend, reducer=job.reducer_label(reducer), cap=job.cap,
                   seed=job.seed, traversal=names.get(t, names.get(os.path.basename(t), t)))
        for c, v in r.items():
            x = as_number(v) if c not in ("run", "traversal") else None
            if x is not None:
                rows.append(dict(key, metric=c, value=fmt_value(x)))
    return rows

def read_results(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def read_steps(folder):
    """steps.csv as a dict of numpy arrays (one per column)."""
    import numpy as np
    path = os.path.join(folder, "steps.csv")
    with open(path) as f:
        header = f.readline().strip().split(",")
    # an empty field or `nan` (a value that does not apply) reads as NaN
    data = np.atleast_2d(np.genfromtxt(path, delimiter=",", skip_header=1, dtype=float))
    return {h: data[:, i] for i, h in enumerate(header)}


def read_tum(path):
    import numpy as np
    if not os.path.isfile(path):
        return None
    return np.loadtxt(path, ndmin=2)


def position_error(folder):
    """(step, error, sigma) of the online robot position against ground truth: error = |p - p_true|,
    sigma = sqrt(var_x + var_y) from steps.csv; None without ground_truth.tum."""
    import numpy as np
    gt = read_tum(os.path.join(folder, "ground_truth.tum"))
    if gt is None or not len(gt):
        return None
    s = read_steps(folder)
    idx = np.searchsorted(gt[:, 0], s["t"])
    idx = np.clip(idx, 0, len(gt) - 1)
    ok = np.abs(gt[idx, 0] - s["t"]) < 1e-6
    err = np.hypot(s["x"] - gt[idx, 1], s["y"] - gt[idx, 2])
    sigma = np.sqrt(np.maximum(s["var_x"] + s["var_y"], 0.0))
    return s["step"][ok], err[ok], sigma[ok]


# ---- what the scripts built on the sweep share (paper_tables, benchmark) ----

def write_experiment(path, sweep, groups, written_by):
    """An experiment file: [sweep] with the keys of `sweep`, then a [group NAME] per (name, keys) of
    `groups`; a list value is written one item a line (the `set` key)."""
    def block(keys):
        out = []
        for k, v in keys.items():
            if isinstance(v, list):
                v = "\n    ".join(v)
            out.append(f"{k} = {v}")
        return "\n".join(out)
    text = f"# Written by {written_by}.\n[sweep]\n" + block(sweep) + "\n"
    for name, keys in groups:
        text += f"\n[group {name}]\n" + block(keys) + "\n"
    os.makedirs(os.path.dirname(path), exist_ok=True)
    write_atomic(path, text)


def run_experiment(ini, outdir, budget_slam, budget_simulate, jobs, retry_failed=False, log=print):
    """Simulations, baselines and the jobs of an experiment file that are not done yet, then
    results.csv. Returns (Experiment, rows, jobs run)."""
    exp = Experiment(ini, outdir, budget_slam, budget_simulate)
    runner = Runner(jobs, os.path.join(outdir, "logs"))
    prepare(exp, runner, log)
    ran = run_jobs(exp, runner, retry_failed=retry_failed, log=log)
    rows = collect(exp, os.path.join(outdir, "results.csv"))
    return exp, rows, ran


def unreduced_trajectory(budget_slam, config, rawlog, dst, log=print):
    """trajectory.tum of one unreduced EKF run over the whole `rawlog` in the folder dst (made once,
    written as dst.part then renamed): what a traversal without ground truth is measured against."""
    tum = os.path.join(dst, "trajectory.tum")
    if os.path.isfile(tum):
        return tum
    log(f"unreduced EKF run over the whole {os.path.basename(rawlog)} (the reference trajectory of its split)")
    part = dst + ".part"
    p = subprocess.run([budget_slam, "run", "-c", config, "-i", rawlog, "-o", part, "--reducer", "none",
                        "--backend", "ekf", "--quiet", "--force"], capture_output=True, text=True)
    if p.returncode != 0 or not os.path.isfile(os.path.join(part, "trajectory.tum")):
        raise RuntimeError(f"the unreduced run over {os.path.basename(rawlog)} failed (exit {p.returncode}): "
                           + (p.stderr.strip().splitlines() or ["no trajectory.tum"])[-1])
    if os.path.isdir(dst):
        shutil.rmtree(dst)
    os.rename(part, dst)
    return tum
