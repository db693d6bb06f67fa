#!/usr/bin/env bash
# A one-node Slurm cluster on loopback for tests and demos (docs/slurm.md,
# ../shared/NOTES-SLURM.md): munged, slurmctld and slurmd run as the current
# user under a private folder, no system services, PIDs kept to stop them.
#
#   scripts/slurm-cluster.sh start  [DIR]   start (DIR default: /tmp/hw-slurm-$UID)
#   scripts/slurm-cluster.sh status [DIR]   daemons and sinfo; exit 1 if not up
#   scripts/slurm-cluster.sh env    [DIR]   print "export SLURM_CONF=..." for eval
#   scripts/slurm-cluster.sh stop   [DIR]   scancel everything, wait, stop by PID
# HW_SLURM_PORT=P (start): slurmctld listens on P, slurmd on P+1.
#
# Clients (sbatch, squeue, scontrol, scancel, hybridwalk --slurm) need
# SLURM_CONF: eval "$(scripts/slurm-cluster.sh env DIR)".
# Needs the Debian packages slurmd slurmctld slurm-client munge
# (scripts/setup.sh --test installs them without starting any service).
set -euo pipefail

cmd=${1:-}
dir=${2:-/tmp/hw-slurm-$(id -u)}
conf=$dir/slurm.conf

die() { echo "slurm-cluster: $*" >&2; exit 1; }

alive() { [ -f "$dir/$1.pid" ] && kill -0 "$(cat "$dir/$1.pid")" 2>/dev/null; }

stop_pid() {  # name: TERM, wait up to 10 s, then KILL
  local name=$1 pid
  [ -f "$dir/$name.pid" ] || return 0
  pid=$(cat "$dir/$name.pid")
  if kill -0 "$pid" 2>/dev/null; then
    kill -TERM "$pid" 2>/dev/null || true
    for _ in $(seq 100); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    if kill -0 "$pid" 2>/dev/null; then
      echo "slurm-cluster: $name ($pid) ignored TERM for 10 s, sending KILL" >&2
      kill -KILL "$pid" 2>/dev/null || true
    fi
  fi
  rm -f "$dir/$name.pid"
}

write_conf() {
  local user cpus
  user=$(id -un)
  cpus=$(nproc)
  mkdir -p "$dir/spool/ctld" "$dir/spool/d" "$dir/log" "$dir/munge"
  chmod 0711 "$dir/munge"  # munge's socket folder must be world-executable
  cat > "$conf" <<EOF
# One-node cluster written by scripts/slurm-cluster.sh (Slurm 22.05).
ClusterName=hybridwalk
SlurmctldHost=localhost(127.0.0.1)
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
AuthInfo=socket=$dir/munge/munge.socket
CredType=cred/munge
CommunicationParameters=NoCtldInAddrAny,NoInAddrAny
SlurmctldPort=$(port 0)
SlurmdPort=$(port 1)
StateSaveLocation=$dir/spool/ctld
SlurmdSpoolDir=$dir/spool/d
SlurmctldPidFile=$dir/slurmctld.pidfile
SlurmdPidFile=$dir/slurmd.pidfile
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/backfill
SchedulerParameters=batch_sched_delay=0
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
MailProg=/bin/true
ReturnToService=2
MinJobAge=600
MaxArraySize=10001
NodeName=localhost NodeAddr=127.0.0.1 NodeHostname=localhost CPUs=$cpus State=UNKNOWN
PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP
EOF
}

# Ports: HW_SLURM_PORT and the next one (a test picks its own, so a second
# cluster on the machine does not collide); default derived from the uid.
port() { echo $(( ${HW_SLURM_PORT:-$(( 16817 + ($(id -u) % 500) * 2 ))} + $1 )); }

start() {
  command -v slurmctld >/dev/null && command -v slurmd >/dev/null && command -v munged >/dev/null ||
    die "slurmctld, slurmd or munged not found: run scripts/setup.sh --test (installs slurmd slurmctld slurm-client munge)"
  if alive slurmctld && alive slurmd && alive munged; then
    echo "slurm-cluster: already running in $dir"
    return 0
  fi
  stop_all quiet
  mkdir -p "$dir"
  write_conf
  # munge: its own key (mode 0400), socket, pid and log under $dir.
  if [ ! -f "$dir/munge/munge.key" ]; then
    dd if=/dev/urandom of="$dir/munge/munge.key" bs=1024 count=1 status=none
    chmod 0400 "$dir/munge/munge.key"
  fi
  munged --key-file="$dir/munge/munge.key" --socket="$dir/munge/munge.socket" \
    --pid-file="$dir/munge/munged.pid" --log-file="$dir/log/munged.log" --seed-file="$dir/munge/seed" \
    --force 2>"$dir/log/munged.stderr" || die "munged did not start: $(cat "$dir/log/munged.stderr")"
  for _ in $(seq 50); do [ -s "$dir/munge/munged.pid" ] && break; sleep 0.1; done
  cp "$dir/munge/munged.pid" "$dir/munged.pid"
  export SLURM_CONF=$conf
  slurmctld -D -f "$conf" >"$dir/log/slurmctld.stderr" 2>&1 &
  echo $! > "$dir/slurmctld.pid"
  slurmd -D -N localhost -f "$conf" >"$dir/log/slurmd.stderr" 2>&1 &
  echo $! > "$dir/slurmd.pid"
  # Up when the node is idle (or mixed/allocated) in sinfo.
  local state=""
  for _ in $(seq 150); do
    alive slurmctld || die "slurmctld exited: $(tail -3 "$dir/log/slurmctld.log" 2>/dev/null) $(tail -3 "$dir/log/slurmctld.stderr")"
    alive slurmd || die "slurmd exited: $(tail -3 "$dir/log/slurmd.log" 2>/dev/null) $(tail -3 "$dir/log/slurmd.stderr")"
    state=$(sinfo -h -N -o %t 2>/dev/null | head -1 || true)
    case "$state" in idle*|mix*|alloc*) break ;; esac
    sleep 0.2
  done
  case "$state" in idle*|mix*|alloc*) ;; *) die "node not up after 30 s (state '$state'); logs in $dir/log" ;; esac
  echo "slurm-cluster: up in $dir (node localhost, $(nproc) CPUs, state $state); eval \"\$($0 env $dir)\""
}

stop_all() {
  if [ -f "$conf" ] && alive slurmctld; then
    export SLURM_CONF=$conf
    scancel --user="$(id -un)" 2>/dev/null || true
    # Job steps outlive slurmd: wait for the queue to empty first.
    for _ in $(seq 100); do
      [ -z "$(squeue -h -o %i 2>/dev/null)" ] && break
      sleep 0.2
    done
  fi
  stop_pid slurmd
  stop_pid slurmctld
  stop_pid munged
  [ "${1:-}" = quiet ] || echo "slurm-cluster: stopped ($dir)"
}

case "$cmd" in
  start) start ;;
  stop) stop_all ;;
  env) echo "export SLURM_CONF='$conf'" ;;
  status)
    ok=1
    for d in munged slurmctld slurmd; do
      if alive "$d"; then echo "$d: running (pid $(cat "$dir/$d.pid"))"; else echo "$d: not running"; ok=0; fi
    done
    if [ "$ok" = 1 ]; then SLURM_CONF=$conf sinfo -N -l || ok=0; fi
    [ "$ok" = 1 ] ;;
  *) sed -n '2,15p' "$0" | sed 's/^# \{0,1\}//'; exit 2 ;;
esac
