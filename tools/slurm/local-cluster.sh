#!/usr/bin/env bash
# A one-node SLURM cluster on this machine, for trying sweeps on a scheduler and for the tests
# (docs/EXPERIMENTS.md, "Cluster (SLURM)"). Debian 12's slurm-wlm 22.05 and munge.
#
#   tools/slurm/local-cluster.sh start    # writes the config, starts munged, slurmctld, slurmd
#   eval "$(tools/slurm/local-cluster.sh env)"   # SLURM_CONF for sbatch, squeue, sinfo, sweep --slurm
#   tools/slurm/local-cluster.sh status
#   tools/slurm/local-cluster.sh stop     # cancels the jobs, stops the daemons, waits for them
#
# Everything lives in one folder, $BUDGET_SLAM_SLURM_DIR (default /tmp/budget-slam-slurm-<uid>):
# slurm.conf, the munge key and socket, state, spool, logs and pid files. Nothing system-wide is
# read or written (no /etc/slurm, /etc/munge, /run/munge), the daemons listen on 127.0.0.1 only,
# on two free ports, and the node has this machine's CPUs and memory (`slurmd -C`).
# Needs root (slurmd starts the jobs' processes) and the packages slurm-wlm and munge.
# Exit codes: 0 ok, 1 failed, 3 not possible here (packages or root privileges missing).
set -euo pipefail

DIR="${BUDGET_SLAM_SLURM_DIR:-${TMPDIR:-/tmp}/budget-slam-slurm-$(id -u)}"
CONF="$DIR/slurm.conf"
PARTITION="${BUDGET_SLAM_SLURM_PARTITION:-local}"
NODE="$(hostname -s)"

die() { echo "local-cluster: $*" >&2; exit 1; }
impossible() { echo "local-cluster: $*" >&2; exit 3; }

pid_of() {  # pid from a pid file, if that process is alive
  local f="$1" pid
  [ -s "$f" ] || return 1
  pid="$(cat "$f")"
  [ -n "$pid" ] && kill -0 "$pid" 2>/dev/null && echo "$pid"
}

