#!/usr/bin/env bash
# A one-node Slurm cluster on this machine, in a folder of its own: munged,
# slurmctld and slurmd with a generated slurm.conf naming this host as the
# only node (all its cores). For trying the Slurm scripts and for the
# `slurm` tests; a real cluster has its own configuration.
#
#   scripts/slurm/local-cluster.sh start DIR   # prints the line to source: export SLURM_CONF=...
#   scripts/slurm/local-cluster.sh stop DIR
#
# Needs Debian's slurm-wlm and munge (scripts/setup.sh installs them) and
# root (slurmd starts the jobs as their submitting user).
set -euo pipefail

cmd=${1:-}
dir=${2:-}
[ -n "$cmd" ] && [ -n "$dir" ] || { echo "usage: $0 start|stop DIR" >&2; exit 2; }

stop() {
  for pid in "$dir"/slurmd.pid "$dir"/slurmctld.pid "$dir"/munged.pid; do
    [ -f "$pid" ] && kill "$(cat "$pid")" 2>/dev/null || true
  done
  sleep 1
  for pid in "$dir"/slurmd.pid "$dir"/slurmctld.pid "$dir"/munged.pid; do
    [ -f "$pid" ] && kill -9 "$(cat "$pid")" 2>/dev/null || true
    rm -f "$pid"
  done
}

if [ "$cmd" = stop ]; then stop; exit 0; fi
[ "$cmd" = start ] || { echo "usage: $0 start|stop DIR" >&2; exit 2; }

fail() { echo "local-cluster: cannot start Slurm: $*" >&2; stop; exit 1; }
for tool in munged mungekey slurmctld slurmd sbatch sinfo; do
  command -v "$tool" >/dev/null || fail "'$tool' is not installed (Debian packages slurm-wlm and munge; scripts/setup.sh installs them)"
done
[ "$(id -u)" -eq 0 ] || fail "slurmd must run as root to start jobs (run as root, e.g. in CI)"

mkdir -p "$dir"/state "$dir"/spool "$dir"/munge
dir=$(cd "$dir" && pwd)
chmod 700 "$dir"/munge

# munge: a key of our own and a socket in our folder, so a system munged (if
# any) is left alone.
mungekey --create --keyfile="$dir/munge/munge.key" --force >/dev/null 2>&1 ||
  fail "mungekey could not create a key"
chmod 600 "$dir/munge/munge.key"
munged --key-file="$dir/munge/munge.key" --socket="$dir/munge/munge.socket" \
  --pid-file="$dir/munged.pid" --log-file="$dir/munge/munged.log" --seed-file="$dir/munge/munged.seed" \
  --force >/dev/null 2>&1 || fail "munged did not start: $(tail -n 3 "$dir/munge/munged.log" 2>/dev/null | tr '\n' ' ')"

# Free TCP ports for the controller and the node daemon: random ones that
# nothing answers on.
port() {
  local p
  while :; do
    p=$((20000 + RANDOM % 30000))
    (echo >"/dev/tcp/127.0.0.1/$p") 2>/dev/null || { echo "$p"; return; }
  done
}
ctl_port=$(port)
node_port=$(port)
while [ "$node_port" = "$ctl_port" ]; do node_port=$(port); done
node=$(hostname -s)
cpus=$(nproc)
mem=$(awk '/MemTotal/ {print int($2 / 1024 * 0.8)}' /proc/meminfo)

# cred_expire is also how long Slurm holds a requeued job before it runs
# again (120 s by default); on one node with no prolog, 10 s is ample for a
# step's credential and lets a failed task come back without a two-minute
# wait.
cat >"$dir/slurm.conf" <<CONF
ClusterName=jade-local
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$ctl_port
SlurmdPort=$node_port
SlurmUser=root
AuthType=auth/munge
AuthInfo=socket=$dir/munge/munge.socket,cred_expire=10
CredType=cred/munge
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
ReturnToService=2
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MinJobAge=3600
NodeName=$node NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=jade Nodes=$node Default=YES MaxTime=INFINITE State=UP
CONF
: >"$dir/cgroup.conf"
export SLURM_CONF=$dir/slurm.conf

slurmctld -f "$dir/slurm.conf" -i >/dev/null 2>&1 ||
  fail "slurmctld did not start: $(tail -n 3 "$dir/slurmctld.log" 2>/dev/null | tr '\n' ' ')"
slurmd -f "$dir/slurm.conf" -N "$node" >/dev/null 2>&1 ||
  fail "slurmd did not start: $(tail -n 3 "$dir/slurmd.log" 2>/dev/null | tr '\n' ' ')"

# Wait until the node takes jobs.
for _ in $(seq 1 60); do
  state=$(sinfo -h -N -o '%T' 2>/dev/null | head -n 1 || true)
  case "$state" in idle*|mixed*|allocated*) echo "export SLURM_CONF=$dir/slurm.conf"; exit 0 ;; esac
  sleep 1
done
fail "the node did not become idle within 60 s (state '${state:-none}'): $(tail -n 3 "$dir/slurmd.log" 2>/dev/null | tr '\n' ' ')"
