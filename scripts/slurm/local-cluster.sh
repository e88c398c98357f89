#!/usr/bin/env bash
# A one-node Slurm cluster on this machine, for the tests of evaluate-array.sh against real
# slurmctld and slurmd (Debian's slurm-wlm and munge). Configuration, munge key, state and logs
# live in DIR; the sockets (munge's, slurmd's spool) in a short directory under /tmp, as Unix
# socket paths are limited to 108 bytes; daemons listen on 127.0.0.1 at free ports.
#
#   local-cluster.sh start DIR   # prints the SLURM_CONF to export; exit 3 when Slurm cannot start
#   local-cluster.sh stop DIR    # stops what start started (by the pids it recorded)
#
# Exit 3 means "Slurm is not usable here" (not installed, not root, a daemon did not come up);
# the tests skip with the reason printed on stderr.
set -euo pipefail

readonly kStartTimeoutS=30  # slurmctld and slurmd come up within a few seconds

die() { echo "local-cluster: $*" >&2; exit 3; }

free_port() {
  python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}

start() {
  local dir=$1
  for program in munged mungekey slurmctld slurmd sinfo sbatch; do
    command -v "$program" > /dev/null || die "$program not installed (Debian packages slurm-wlm, munge)"
  done
  [[ $(id -u) -eq 0 ]] || die "slurmd must run as root to start jobs as their user"
  mkdir -p "$dir"/{state,log,munge}
  dir=$(cd "$dir" && pwd)
  chmod 700 "$dir/munge"
  local sockets
  sockets=$(mktemp -d /tmp/skelgrasp-slurm.XXXXXX)
  echo "$sockets" > "$dir/sockets"
  mkdir -p "$sockets/spool"
  chmod 755 "$sockets"
  mungekey --create --keyfile="$dir/munge/munge.key" --force > /dev/null 2>&1 ||
    die "mungekey failed"
  munged --force --key-file="$dir/munge/munge.key" --socket="$sockets/munge" \
    --pid-file="$dir/munge/munged.pid" --log-file="$dir/log/munged.log" \
    --seed-file="$dir/munge/seed" || die "munged did not start (see $dir/log/munged.log)"
  local cpus memory_mb
  cpus=$(nproc)
  memory_mb=$(awk '/MemTotal/ {print int($2 / 1024 / 2)}' /proc/meminfo)
  cat > "$dir/slurm.conf" << CONF
ClusterName=skelgrasp-local
SlurmctldHost=$(hostname -s)(127.0.0.1)
SlurmctldPort=$(free_port)
SlurmdPort=$(free_port)
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$sockets/munge
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$dir/state
SlurmdSpoolDir=$sockets/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MpiDefault=none
ReturnToService=2
SchedulerType=sched/backfill
NodeName=$(hostname -s) NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$memory_mb State=UNKNOWN
PartitionName=local Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
  export SLURM_CONF=$dir/slurm.conf
  slurmctld -f "$SLURM_CONF" > "$dir/log/slurmctld.out" 2>&1 ||
    die "slurmctld did not start (see $dir/log/slurmctld.log)"
  slurmd -f "$SLURM_CONF" > "$dir/log/slurmd.out" 2>&1 ||
    die "slurmd did not start (see $dir/log/slurmd.log)"
  local waited=0
  until sinfo -h -o %t 2>/dev/null | grep -qx 'idle'; do
    (( waited++ < kStartTimeoutS )) || die "the node did not come up in ${kStartTimeoutS} s (see $dir/log)"
    sleep 1
  done
  echo "$SLURM_CONF"
}

stop() {
  local dir=$1
  for pid_file in "$dir/slurmd.pid" "$dir/slurmctld.pid" "$dir/munge/munged.pid"; do
    [[ -f $pid_file ]] || continue
    local pid
    pid=$(cat "$pid_file")
    kill "$pid" 2> /dev/null || true
    for _ in $(seq 50); do kill -0 "$pid" 2> /dev/null || break; sleep 0.1; done
  done
  if [[ -f $dir/sockets ]]; then
    local sockets
    sockets=$(cat "$dir/sockets")
    [[ $sockets == /tmp/skelgrasp-slurm.* ]] && rm -rf "$sockets"
  fi
}

case ${1:-} in
  start) [[ $# -eq 2 ]] || die "usage: local-cluster.sh start DIR"; start "$2" ;;
  stop) [[ $# -eq 2 ]] || die "usage: local-cluster.sh stop DIR"; stop "$2" ;;
  *) echo "usage: local-cluster.sh start|stop DIR" >&2; exit 2 ;;
esac
