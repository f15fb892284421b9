#!/usr/bin/env bash
# A single-host SLURM cluster for trying the batch recipes for real (docs/slurm.md): installs
# Debian's slurm-wlm and munge when missing, then starts munged, slurmctld and one slurmd
# named `localhost` on this machine (loopback only, every file under one folder, no system
# configuration touched). Usage:
#   scripts/local_slurm.sh start DIR   # writes DIR/slurm.conf and DIR/env; prints `source DIR/env`
#   scripts/local_slurm.sh stop DIR    # ends the daemons it started, by the ids in their pid files
# After `source DIR/env`, sbatch, squeue, scancel and scontrol talk to this cluster.
set -euo pipefail
cmd=${1:?usage: local_slurm.sh start|stop DIR}
work=${2:?usage: local_slurm.sh start|stop DIR}

stop() {
    for d in slurmd slurmctld munged; do
        [ -s "$work/$d.pid" ] || continue
        pid=$(cat "$work/$d.pid")
        kill "$pid" 2>/dev/null || continue
        for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.2; done
    done
}

case $cmd in
stop)
    stop
    exit 0
    ;;
start) ;;
*)
    echo "usage: local_slurm.sh start|stop DIR" >&2
    exit 2
    ;;
esac

if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then
    echo "== installing slurm-wlm and munge" >&2
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq slurm-wlm munge >/dev/null
fi
mkdir -p "$work/state" "$work/spool"
chmod 700 "$work"
dd if=/dev/urandom of="$work/munge.key" bs=1024 count=1 status=none
chmod 400 "$work/munge.key"
munged --force --key-file="$work/munge.key" --socket="$work/munge.socket" \
    --pid-file="$work/munged.pid" --log-file="$work/munged.log" --seed-file="$work/munge.seed"

cpus=$(nproc)
cat >"$work/slurm.conf" <<CONF
ClusterName=suspflow-local
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=6817
SlurmdPort=6818
SlurmUser=root
AuthType=auth/munge
AuthInfo=socket=$work/munge.socket
CredType=cred/munge
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SwitchType=switch/none
MpiDefault=none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
# A node set DOWN comes back when told to (scontrol update ... State=RESUME).
ReturnToService=2
# Requeued jobs (a node failure, or scontrol requeue) run again; a job's steps get
# KillWait seconds between SIGTERM and SIGKILL.
JobRequeue=1
KillWait=10
# Time limits and the --signal before them are checked every few seconds, not every minute.
MessageTimeout=5
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
NodeName=localhost NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=local Nodes=localhost Default=YES MaxTime=30 State=UP
CONF
echo "export SLURM_CONF=$work/slurm.conf" >"$work/env"
export SLURM_CONF=$work/slurm.conf
slurmctld
slurmd -N localhost
for _ in $(seq 60); do
    sinfo -h -o %T 2>/dev/null | grep -q idle && break
    sleep 1
done
echo "== single-host SLURM in $work ($(slurmctld -V), $(munged -V | head -1)); source $work/env" >&2
sinfo
