#!/usr/bin/env bash
# A single-node Slurm cluster on this machine, for tests and trials of
# `sylva batch --engine snakemake --profile slurm`: munged, slurmctld and
# slurmd (Debian's munge and slurm-wlm) on localhost, with their own
# configuration, munge key, state, spool and logs in DIR and their own ports,
# so they touch nothing of a Slurm or munge the machine may already run. No
# systemd: the daemons are started and stopped by pid. Jobs run as the user
# who started the cluster (run it as root to be like a real cluster).
#
#   scripts/local-slurm.sh start  [DIR]   start (DIR: default build/local-slurm)
#   scripts/local-slurm.sh status [DIR]   sinfo and squeue; exit 1 if not running
#   scripts/local-slurm.sh stop   [DIR]   cancel the jobs, stop the daemons
#
# Then, to use it: export SLURM_CONF=DIR/etc/slurm.conf (start prints it).
# No accounting database: sacct says "accounting storage is disabled" (and
# Snakemake asks scontrol instead); finished jobs stay in `scontrol show job`
# for MinJobAge (10 minutes) and are listed in DIR/log/jobcomp.txt.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
COMMAND="${1:-}"
DIR="${2:-$ROOT/build/local-slurm}"
mkdir -p "$DIR"
DIR="$(cd "$DIR" && pwd)"
CONF="$DIR/etc/slurm.conf"
SOCKET="$DIR/munge/munge.socket"
NODE=localhost
export PATH="$PATH:/usr/sbin"

log() { printf 'local-slurm: %s\n' "$*" >&2; }
die() {
  log "$*"
  exit 1
}

# Sends TERM to the process in pid file $1 (if it runs), KILL after 10 s.
stop_pid_file() {
  local file="$1" pid
  [ -s "$file" ] || return 0
  pid="$(cat "$file")"
  if kill -0 "$pid" 2>/dev/null; then
    kill -TERM "$pid" 2>/dev/null || true
    for _ in $(seq 100); do
      kill -0 "$pid" 2>/dev/null || break
      sleep 0.1
    done
    kill -0 "$pid" 2>/dev/null && kill -KILL "$pid" 2>/dev/null || true
  fi
  rm -f "$file"
}

running() { [ -s "$DIR/slurmctld.pid" ] && kill -0 "$(cat "$DIR/slurmctld.pid")" 2>/dev/null; }

# Two free TCP ports on localhost (for slurmctld and slurmd).
free_ports() {
  /usr/bin/python3 - <<'EOF'
import socket
socks = [socket.socket() for _ in range(2)]
for s in socks:
    s.bind(("127.0.0.1", 0))
print(" ".join(str(s.getsockname()[1]) for s in socks))
EOF
}

# Shows the logs, stops what did start, and exits 1 with message $1.
fail() {
  show_logs
  stop_daemons
  die "$*"
}

