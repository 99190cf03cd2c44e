#!/bin/bash
# start-local-slurm.sh - bring up a real single-node SLURM cluster on this machine
# (munged + slurmctld + slurmd on localhost, optionally slurmdbd + MariaDB for sacct),
# for the tests of demsa's SLURM executor (ctest -L slurm) and for trying it by hand.
#
# Works on Debian 12 (bookworm), slurm 22.05, munge 0.5.15, MariaDB 10.11, as root, without
# systemd (daemons are started directly and tracked by pid files).
#
# Usage:  scripts/start-local-slurm.sh        (as root; stop with scripts/stop-local-slurm.sh)
# Then:   sinfo; squeue; demsa run STUDY.toml   (with [run] executor = "slurm")
# Env:
#   SLURM_SKIP_INSTALL=1   do not run apt-get (packages already installed)
#   SLURM_WITH_DBD=1       also install/start MariaDB + slurmdbd so that 'sacct' works
#                          (without it: accounting_storage/none, 'sacct' says disabled)
#   SLURM_CPUS=N           CPUs to declare for the node (default: nproc).
#                          N > real CPUs is allowed (SlurmdParameters=config_overrides).
#   SLURM_WAIT_S=60        how long to wait for the node to become idle
#   SLURM_KEEP_STATE=1     keep slurmctld state / accounting DB from an earlier run
#                          (default: wipe, so job ids start at 1 again)
set -euo pipefail

[ "$(id -u)" = 0 ] || { echo "start-local-slurm: must run as root" >&2; exit 1; }

SLURM_CPUS=${SLURM_CPUS:-$(nproc)}
SLURM_WAIT_S=${SLURM_WAIT_S:-60}
WITH_DBD=${SLURM_WITH_DBD:-0}
CONF=/etc/slurm/slurm.conf
STATE=/var/spool/slurmctld
SPOOL=/var/spool/slurmd
LOGDIR=/var/log/slurm
MARK=/run/local-slurm      # records what this script started (read by stop-local-slurm.sh)
T0=$(date +%s.%N)

log() { echo "start-local-slurm: $*"; }
# an exited but not yet reaped process (zombie) counts as not running
running() { local s; s=$(ps -o stat= -p "$1" 2>/dev/null) || return 1; [[ $s != Z* ]]; }
alive() { [ -s "$1" ] && running "$(cat "$1")"; }
elapsed() { awk -v a="$T0" -v b="$(date +%s.%N)" 'BEGIN{printf "%.1f", b-a}'; }

# ---------------------------------------------------------------- packages
if [ "${SLURM_SKIP_INSTALL:-0}" != 1 ]; then
  pkgs=""
  for c in slurmctld:slurmctld slurmd:slurmd sbatch:slurm-client munged:munge; do
    command -v "${c%%:*}" >/dev/null || pkgs="$pkgs ${c#*:}"
  done
  if [ "$WITH_DBD" = 1 ]; then
    command -v slurmdbd >/dev/null || pkgs="$pkgs slurmdbd"
    command -v mariadbd >/dev/null || pkgs="$pkgs mariadb-server"
  fi
  if [ -n "$pkgs" ]; then
    log "installing:$pkgs"
    export DEBIAN_FRONTEND=noninteractive
    # Lock::Timeout: wait (instead of failing) if another apt/dpkg is running
    apt-get update -qq -o DPkg::Lock::Timeout=300
    # shellcheck disable=SC2086
    apt-get install -y -qq -o DPkg::Lock::Timeout=300 --no-install-recommends $pkgs >/dev/null
    log "packages installed after $(elapsed) s"
  fi
fi

# ---------------------------------------------------------------- already up?
if alive /run/slurmctld.pid && alive /run/slurmd.pid \
   && [ "$(sinfo -h -n localhost -o %T 2>/dev/null)" = idle ] \
   && { [ "$WITH_DBD" != 1 ] || alive /run/slurmdbd.pid; }; then
  log "already running, node idle"; exit 0
fi

mkdir -p "$MARK"

# ---------------------------------------------------------------- munge
# The Debian postinst creates /etc/munge/munge.key (munge:munge 0600); re-create if missing.
# munged refuses to start if the key is group/other-readable or not owned by its user,
# and if /run/munge (a tmpfs dir normally made by systemd) does not exist.
install -d -o munge -g munge -m 0700 /etc/munge /var/log/munge
install -d -o munge -g munge -m 0711 /var/lib/munge
install -d -o munge -g munge -m 0755 /run/munge
if [ ! -s /etc/munge/munge.key ]; then
  log "creating munge key"
  dd if=/dev/urandom of=/etc/munge/munge.key bs=1024 count=1 status=none
fi
chown munge:munge /etc/munge/munge.key
chmod 0600 /etc/munge/munge.key
if munge -n 2>/dev/null | unmunge >/dev/null 2>&1; then
  log "munged already running (not started by this script)"
else
  runuser -u munge -- /usr/sbin/munged     # as its own user: files belong to munge
  touch "$MARK/munged"
  for _ in $(seq 50); do munge -n 2>/dev/null | unmunge >/dev/null 2>&1 && break; sleep 0.1; done
  munge -n | unmunge >/dev/null || { echo "munged not working" >&2; tail /var/log/munge/munged.log >&2; exit 1; }
fi

