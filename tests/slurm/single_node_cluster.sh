#!/bin/bash
# A one-node Slurm cluster for tests (facts in ../shared/notes/slurm-single-node.md): munged,
# slurmctld and slurmd on this machine, configured in DIR, without systemd.
#
#   single_node_cluster.sh start DIR   # then: SLURM_CONF=DIR/slurm.conf sbatch ...
#   single_node_cluster.sh stop DIR    # kills what start started, by the pids it recorded
set -euo pipefail
export PATH="$PATH:/usr/sbin:/sbin"
cmd=$1
dir=$(mkdir -p "$2" && cd "$2" && pwd)

stop() {
    for name in slurmd slurmctld munged; do
        if [ -f "$dir/$name.pid" ]; then
            pid=$(cat "$dir/$name.pid")
            kill "$pid" 2>/dev/null || true
            for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
            rm -f "$dir/$name.pid"
        fi
    done
}

case $cmd in
start)
    host=$(hostname -s)
    mem=$(awk '/MemTotal/ { print int($2 / 1024) - 1024 }' /proc/meminfo)
    mkdir -p "$dir/state" "$dir/spool" "$dir/log"
    cat > "$dir/slurm.conf" <<CONF
ClusterName=pathlabtest
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
ReturnToService=2
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
NodeName=$host CPUs=$(nproc) RealMemory=$mem State=UNKNOWN
PartitionName=main Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
    printf 'CgroupPlugin=cgroup/v1\nIgnoreSystemd=yes\n' > "$dir/cgroup.conf"
    # munge: start our own unless one already answers (then it is not ours to stop).
    if ! (munge -n | unmunge) >/dev/null 2>&1; then
        [ -f /etc/munge/munge.key ] || mungekey -c
        mkdir -p /run/munge
        chown munge:munge /run/munge /etc/munge/munge.key
        runuser -u munge -- /usr/sbin/munged
        for _ in $(seq 50); do (munge -n | unmunge) >/dev/null 2>&1 && break; sleep 0.1; done
        cp /run/munge/munged.pid "$dir/munged.pid"
    fi
    slurmctld -f "$dir/slurm.conf"
    slurmd -f "$dir/slurm.conf"
    export SLURM_CONF="$dir/slurm.conf"
    for _ in $(seq 120); do
        state=$(sinfo -h -o %T 2>/dev/null || true)
        case $state in idle*) echo "slurm: node $host $state"; exit 0 ;; esac
        sleep 0.5
    done
    echo "slurm: the node did not come up; logs in $dir/log" >&2
    tail -n 20 "$dir/log/"*.log >&2 || true
    stop
    exit 1
    ;;
stop)
    stop
    ;;
*)
    echo "usage: $0 start|stop DIR" >&2
    exit 2
    ;;
esac