check_possible() {
  local missing=()
  for b in slurmctld slurmd munged mungekey sbatch squeue sinfo scontrol scancel; do
    command -v "$b" >/dev/null 2>&1 || [ -x "/usr/sbin/$b" ] || missing+=("$b")
  done
  [ ${#missing[@]} -eq 0 ] || impossible "missing ${missing[*]} (install the Debian packages slurm-wlm and munge; tools/setup.sh does)"
  [ "$(id -u)" -eq 0 ] || impossible "needs root: slurmd starts the jobs' processes as their user"
}

free_port() {  # a TCP port free on 127.0.0.1 now
  /usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}

write_config() {
  local node_line ctld_port slurmd_port
  node_line="$(slurmd -C | head -n 1)"  # NodeName=<host> CPUs=.. Boards=.. ... RealMemory=..
  [[ "$node_line" == NodeName=* ]] || die "slurmd -C did not describe this node: $node_line"
  node_line="${node_line#NodeName=* }"
  ctld_port="$(free_port)"
  slurmd_port="$(free_port)"
  while [ "$slurmd_port" = "$ctld_port" ]; do slurmd_port="$(free_port)"; done
  : > "$DIR/plugstack.conf"
  cat > "$CONF" <<EOF
# Written by tools/slurm/local-cluster.sh: a one-node cluster on 127.0.0.1.
ClusterName=budgetslam
SlurmctldHost=$NODE(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
CommunicationParameters=NoInAddrAny,NoCtldInAddrAny
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$DIR/munge/munge.socket.2
CredType=cred/munge
PlugStackConfig=$DIR/plugstack.conf
StateSaveLocation=$DIR/state
SlurmdSpoolDir=$DIR/spool
SlurmctldPidFile=$DIR/run/slurmctld.pid
SlurmdPidFile=$DIR/run/slurmd.pid
SlurmctldLogFile=$DIR/log/slurmctld.log
SlurmdLogFile=$DIR/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MaxArraySize=100001
NodeName=$NODE NodeAddr=127.0.0.1 $node_line State=UNKNOWN
PartitionName=$PARTITION Nodes=$NODE Default=YES MaxTime=INFINITE State=UP
EOF
}

start() {
  check_possible
  if pid_of "$DIR/run/slurmctld.pid" >/dev/null || pid_of "$DIR/run/munged.pid" >/dev/null; then
    die "already running in $DIR (stop it first)"
  fi
  mkdir -p "$DIR"
  chmod 0700 "$DIR"
  rm -rf "$DIR/state" "$DIR/spool" "$DIR/run" "$DIR/munge"
  mkdir -p "$DIR/state" "$DIR/spool" "$DIR/run" "$DIR/log" "$DIR/munge"
  chmod 0700 "$DIR/munge"
  write_config

  mungekey --create --keyfile="$DIR/munge/munge.key" --force
  chmod 0600 "$DIR/munge/munge.key"
  munged --socket="$DIR/munge/munge.socket.2" --key-file="$DIR/munge/munge.key" \
         --pid-file="$DIR/run/munged.pid" --log-file="$DIR/log/munged.log" \
         --seed-file="$DIR/munge/munged.seed" --force \
    || die "munged did not start (see $DIR/log/munged.log)"

  slurmctld -f "$CONF" -c -i || die "slurmctld did not start (see $DIR/log/slurmctld.log)"
  slurmd -f "$CONF" || die "slurmd did not start (see $DIR/log/slurmd.log)"

  # Ready when the node is idle.
  local state=""
  for _ in $(seq 1 300); do
    state="$(SLURM_CONF="$CONF" sinfo -h -n "$NODE" -o %T 2>/dev/null || true)"
    [ "$state" = idle ] && break
    sleep 0.1
  done
  if [ "$state" != idle ]; then
    echo "local-cluster: node $NODE is '${state:-unknown}' after 30 s; logs in $DIR/log" >&2
    stop >/dev/null 2>&1 || true
    exit 1
  fi
  echo "local-cluster: running in $DIR (partition $PARTITION, node $NODE)"
  echo "export SLURM_CONF=$CONF"
}

stop() {
  local pids=() pid
  if [ -f "$CONF" ] && pid_of "$DIR/run/slurmctld.pid" >/dev/null; then
    SLURM_CONF="$CONF" scancel --quiet --full --partition="$PARTITION" 2>/dev/null || true
  fi
  for f in slurmd slurmctld munged; do
    pid="$(pid_of "$DIR/run/$f.pid" || true)"
    if [ -n "$pid" ]; then
      pids+=("$pid")
      kill -TERM "$pid" 2>/dev/null || true
    fi
  done
  # Job steps outlive slurmd for a moment; wait for every process of this cluster.
  for _ in $(seq 1 100); do
    local alive=()
    for pid in "${pids[@]}" $(cluster_pids); do kill -0 "$pid" 2>/dev/null && alive+=("$pid"); done
    [ ${#alive[@]} -eq 0 ] && { echo "local-cluster: stopped ($DIR)"; return 0; }
    sleep 0.1
  done
  for pid in "${pids[@]}" $(cluster_pids); do kill -KILL "$pid" 2>/dev/null || true; done
  echo "local-cluster: stopped ($DIR; some processes had to be killed)"
}

cluster_pids() {  # slurmstepd processes of this cluster (their spool folder is ours)
  local p
  for p in /proc/[0-9]*; do
    [ "$(readlink "$p/exe" 2>/dev/null || true)" = /usr/sbin/slurmstepd ] || continue
    [ "$(readlink "$p/cwd" 2>/dev/null || true)" = "$DIR/spool" ] && echo "${p#/proc/}"
  done
}

status() {
  local running=0 pid
  for f in munged slurmctld slurmd; do
    if pid="$(pid_of "$DIR/run/$f.pid")"; then
      echo "$f: running (pid $pid)"
      running=$((running + 1))
    else
      echo "$f: not running"
    fi
  done
  if [ "$running" -eq 3 ]; then
    SLURM_CONF="$CONF" sinfo
    echo "export SLURM_CONF=$CONF"
    return 0
  fi
  return 1
}

case "${1:-}" in
  start) start ;;
  stop) stop ;;
  status) status ;;
  env) echo "export SLURM_CONF=$CONF" ;;
  *) echo "usage: $0 start|stop|status|env   (folder: \$BUDGET_SLAM_SLURM_DIR, now $DIR)" >&2; exit 2 ;;
esac