# ---------------------------------------------------------------- slurm.conf
MEM_MB=$(free -m | awk '/^Mem:/{print $2}')
mkdir -p /etc/slurm "$STATE" "$SPOOL" "$LOGDIR"
[ "${SLURM_KEEP_STATE:-0}" = 1 ] || rm -rf "${STATE:?}"/* "${SPOOL:?}"/*
if [ "$WITH_DBD" = 1 ]; then
  ACCT="AccountingStorageType=accounting_storage/slurmdbd
AccountingStorageHost=localhost
JobAcctGatherType=jobacct_gather/linux"
else
  ACCT="AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none"
fi
cat > "$CONF" <<EOF
# written by start-local-slurm.sh
ClusterName=localcluster
SlurmctldHost=localhost(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
SlurmctldPort=6817
SlurmdPort=6818
StateSaveLocation=$STATE
SlurmdSpoolDir=$SPOOL
SlurmctldPidFile=/run/slurmctld.pid
SlurmdPidFile=/run/slurmd.pid
SlurmctldLogFile=$LOGDIR/slurmctld.log
SlurmdLogFile=$LOGDIR/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
MailProg=/bin/true
ReturnToService=2
MpiDefault=none
# no cgroups: plain process tracking, no CPU binding / memory confinement
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
# accept the CPUs/RealMemory below even if they exceed the hardware
SlurmdParameters=config_overrides
SchedulerType=sched/backfill
# batch_sched_delay=0: with the default (3 s) a freed CPU got its next array task
# only ~3 s later; with 0, ~1 s later (50 tiny tasks on 2 CPUs: 65 s -> 21-24 s)
SchedulerParameters=batch_sched_delay=0
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
$ACCT
# completion records also go to a text file (readable with 'sacct -c' or by parsing)
JobCompType=jobcomp/filetxt
JobCompLoc=$LOGDIR/jobcomp.log
# keep finished jobs visible to 'squeue -t all' / 'scontrol show job' for 1 h (default 300 s)
MinJobAge=3600
NodeName=localhost NodeAddr=127.0.0.1 CPUs=$SLURM_CPUS RealMemory=$MEM_MB State=UNKNOWN
PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP
EOF

# ---------------------------------------------------------------- optional: MariaDB + slurmdbd
if [ "$WITH_DBD" = 1 ]; then
  install -d -o mysql -g mysql -m 0755 /run/mysqld
  if ! mariadb -e 'select 1' >/dev/null 2>&1; then
    # Debian's postinst has already initialised /var/lib/mysql
    setsid /usr/sbin/mariadbd --user=mysql --pid-file=/run/mysqld/mysqld.pid \
      --socket=/run/mysqld/mysqld.sock --bind-address=127.0.0.1 \
      >>"$LOGDIR/mariadb.log" 2>&1 < /dev/null &
    touch "$MARK/mariadbd"
    for _ in $(seq 150); do mariadb -e 'select 1' >/dev/null 2>&1 && break; sleep 0.2; done
    mariadb -e 'select 1' >/dev/null || { echo "mariadb did not start" >&2; tail "$LOGDIR/mariadb.log" >&2; exit 1; }
  fi
  # a fresh slurmctld state restarts job ids at 1: drop old accounting too, or sacct -j mixes runs
  [ "${SLURM_KEEP_STATE:-0}" = 1 ] || mariadb -e 'DROP DATABASE IF EXISTS slurm_acct_db'
  mariadb -e "CREATE USER IF NOT EXISTS 'slurm'@'localhost' IDENTIFIED BY 'slurm';
              GRANT ALL ON slurm_acct_db.* TO 'slurm'@'localhost';"
  cat > /etc/slurm/slurmdbd.conf <<EOF
AuthType=auth/munge
DbdHost=localhost
DbdPort=6819
SlurmUser=root
LogFile=$LOGDIR/slurmdbd.log
PidFile=/run/slurmdbd.pid
StorageType=accounting_storage/mysql
StorageHost=localhost
StorageUser=slurm
StoragePass=slurm
StorageLoc=slurm_acct_db
EOF
  chmod 0600 /etc/slurm/slurmdbd.conf        # slurmdbd refuses a readable slurmdbd.conf
  alive /run/slurmdbd.pid || slurmdbd
  touch "$MARK/slurmdbd"
  for _ in $(seq 150); do sacctmgr -n list cluster >/dev/null 2>&1 && break; sleep 0.2; done
  sacctmgr -n list cluster >/dev/null || { echo "slurmdbd not answering" >&2; tail "$LOGDIR/slurmdbd.log" >&2; exit 1; }
  # slurmctld registers the cluster in the DB by itself on start
else
  rm -f /etc/slurm/slurmdbd.conf
fi

# ---------------------------------------------------------------- slurmctld + slurmd
# Without systemd: both daemons fork into the background and write their pid files.
alive /run/slurmctld.pid || slurmctld
touch "$MARK/slurmctld"
# -N localhost: the node is called localhost whatever this machine's hostname is
alive /run/slurmd.pid || slurmd -N localhost
touch "$MARK/slurmd"

# ---------------------------------------------------------------- wait for idle
state=""
end=$(( $(date +%s) + SLURM_WAIT_S ))
while [ "$(date +%s)" -lt "$end" ]; do
  state=$(sinfo -h -n localhost -o %T 2>/dev/null || true)
  [ "$state" = idle ] && break
  sleep 0.2
done
if [ "$state" != idle ]; then
  echo "start-local-slurm: node not idle after ${SLURM_WAIT_S}s (state='$state')" >&2
  sinfo -R >&2 || true
  tail -20 "$LOGDIR/slurmctld.log" "$LOGDIR/slurmd.log" >&2 || true
  exit 1
fi
log "node localhost idle (CPUs=$SLURM_CPUS RealMemory=${MEM_MB}M$([ "$WITH_DBD" = 1 ] && echo ", slurmdbd")) after $(elapsed) s"