show_logs() {
  local file
  for file in "$DIR"/log/*.log "$DIR"/log/*.out; do
    [ -f "$file" ] || continue
    log "--- $file"
    tail -n 15 "$file" >&2
  done
}

start() {
  local missing=() program
  for program in munged munge slurmctld slurmd sinfo srun sbatch scontrol; do
    command -v "$program" >/dev/null || missing+=("$program")
  done
  [ ${#missing[@]} -eq 0 ] || die "not installed: ${missing[*]} (apt-get install slurm-wlm munge)"
  if running; then
    log "already running"
    echo "export SLURM_CONF=$CONF"
    return 0
  fi
  stop_daemons
  rm -rf "$DIR/etc" "$DIR/state" "$DIR/spool" "$DIR/log" "$DIR/munge"
  mkdir -p "$DIR/etc" "$DIR/state" "$DIR/spool" "$DIR/log" "$DIR/munge"
  # munged wants its key private and its socket's folder open to all.
  chmod 755 "$DIR" "$DIR/munge"
  (umask 077 && head -c 1024 /dev/urandom >"$DIR/munge/munge.key")
  chmod 400 "$DIR/munge/munge.key"

  local user ports ctld_port slurmd_port cpus memory
  user="$(id -un)"
  read -r ctld_port slurmd_port <<<"$(free_ports)"
  cpus="$(nproc)"
  # Half the memory, at most 8 GB: enough for the profile's mem_mb=4000.
  memory=$(awk '/^MemTotal:/ { m = int($2 / 1024 / 2); print (m > 8192 ? 8192 : m) }' /proc/meminfo)
  cat >"$CONF" <<EOF
# Written by scripts/local-slurm.sh: a one-node cluster on localhost.
ClusterName=sylvalocal
SlurmctldHost=$NODE
SlurmUser=$user
SlurmdUser=$user
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
AuthType=auth/munge
AuthInfo=socket=$SOCKET
CredType=cred/munge
StateSaveLocation=$DIR/state
SlurmdSpoolDir=$DIR/spool
SlurmctldPidFile=$DIR/slurmctld.pid
SlurmdPidFile=$DIR/slurmd.pid
SlurmctldLogFile=$DIR/log/slurmctld.log
SlurmdLogFile=$DIR/log/slurmd.log
# No cgroups (containers without systemd): processes are tracked by their
# parent, tasks are not bound to CPUs.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/filetxt
JobCompLoc=$DIR/log/jobcomp.txt
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU_Memory
SchedulerType=sched/backfill
MpiDefault=none
MailProg=/bin/true
ReturnToService=2
MinJobAge=600
SlurmctldTimeout=30
SlurmdTimeout=30
NodeName=$NODE NodeHostname=$(hostname -s) NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$memory State=UNKNOWN
PartitionName=local Nodes=$NODE Default=YES MaxTime=INFINITE State=UP
EOF
  export SLURM_CONF="$CONF"

  log "starting munged, slurmctld, slurmd in $DIR (ports $ctld_port, $slurmd_port, $cpus CPUs, ${memory} MB)"
  munged --force --socket="$SOCKET" --key-file="$DIR/munge/munge.key" \
    --log-file="$DIR/log/munged.log" --pid-file="$DIR/munged.pid" \
    --seed-file="$DIR/munge/munged.seed" || fail "munged did not start"
  munge -S "$SOCKET" -n | unmunge -S "$SOCKET" >/dev/null \
    || fail "munge cannot encode and decode a credential"
  # Both daemons go to the background themselves and write their pid files.
  slurmctld -f "$CONF" </dev/null >>"$DIR/log/slurmctld.out" 2>&1 \
    || fail "slurmctld did not start"
  slurmd -f "$CONF" -N "$NODE" </dev/null >>"$DIR/log/slurmd.out" 2>&1 \
    || fail "slurmd did not start"
  local state=""
  for _ in $(seq 300); do
    state="$(sinfo -h -n "$NODE" -o %T 2>/dev/null || true)"
    [ "$state" = idle ] && break
    sleep 0.1
  done
  [ "$state" = idle ] || fail "the node is not idle after 30 s (state '${state:-none}')"
  local answer
  answer="$(timeout 60 srun -t 1 -n 1 hostname 2>&1)" || fail "srun hostname failed: $answer"
  log "running: srun ran on $answer"
  echo "export SLURM_CONF=$CONF"
}

stop_daemons() {
  if running && [ -f "$CONF" ]; then
    # Jobs first: slurmstepd outlives slurmd.
    SLURM_CONF="$CONF" scancel --full --quiet --user="$(id -un)" 2>/dev/null || true
    for _ in $(seq 100); do
      [ -z "$(SLURM_CONF="$CONF" squeue -h -o %i 2>/dev/null)" ] && break
      sleep 0.1
    done
  fi
  stop_pid_file "$DIR/slurmd.pid"
  stop_pid_file "$DIR/slurmctld.pid"
  stop_pid_file "$DIR/munged.pid"
}

case "$COMMAND" in
  start) start ;;
  stop)
    stop_daemons
    log "stopped ($DIR)"
    ;;
  status)
    running || die "not running ($DIR)"
    export SLURM_CONF="$CONF"
    sinfo
    squeue
    ;;
  *) die "usage: $0 start|stop|status [DIR]" ;;
esac
