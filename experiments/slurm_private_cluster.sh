#!/usr/bin/env bash
# A private single-node Slurm cluster for the length of one command: munged, slurmctld and
# slurmd on 127.0.0.1 on free ports, their config, state, logs, munge socket and key in one fresh
# temp folder; the command runs with SLURM_CONF pointing at it, so sbatch, squeue and
# `gibench sweep --backend slurm` inside it reach this cluster and nothing else. Afterwards every
# job is cancelled, every daemon, step and job it started is stopped and checked gone, and the
# folder is removed, whatever happened (trap). For trying the Slurm backend on one machine and for
# tests/slurm/slurm_roundtrip.sh; docs/slurm.md, the facts it relies on: ../shared/SLURM_NOTES.md.
#
#   experiments/slurm_private_cluster.sh COMMAND [ARG...]
#   e.g. experiments/slurm_private_cluster.sh experiments/paper.sh --backend slurm
#
# The node offers every core and the machine's memory less 1 GiB. Installs slurmctld slurmd
# slurm-client munge when missing (as root, with their daemons kept from starting). Exit status:
# the command's; 1 when the cluster fails or leaves a process behind; 77 (with the reason) when
# no cluster can be started here: the packages cannot be installed, or the hostname does not
# resolve to a 127.x address (Slurm binds to it).
set -euo pipefail
now_ms() { echo $(( $(date +%s%N) / 1000000 )); }
seconds_since() { local ms=$(( $(now_ms) - $1 )); printf '%d.%d' $((ms / 1000)) $((ms % 1000 / 100)); }
started=$(now_ms)

