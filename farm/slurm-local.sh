#!/bin/bash
# A single-node Slurm cluster on this machine, for lgh's farm test and for trying the farm
# recipe (docs/farm.md): Debian's slurm-wlm and munge, every file of the
# cluster under DIR, nothing in /etc touched.
#
#   farm/slurm-local.sh start DIR   # prints the line to source: export SLURM_CONF=DIR/slurm.conf
#   farm/slurm-local.sh stop DIR
#
# Needs root (slurmd runs the jobs as their user, and munged keeps its key private).
set -euo pipefail
cmd=${1:-} dir=${2:-}
if [ -z "$cmd" ] || [ -z "$dir" ]; then
    echo "usage: $0 start|stop DIR" >&2
    exit 2
fi
if [ "$cmd" = start ]; then mkdir -p "$dir"; fi
[ -d "$dir" ] && dir=$(cd "$dir" && pwd)
conf=$dir/slurm.conf

stop() {
    [ -d "$dir" ] || return 0
    # By the daemons' pid files, then anything still running from this folder's config (a
    # fixed string, not a pattern), SIGKILL after 10 s.
    local pids=""
    for d in slurmd slurmctld munged; do
        [ -f "$dir/$d.pid" ] && pids="$pids $(cat "$dir/$d.pid")"
    done
    for p in /proc/[0-9]*; do
        # Not this script (its own command line may name the folder).
        [ "${p#/proc/}" = "$$" ] && continue
        if tr '\0' ' ' < "$p/cmdline" 2>/dev/null | grep -qF -- "$dir/"; then
            pids="$pids ${p#/proc/}"
        fi
    done
    [ -n "$pids" ] && kill $pids 2>/dev/null || true
    for _ in $(seq 50); do
        alive=""
        for p in $pids; do kill -0 "$p" 2>/dev/null && alive="$alive $p"; done
        [ -z "$alive" ] && break
        sleep 0.2
    done
    [ -n "${alive:-}" ] && kill -9 $alive 2>/dev/null || true
    rm -f "$dir"/*.pid
}

case $cmd in
stop)
    stop
    exit 0
    ;;
start) ;;
*)
    echo "usage: $0 start|stop DIR" >&2
    exit 2
    ;;
esac

for tool in munged slurmctld slurmd sbatch; do
    if ! command -v "$tool" >/dev/null && [ ! -x "/usr/sbin/$tool" ]; then
        echo "$tool is missing: apt-get install slurm-wlm munge" >&2
        exit 1
    fi
done
export PATH=$PATH:/usr/sbin
host=$(hostname -s)
cpus=$(nproc)
mem=$(( $(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 * 9 / 10 ))
mkdir -p "$dir/state" "$dir/spool" "$dir/munge"

# munge: its own key and socket here (the package's key may be missing or unreadable).
if [ ! -f "$dir/munge/munge.key" ]; then
    dd if=/dev/urandom bs=1 count=1024 of="$dir/munge/munge.key" status=none
fi

chmod 400 "$dir/munge/munge.key"
cat > "$conf" <<CONF
ClusterName=lghfarm
SlurmctldHost=$host
AuthType=auth/munge
AuthInfo=socket=$dir/munge/munge.sock
CredType=cred/munge
SlurmUser=root
SlurmdUser=root
SlurmctldPort=$((6817 + RANDOM % 1000 * 2))
SlurmdPort=$((6818 + RANDOM % 1000 * 2))
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
SwitchType=switch/none
MpiDefault=none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
SlurmdTimeout=30
NodeName=$host CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=lgh Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
stop
munged --socket="$dir/munge/munge.sock" --key-file="$dir/munge/munge.key" \
    --pid-file="$dir/munged.pid" --log-file="$dir/munge/munged.log" \
    --seed-file="$dir/munge/munge.seed" --force
export SLURM_CONF=$conf
slurmctld -f "$conf"
slurmd -f "$conf"
# Up when the node takes jobs (at most 30 s).
for _ in $(seq 150); do
    state=$(sinfo -h -o %t 2>/dev/null || true)
    # "idle*" (with the star) is a node that does not respond.
    case $state in
    idle | mix | alloc)
        echo "export SLURM_CONF=$conf"
        exit 0
        ;;
    esac
    sleep 0.2
done
echo "the Slurm node did not come up; its logs:" >&2
tail -n 20 "$dir/slurmctld.log" "$dir/slurmd.log" >&2 || true
stop
exit 1
