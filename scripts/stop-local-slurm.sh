#!/bin/bash
# stop-local-slurm.sh - stop what scripts/start-local-slurm.sh started, by pid files.
# Cancels all jobs first (slurmstepd and the job's processes outlive a killed slurmd),
# then stops slurmd, slurmctld, slurmdbd, and munged / mariadbd only if
# start-local-slurm.sh started them (marker files in /run/local-slurm).
set -uo pipefail

MARK=/run/local-slurm
log() { echo "stop-local-slurm: $*"; }
# an exited but not yet reaped process (zombie) counts as gone; PID 1 in this
# sandbox reaps orphans only every ~2 s, so plain 'kill -0' would wait for that
running() { local s; s=$(ps -o stat= -p "$1" 2>/dev/null) || return 1; [[ $s != Z* ]]; }
alive() { [ -s "$1" ] && running "$(cat "$1")"; }

stop_pidfile() {  # name pidfile
  local name=$1 pf=$2 pid
  if ! alive "$pf"; then log "$name not running"; rm -f "$pf"; return 0; fi
  pid=$(cat "$pf")
  kill -TERM "$pid"
  for _ in $(seq 150); do running "$pid" || break; sleep 0.1; done
  if running "$pid"; then log "$name ($pid) still alive after 15 s, SIGKILL"; kill -KILL "$pid"; fi
  rm -f "$pf"
  log "$name ($pid) stopped"
}

# 1. cancel every job while the controller is still up, and wait for them to go
if alive /run/slurmctld.pid; then
  jobs=$(squeue -h -o %A 2>/dev/null | sort -u)
  if [ -n "$jobs" ]; then
    log "cancelling jobs: $(echo "$jobs" | tr "\n" " ")"
    # shellcheck disable=SC2086
    scancel $jobs
    for _ in $(seq 100); do [ -z "$(squeue -h 2>/dev/null)" ] && break; sleep 0.1; done
  fi
fi

# 2. daemons, compute side first
stop_pidfile slurmd /run/slurmd.pid
stop_pidfile slurmctld /run/slurmctld.pid
[ -e "$MARK/slurmdbd" ] && stop_pidfile slurmdbd /run/slurmdbd.pid
[ -e "$MARK/mariadbd" ] && stop_pidfile mariadbd /run/mysqld/mysqld.pid
if [ -e "$MARK/munged" ]; then
  stop_pidfile munged /run/munge/munged.pid
else
  log "munged left alone (not started by start-local-slurm.sh)"
fi
rm -rf "$MARK"

# slurmstepd of just-finished tasks may need a moment to exit
for _ in $(seq 50); do pgrep -x slurmstepd >/dev/null || break; sleep 0.1; done
left=$(pgrep -x slurmstepd | tr '\n' ' ')
[ -z "$left" ] || log "warning: slurmstepd processes still running: $left"
exit 0
