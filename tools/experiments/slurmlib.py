"""A sweep's jobs.txt submitted to SLURM as one job array (docs/EXPERIMENTS.md, "Cluster (SLURM)").

The array's task i runs line i of jobs.txt through slurm-array.sh; only the lines whose job is not
done are submitted. Submissions are recorded in OUT/slurm_jobs.txt (`<job id> <array spec>` a line)
so that a second submission is refused while the first is still queued or running: two arrays
running the same line would write the same `.part` folder.
"""
import os
import re
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ARRAY_SCRIPT = os.path.join(HERE, "slurm-array.sh")

# squeue states after which a task does nothing more (SLURM 22.05, squeue(1) "JOB STATE CODES").
TERMINAL = {"BOOT_FAIL", "CANCELLED", "COMPLETED", "DEADLINE", "FAILED", "NODE_FAIL",
            "OUT_OF_MEMORY", "PREEMPTED", "REVOKED", "SPECIAL_EXIT", "TIMEOUT"}


# Pending reasons that no amount of waiting resolves (squeue(1) "JOB REASON CODES").
NEVER_RUNS = {"PartitionConfig", "BadConstraints", "PartitionNodeLimit", "PartitionTimeLimit",
              "InvalidAccount", "InvalidQOS", "DependencyNeverSatisfied", "JobHeldAdmin", "JobHeldUser"}


class SlurmError(Exception):
    pass


def _tool(name):
    path = shutil.which(name)
    if not path:
        raise SlurmError(f"{name} not found: install SLURM's clients (Debian: slurm-client) or run on the "
                         "cluster's login node")
    return path


def array_spec(indices, throttle=None):
    """'1-3,7,9-10' (1-based line numbers) with '%N' when throttled."""
    ranges, start, prev = [], None, None
    for i in sorted(indices):
        if start is None:
            start = prev = i
        elif i == prev + 1:
            prev = i
        else:
            ranges.append((start, prev))
            start = prev = i
    if start is not None:
        ranges.append((start, prev))
    spec = ",".join(f"{a}" if a == b else f"{a}-{b}" for a, b in ranges)
    return spec + (f"%{throttle}" if throttle else "")


def sbatch_command(jobs_txt, logdir, indices, partition=None, throttle=None, cpus_per_task=None,
                   extra=()):
    """The sbatch line: the array script over jobs.txt, logs into OUT/logs/slurm-<job>_<task>.out."""
    cmd = [_tool("sbatch"), "--parsable", f"--array={array_spec(indices, throttle)}",
           f"--chdir={os.path.dirname(jobs_txt)}", f"--output={os.path.join(logdir, 'slurm-%A_%a.out')}"]
    if partition:
        cmd.append(f"--partition={partition}")
    if cpus_per_task:
        cmd.append(f"--cpus-per-task={cpus_per_task}")
    cmd += list(extra)
    return cmd + [ARRAY_SCRIPT, jobs_txt]


def task_states(job_id, reasons=None):
    """{task label: state} of a job array as squeue knows it ('12_3': 'RUNNING', '12_[4-9]':
    'PENDING'); {} once SLURM has forgotten the job (MinJobAge after its end). `reasons`, a dict,
    receives each label's pending reason."""
    p = subprocess.run([_tool("squeue"), "-h", "-t", "all", "-j", str(job_id), "-o", "%i|%T|%r"],
                       capture_output=True, text=True)
    if p.returncode != 0:
        if "Invalid job id" in p.stderr:
            return {}
        raise SlurmError(f"squeue -j {job_id}: {p.stderr.strip() or 'exit ' + str(p.returncode)}")
    out = {}
    for line in p.stdout.splitlines():
        parts = line.strip().split("|")
        if len(parts) >= 2:
            out[parts[0]] = parts[1].split()[0]
            if reasons is not None and len(parts) >= 3:
                reasons[parts[0]] = parts[2].strip()
    return out


def active(states):
    return {k: v for k, v in states.items() if v not in TERMINAL}


def recorded_jobs(outdir):
    path = os.path.join(outdir, "slurm_jobs.txt")
    try:
        with open(path) as f:
            return [line.split()[0] for line in f if line.strip()]
    except OSError:
        return []


SCRIPT_CPUS_PER_TASK = 4  # slurm-array.sh's #SBATCH --cpus-per-task


def default_cpus_per_task(partition=None):
    """The CPUs a task asks for when --cpus-per-task is not given: the array script's 4, or fewer
    when no node of the partition has 4 (sinfo's CPU count of its largest node), so that the
    default never asks for more than the cluster has. None when sinfo cannot tell (the script's
    value then stands)."""
    try:
        cmd = [_tool("sinfo"), "-h", "-o", "%c"] + ([f"--partition={partition}"] if partition else [])
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=30)
    except (SlurmError, OSError, subprocess.TimeoutExpired):
        return None
    cpus = [int(m.group(1)) for m in re.finditer(r"(\d+)", p.stdout)] if p.returncode == 0 else []
    return min(SCRIPT_CPUS_PER_TASK, max(cpus)) if cpus else None


