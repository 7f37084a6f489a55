#!/usr/bin/env bash
# A single-node Slurm cluster on this machine for the tests, all of it in one folder:
#   single_node_cluster.sh start DIR [PID]
#                                      writes DIR/slurm.conf, starts slurmctld and slurmd, waits (bounded)
#                                      until the node is idle; exit 0 when the cluster takes jobs,
#                                      77 when the daemons cannot start here (the test is then skipped).
#                                      With PID (the test's), a watchdog stops the cluster when that
#                                      process ends without stopping it (killed on a CTest timeout).
#   single_node_cluster.sh stop DIR    stops both daemons (by the pids they wrote into DIR)
# Jobs are submitted with SLURM_CONF=DIR/slurm.conf. Authentication is auth/none and cred/none (Slurm 22.05
# ships both): nothing but this machine's 127.0.0.1 is ever contacted, and no munge key is needed.
set -uo pipefail

action=${1:?start or stop}
folder=${2:?folder}
mkdir -p "$folder"
folder=$(cd "$folder" && pwd)

stop() {
  # Jobs first: their processes (under slurmstepd) would outlive the daemons.
  if [ -f "$folder/slurm.conf" ] && [ -f "$folder/slurmctld.pid" ]; then
    SLURM_CONF=$folder/slurm.conf timeout 10 scancel --user="$(id -un)" 2>/dev/null
    for _ in $(seq 25); do
      [ -z "$(SLURM_CONF=$folder/slurm.conf timeout 5 squeue -h 2>/dev/null)" ] && break
      sleep 0.2
    done
  fi
  for daemon in slurmd slurmctld; do
    if [ -f "$folder/$daemon.pid" ]; then
      pid=$(cat "$folder/$daemon.pid")
      kill "$pid" 2>/dev/null
      for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
      kill -9 "$pid" 2>/dev/null
      rm -f "$folder/$daemon.pid"
    fi
  done
}

# A port of 127.0.0.1 that nothing listens on (a refused connection), drawn at random above the usual ones.
free_port() {
  local port
  for _ in $(seq 50); do
    port=$(( 20000 + RANDOM % 30000 ))
    if ! (exec 3<>"/dev/tcp/127.0.0.1/$port") 2>/dev/null; then
      echo "$port"
      return
    fi
  done
  echo 0
}

if [ "$action" = stop ]; then
  stop
  exit 0
fi

for program in slurmctld slurmd sbatch squeue sinfo; do
  if ! command -v "$program" >/dev/null; then
    echo "single_node_cluster: $program is not installed (scripts/setup.sh installs slurm-wlm)" >&2
    exit 77
  fi
done
plugins=$(dirname "$(find /usr/lib -name auth_none.so -path '*slurm*' 2>/dev/null | head -1)")
if [ ! -f "$plugins/auth_none.so" ] || [ ! -f "$plugins/cred_none.so" ]; then
  echo "single_node_cluster: this Slurm has no auth/none and cred/none plugins" >&2
  exit 77
fi

node=$(hostname -s)
cpus=$(nproc)
memory=$(( $(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 / 2 ))
mkdir -p "$folder/state" "$folder/spool" "$folder/log"
export SLURM_CONF=$folder/slurm.conf

# Starts both daemons on two free ports; 0 once the node is idle, within 30 s. Two attempts: a port found
# free may be taken by another program before slurmctld binds it.
start_daemons() {
  local controller_port node_port state
  controller_port=$(free_port)
  node_port=$(free_port)
  while [ "$node_port" = "$controller_port" ]; do node_port=$(free_port); done
  cat > "$SLURM_CONF" <<CONF
ClusterName=causticbench-test
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$controller_port
SlurmdPort=$node_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/none
CredType=cred/none
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
ReturnToService=2
StateSaveLocation=$folder/state
SlurmdSpoolDir=$folder/spool
SlurmctldPidFile=$folder/slurmctld.pid
SlurmdPidFile=$folder/slurmd.pid
SlurmctldLogFile=$folder/log/slurmctld.log
SlurmdLogFile=$folder/log/slurmd.log
SlurmctldTimeout=30
SlurmdTimeout=30
MinJobAge=600
SchedulerType=sched/backfill
NodeName=$node NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$memory State=UNKNOWN
PartitionName=test Nodes=$node Default=YES MaxTime=INFINITE State=UP
CONF
  slurmctld -D -i -f "$SLURM_CONF" >>"$folder/log/slurmctld.out" 2>&1 &
  echo $! > "$folder/slurmctld.pid"
  slurmd -D -f "$SLURM_CONF" -N "$node" >>"$folder/log/slurmd.out" 2>&1 &
  echo $! > "$folder/slurmd.pid"
  for _ in $(seq 150); do
    state=$(sinfo -h -N -o '%T' 2>/dev/null | head -1)
    if [ "$state" = idle ]; then
      echo "single_node_cluster: node $node idle (controller 127.0.0.1:$controller_port, slurmd :$node_port)"
      return 0
    fi
    sleep 0.2
  done
  echo "single_node_cluster: the node did not become idle in 30 s (state '${state:-none}')" >&2
  stop
  return 1
}

watch_owner() {
  local owner=$1
  while kill -0 "$owner" 2>/dev/null && [ -f "$folder/slurmctld.pid" ]; do sleep 1; done
  stop
}

for attempt in 1 2; do
  if start_daemons; then
    if [ -n "${3:-}" ]; then
      # Detached from the caller's output, which it would otherwise keep open.
      watch_owner "$3" </dev/null >/dev/null 2>&1 &
      disown
    fi
    exit 0
  fi
done
echo "single_node_cluster: the daemons did not start; logs:" >&2
tail -n 20 "$folder/log/"*.log "$folder/log/"*.out >&2 2>/dev/null
stop
exit 77