[ $# -gt 0 ] || { echo "usage: $0 COMMAND [ARG...]" >&2; exit 2; }
cannot() { echo "cannot start a private Slurm cluster: $*" >&2; exit 77; }
fail() { echo "error: private Slurm cluster: $*" >&2; exit 1; }

# --- Slurm and munge, installed if missing --------------------------------------------------
packages=(slurmctld slurmd slurm-client munge)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  [ "$(id -u)" -eq 0 ] || cannot "${missing[*]} not installed and not root to install them"
  command -v apt-get >/dev/null || cannot "${missing[*]} not installed and no apt-get"
  # The packages' scripts would start system daemons, which fail without /etc/slurm/slurm.conf.
  policy=/usr/sbin/policy-rc.d made_policy=""
  if [ ! -e "$policy" ]; then printf '#!/bin/sh\nexit 101\n' > "$policy"; chmod 755 "$policy"; made_policy=1; fi
  echo "installing: ${missing[*]}"
  installed=1
  { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"; } \
    >/tmp/gibench-slurm-apt.log 2>&1 || installed=""
  [ -n "$made_policy" ] && rm -f "$policy"
  [ -n "$installed" ] || cannot "cannot install ${missing[*]} (apt-get: /tmp/gibench-slurm-apt.log)"
fi
address=$(getent hosts "$(hostname)" | awk '{print $1; exit}')
[[ "$address" == 127.* ]] || cannot "hostname $(hostname) resolves to '${address:-nothing}', not 127.x: Slurm would listen beyond loopback"

# --- a private cluster in a fresh folder -----------------------------------------------------
T=$(mktemp -d /tmp/gibench-slurm.XXXXXX)
mkdir -p "$T"/{etc,state,spool,log,munge}
chmod 755 "$T" "$T/munge"  # munged refuses a socket folder others cannot reach
# Nothing of an outer Slurm job (a CI runner may be one) may leak into this cluster's commands.
for v in $(compgen -e | grep '^SLURM_' || true); do unset "$v"; done
export SLURM_CONF=$T/etc/slurm.conf
# The daemons carry a marker in their environment, which slurmstepd inherits from slurmd; a job
# has this cluster's SLURM_CONF and a SLURM_JOB_ID. So the clean-up can find and check exactly
# the processes this test started.
marker="GIBENCH_SLURM_TEST=$T"
daemon_pids=() command_ran=""

ours() {  # PIDs of live processes of this test's cluster: daemons, steps, jobs
  local p
  for p in /proc/[0-9]*; do
    tr '\0' '\n' 2>/dev/null < "$p/environ" |
      awk -v marker="$marker" -v conf="SLURM_CONF=$SLURM_CONF" '
        $0 == marker { found = 1 } $0 == conf { c = 1 } /^SLURM_JOB_ID=/ { j = 1 }
        END { exit !(found || (c && j)) }' && echo "${p#/proc/}"
  done
  return 0
}

cleanup() {
  local rc=$? left deadline stop_started
  set +e
  stop_started=$(now_ms)
  if [ -f "$SLURM_CONF" ] && [ ${#daemon_pids[@]} -gt 0 ]; then
    # scontrol shutdown leaves running jobs behind: cancel and wait for an empty queue first.
    scancel --full --user="$(id -un)" 2>/dev/null
    deadline=$((SECONDS + 20))
    while [ -n "$(squeue --noheader 2>/dev/null)" ] && [ $SECONDS -lt $deadline ]; do sleep 0.2; done
    scontrol shutdown >/dev/null 2>&1
  fi
  deadline=$((SECONDS + 15))
  while [ $SECONDS -lt $deadline ]; do
    left=$(ours | grep -vxF "${munged_pid:-none}")
    [ -z "$left" ] && break
    sleep 0.2
  done
  [ -n "${munged_pid:-}" ] && kill "$munged_pid" 2>/dev/null
  wait 2>/dev/null
  left=$(ours)
  if [ -n "$left" ]; then
    echo "error: private Slurm cluster: processes of the cluster left after the stop:" >&2
    for p in $left; do echo "  $p $(tr '\0' ' ' < /proc/$p/cmdline 2>/dev/null)" >&2; kill -9 "$p" 2>/dev/null; done
    rc=1
  fi
  # The daemons' logs tell why the cluster failed; a failing command has its own output.
  if [ $rc -ne 0 ] && { [ -z "$command_ran" ] || [ -n "$left" ]; }; then
    for f in "$T"/log/*.log "$T"/munge/munged.log; do [ -f "$f" ] && { echo "--- $f (tail)"; tail -n 15 "$f"; } >&2; done
  fi
  rm -rf "$T"
  [ -z "$left" ] && echo "cluster stopped, nothing left, in $(seconds_since "$stop_started") s; $(seconds_since "$started") s in all"
  exit $rc
}
trap cleanup EXIT
trap 'exit 1' INT TERM

read -r ctld_port slurmd_port < <(python3 -c '
import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(*[x.getsockname()[1] for x in s])')
memory_mb=$(( $(awk '/^MemTotal:/ {print $2}' /proc/meminfo) / 1024 - 1024 ))
cat > "$SLURM_CONF" <<EOF
ClusterName=gibenchtest
SlurmctldHost=localhost
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
CommunicationParameters=NoCtldInAddrAny,NoInAddrAny
SlurmUser=$(id -un)
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$T/munge/munge.socket
StateSaveLocation=$T/state
SlurmdSpoolDir=$T/spool
SlurmctldPidFile=$T/slurmctld.pid
SlurmdPidFile=$T/slurmd.pid
SlurmctldLogFile=$T/log/slurmctld.log
SlurmdLogFile=$T/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
ReturnToService=2
MailProg=/bin/true
SchedulerParameters=batch_sched_delay=0
NodeName=localhost NodeAddr=127.0.0.1 CPUs=$(nproc) RealMemory=$memory_mb State=UNKNOWN
PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP
EOF
dd if=/dev/urandom of="$T/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$T/munge/munge.key"
env "$marker" munged -F --socket="$T/munge/munge.socket" --key-file="$T/munge/munge.key" \
  --pid-file="$T/munge/munged.pid" --log-file="$T/munge/munged.log" --seed-file="$T/munge/munged.seed" \
  --origin=127.0.0.1 >"$T/log/munged.out" 2>&1 &
munged_pid=$!
daemon_pids+=("$munged_pid")
deadline=$((SECONDS + 10))
until [ -S "$T/munge/munge.socket" ]; do
  kill -0 "$munged_pid" 2>/dev/null || fail "munged exited: $(cat "$T/log/munged.out")"
  [ $SECONDS -lt $deadline ] || fail "munged did not create its socket in 10 s"
  sleep 0.05
done
env "$marker" slurmctld -D -i >"$T/log/slurmctld.out" 2>&1 &
daemon_pids+=($!)
env "$marker" slurmd -D -N localhost >"$T/log/slurmd.out" 2>&1 &
daemon_pids+=($!)
deadline=$((SECONDS + 20))
until scontrol ping 2>/dev/null | grep -q "is UP" && [ "$(sinfo --noheader --nodes=localhost --format=%t 2>/dev/null)" = idle ]; do
  state=$(sinfo --noheader --nodes=localhost --format=%t 2>/dev/null || true)
  case "$state" in inval*|drain*) fail "the node is $state: $(sinfo --noheader --list-reasons 2>/dev/null)";; esac
  for pid in "${daemon_pids[@]}"; do kill -0 "$pid" 2>/dev/null || fail "a daemon (pid $pid) exited while starting"; done
  [ $SECONDS -lt $deadline ] || fail "the cluster was not ready in 20 s (node: ${state:-unknown})"
  sleep 0.1
done
# The clean-up finds the cluster's processes by the marker: it must see the daemons.
[ "$(ours | wc -l)" -ge 3 ] || fail "the marker finds $(ours | wc -l) of the 3 daemons"
echo "cluster up on 127.0.0.1, ports $ctld_port and $slurmd_port, in $(seconds_since "$started") s"

set +e
command_ran=1
"$@"
status=$?
set -e
exit $status

