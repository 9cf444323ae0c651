#!/usr/bin/env bash
# A one-node Slurm cluster on this machine (controller, node daemon and munge
# on localhost, all as root), to run glint the way a cluster does: an sbatch
# job whose srun starts the ranks over PMIx. Not part of the tests; it
# installs Debian's slurmd, slurmctld, slurm-client and munge when missing
# and writes /etc/slurm/slurm.conf (use it on a machine of your own).
# Usage: scripts/slurm-local.sh [start|demo|stop]   (default: start, demo)
#   start  munged, slurmctld, slurmd; waits for the node to be idle
#   demo   sbatch: 2 tasks x 1 CPU render the showcase and a 4-frame
#          animation with srun --mpi=pmix; compares the bytes with a
#          single-process render
#   stop   ends the three daemons (by their pid files)
# Needs build/glint built with MPI (Open MPI; Debian's Slurm has its PMIx plugin).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
[ "$(id -u)" -eq 0 ] || { echo "slurm-local.sh: run as root (it starts daemons and writes /etc/slurm)" >&2; exit 1; }

start() {
  if ! command -v slurmctld > /dev/null || ! command -v munged > /dev/null; then
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq slurmd slurmctld slurm-client munge > /dev/null
  fi
  # munge: the key the package made, the socket folder no init system made here.
  mkdir -p /run/munge && chown munge:munge /run/munge
  [ -s /etc/munge/munge.key ] || runuser -u munge -- /usr/sbin/mungekey --create
  pgrep -x munged > /dev/null || runuser -u munge -- /usr/sbin/munged
  local node
  node=$(slurmd -C | head -1)  # NodeName=HOST CPUs=... RealMemory=... as slurmd sees this machine
  mkdir -p /var/lib/slurm/slurmctld /var/lib/slurm/slurmd /var/log/slurm /etc/slurm
  cat > /etc/slurm/slurm.conf <<EOF
# One-node Slurm on this machine (glint scripts/slurm-local.sh).
ClusterName=glint-local
SlurmctldHost=$(hostname -s)(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
StateSaveLocation=/var/lib/slurm/slurmctld
SlurmdSpoolDir=/var/lib/slurm/slurmd
SlurmctldPidFile=/run/slurmctld.pid
SlurmdPidFile=/run/slurmd.pid
SlurmctldLogFile=/var/log/slurm/slurmctld.log
SlurmdLogFile=/var/log/slurm/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
MpiDefault=none
ReturnToService=2
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
$node NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=local Nodes=$(hostname -s) Default=YES MaxTime=INFINITE State=UP
EOF
  [ -e /run/slurmctld.pid ] && kill -0 "$(cat /run/slurmctld.pid)" 2> /dev/null || slurmctld
  [ -e /run/slurmd.pid ] && kill -0 "$(cat /run/slurmd.pid)" 2> /dev/null || slurmd
  for _ in $(seq 30); do
    sinfo -h -o %T 2> /dev/null | grep -q idle && { sinfo; return 0; }
    sleep 1
  done
  echo "slurm-local.sh: the node did not come up; see /var/log/slurm/" >&2
  exit 1
}

demo() {
  local work
  work=$(mktemp -d /tmp/glint-slurm.XXXXXX)
  mkdir -p "$work/frames"
  cat > "$work/job.sh" <<EOF
#!/bin/sh
#SBATCH --nodes=1 --ntasks-per-node=2 --cpus-per-task=1
#SBATCH --output=$work/job.log
srun --mpi=pmix $root/build/glint render $root/scenes/showcase.json -o $work/showcase.exr --threads "\$SLURM_CPUS_PER_TASK"
srun --mpi=pmix $root/build/glint render $root/tests/mpi/anim4.json -o $work/frames/out_%04d.exr --threads "\$SLURM_CPUS_PER_TASK" -q
EOF
  local job
  job=$(sbatch --parsable "$work/job.sh")
  echo "sbatch $work/job.sh: job $job"
  for _ in $(seq 120); do
    squeue -h -j "$job" 2> /dev/null | grep -q . || break
    sleep 1
  done
  cat "$work/job.log"
  "$root/build/glint" render "$root/scenes/showcase.json" -o "$work/one.exr" -q
  cmp "$work/showcase.exr" "$work/one.exr" && echo "srun showcase == single-process render"
  for f in 0 1 2 3; do
    "$root/build/glint" render "$root/tests/mpi/anim4.json" --frames $f -o "$work/one_%04d.exr" -q
    cmp "$work/frames/out_000$f.exr" "$work/one_000$f.exr"
  done
  echo "srun frames 0-3 == single-process renders"
  rm -rf "$work"
}

stop() {
  for pidfile in /run/slurmd.pid /run/slurmctld.pid; do
    [ -e "$pidfile" ] && kill "$(cat "$pidfile")" 2> /dev/null || true
  done
  [ -e /run/munge/munged.pid ] && kill "$(cat /run/munge/munged.pid)" 2> /dev/null || true
}

if [ $# -eq 0 ]; then set -- start demo; fi
for step in "$@"; do
  case $step in
    start | demo | stop) "$step" ;;
    *) echo "usage: scripts/slurm-local.sh [start|demo|stop]" >&2; exit 2 ;;
  esac
done