def submit(exp, lines, todo_jobs, partition=None, throttle=None, cpus_per_task=None, extra=(), log=print):
    """Submits the lines of jobs.txt whose jobs are in `todo_jobs`. Returns the job id."""
    if cpus_per_task is None:
        cpus_per_task = default_cpus_per_task(partition)
    for job_id in recorded_jobs(exp.outdir):
        still = active(task_states(job_id))
        if still:
            raise SlurmError(f"job array {job_id} of this sweep is still queued or running "
                             f"({len(still)} task(s)); wait for it (squeue -j {job_id}) or cancel it "
                             f"(scancel {job_id}), then submit again")
    jobs_txt = os.path.join(exp.outdir, "jobs.txt")
    indices = [i + 1 for i, job in enumerate(exp.jobs) if job in todo_jobs]
    logdir = os.path.join(exp.outdir, "logs")
    os.makedirs(logdir, exist_ok=True)
    cmd = sbatch_command(jobs_txt, logdir, indices, partition, throttle, cpus_per_task, extra)
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        said = [line.strip() for line in (p.stderr or p.stdout).splitlines() if line.strip()]
        raise SlurmError(f"sbatch refused the array: {said[-1] if said else 'exit ' + str(p.returncode)} "
                         f"(command: {' '.join(cmd)})")
    m = re.match(r"(\d+)", p.stdout.strip())
    if not m:
        raise SlurmError(f"sbatch printed no job id: {p.stdout.strip()!r}")
    job_id = m.group(1)
    with open(os.path.join(exp.outdir, "slurm_jobs.txt"), "a") as f:
        f.write(f"{job_id} {array_spec(indices, throttle)}\n")
    log(f"submitted job array {job_id}: {len(indices)} task(s), lines {array_spec(indices)} of {jobs_txt}"
        + (f", partition {partition}" if partition else "") + (f", at most {throttle} at once" if throttle else "")
        + (f", {cpus_per_task} CPU(s) a task" if cpus_per_task else "")
        + f"; logs {logdir}/slurm-{job_id}_<task>.out")
    return job_id


def wait(job_id, log=print, poll_s=1.0):
    """Blocks until no task of the array is pending or running. Returns {task: final state}."""
    last, start, final = None, time.time(), {}
    while True:
        reasons = {}
        states = task_states(job_id, reasons)
        stuck = sorted({reasons.get(k) for k, v in states.items() if v == "PENDING"} & NEVER_RUNS)
        if stuck:
            subprocess.run([_tool("scancel"), str(job_id)], capture_output=True)
            raise SlurmError(f"job array {job_id} cannot run (squeue reason {', '.join(stuck)}: it asks for "
                             "more than the partition gives, e.g. --cpus-per-task or --time); cancelled it")
        # Pending tasks show up folded ('12_[3-9%2]'); keep only the labels of single tasks.
        final = {k: v for k, v in final.items() if "[" not in k}
        final.update(states)
        now_active = active(states)
        summary = (sum(1 for v in states.values() if v in TERMINAL),
                   sum(1 for v in now_active.values() if v == "RUNNING"),
                   sum(1 for v in now_active.values() if v != "RUNNING"))
        if summary != last:
            log(f"[slurm {job_id}] {summary[0]} task(s) ended, {summary[1]} running, {summary[2]} waiting "
                f"({int(time.time() - start)} s)")
            last = summary
        if not now_active:
            return {k: v for k, v in final.items() if "[" not in k} or final
        time.sleep(min(10.0, poll_s + (time.time() - start) / 60.0))


def main_submit(exp, write_jobs, job_done, a, log):
    """`sweep --slurm`: returns (job id or None, whether the caller should collect now)."""
    lines = write_jobs(exp)
    todo = [j for j in exp.jobs if not job_done(j)]
    log(f"{len(exp.jobs)} job(s): {len(exp.jobs) - len(todo)} already done, {len(todo)} to submit")
    if not todo:
        return None, True
    job_id = submit(exp, lines, todo, a.partition, a.array_throttle, a.cpus_per_task, a.sbatch_arg or (), log)
    print(job_id, flush=True)  # stdout: the job id alone, for scripts
    if not a.wait:
        log(f"collect when it has ended: {os.path.basename(sys.argv[0])} {a.experiment} -o {a.out} --collect-only")
        return job_id, False
    try:
        states = wait(job_id, log)
    except KeyboardInterrupt:
        log(f"stopped waiting; job array {job_id} goes on (scancel {job_id} stops it); collect later with --collect-only")
        raise
    bad = {k: v for k, v in states.items() if v != "COMPLETED"}
    if bad:
        log(f"[slurm {job_id}] not completed: " + ", ".join(f"{k} {v}" for k, v in sorted(bad.items())))
    return job_id, True
