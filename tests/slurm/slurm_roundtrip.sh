#!/usr/bin/env bash
# The Slurm backend through a real cluster (issue 10 item 4): a private single-node cluster on
# 127.0.0.1 (munged, slurmctld, slurmd; config, state, logs, munge socket and key in one fresh
# temp folder, ports chosen free), the 4-run sweep configs/sweeps/slurm_smoke.json submitted with
# `gibench sweep --backend slurm --wait`, the same sweep run locally; every run's image.exr and
# metrics.json's errors must be bit-identical, `gibench collect` must say 0 with every run there
# and 1 with one deleted. Every daemon, step and job it started is stopped, and checked gone,
# whatever happens (trap). docs/slurm.md; the facts it relies on: ../shared/SLURM_NOTES.md.
#
#   tests/slurm/slurm_roundtrip.sh [GIBENCH]   (default: build/gibench; run by .ci/run)
#
# Installs slurmctld slurmd slurm-client munge when missing (as root, with daemons kept from
# starting); skips with exit 0 and a "SKIP" line only where they cannot be installed or the
# hostname does not resolve to a 127.x address (Slurm binds to it). Exit 1 on any failure.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
gibench=$(realpath "${1:-$root/build/gibench}")
sweep=$root/configs/sweeps/slurm_smoke.json
now_ms() { echo $(( $(date +%s%N) / 1000000 )); }
seconds_since() { local ms=$(( $(now_ms) - $1 )); printf '%d.%d' $((ms / 1000)) $((ms % 1000 / 100)); }
started=$(now_ms)

skip() { echo "SKIP slurm round trip: $*"; exit 0; }
fail() { echo "FAIL slurm round trip: $*" >&2; exit 1; }
[ -x "$gibench" ] || fail "no gibench executable at $gibench (build first)"

# --- Slurm and munge, installed if missing --------------------------------------------------
packages=(slurmctld slurmd slurm-client munge)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  [ "$(id -u)" -eq 0 ] || skip "${missing[*]} not installed and not root to install them"
  command -v apt-get >/dev/null || skip "${missing[*]} not installed and no apt-get"
  # The packages' scripts would start system daemons, which fail without /etc/slurm/slurm.conf.
  policy=/usr/sbin/policy-rc.d made_policy=""
  if [ ! -e "$policy" ]; then printf '#!/bin/sh\nexit 101\n' > "$policy"; chmod 755 "$policy"; made_policy=1; fi
  echo "installing: ${missing[*]}"
  installed=1
  { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"; } \
    >/tmp/gibench-slurm-apt.log 2>&1 || installed=""
  [ -n "$made_policy" ] && rm -f "$policy"
  [ -n "$installed" ] || skip "cannot install ${missing[*]} (apt-get: /tmp/gibench-slurm-apt.log)"
fi
address=$(getent hosts "$(hostname)" | awk '{print $1; exit}')
[[ "$address" == 127.* ]] || skip "hostname $(hostname) resolves to '${address:-nothing}', not 127.x: Slurm would listen beyond loopback"

# --- a private cluster in a fresh folder -----------------------------------------------------
T=$(mktemp -d /tmp/gibench-slurm.XXXXXX)
mkdir -p "$T"/{etc,state,spool,log,munge,slurm_cwd,local_cwd}
chmod 755 "$T" "$T/munge"  # munged refuses a socket folder others cannot reach
# Nothing of an outer Slurm job (a CI runner may be one) may leak into this cluster's commands.
for v in $(compgen -e | grep '^SLURM_' || true); do unset "$v"; done
export SLURM_CONF=$T/etc/slurm.conf
# The daemons carry a marker in their environment, which slurmstepd inherits from slurmd; a job
# has this cluster's SLURM_CONF and a SLURM_JOB_ID. So the clean-up can find and check exactly
# the processes this test started.
marker="GIBENCH_SLURM_TEST=$T"
daemon_pids=()

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
    echo "FAIL slurm round trip: processes of the test cluster left after the stop:" >&2
    for p in $left; do echo "  $p $(tr '\0' ' ' < /proc/$p/cmdline 2>/dev/null)" >&2; kill -9 "$p" 2>/dev/null; done
    rc=1
  fi
  if [ $rc -ne 0 ]; then
    for f in "$T"/log/*.log "$T"/munge/munged.log; do [ -f "$f" ] && { echo "--- $f (tail)"; tail -n 15 "$f"; } >&2; done
  fi
  rm -rf "$T"
  if [ $rc -eq 0 ]; then
    echo "stopped, nothing left, in $(seconds_since "$stop_started") s; $(seconds_since "$started") s in all"
    echo "PASS slurm round trip"
  fi
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
ready=$(now_ms)
echo "cluster up on 127.0.0.1, ports $ctld_port and $slurmd_port, in $(seconds_since "$started") s"

# --- the sweep through Slurm and here --------------------------------------------------------
(cd "$T/slurm_cwd" && timeout 120 "$gibench" sweep "$sweep" --backend slurm --wait) || fail "the sweep through Slurm failed (exit $?)"
echo "the sweep through Slurm: $(seconds_since "$ready") s from submission to collected"
(cd "$T/local_cwd" && timeout 120 "$gibench" sweep "$sweep" --threads 2 --quiet >/dev/null) || fail "the local sweep failed (exit $?)"

a=$T/slurm_cwd/results/slurm_smoke b=$T/local_cwd/results/slurm_smoke
runs=$(cd "$b" && ls)
[ "$(echo "$runs" | wc -l)" -eq 4 ] || fail "expected 4 local runs, got: $runs"
for run in $runs; do
  cmp -s "$a/$run/image.exr" "$b/$run/image.exr" || fail "$run: image.exr differs between Slurm and the local run"
  python3 - "$a/$run" "$b/$run" <<'EOF' || fail "$run: metrics differ between Slurm and the local run"
import json, sys
slurm, local = (json.load(open(d + "/metrics.json")) for d in sys.argv[1:])
manifests = [json.load(open(d + "/manifest.json")) for d in sys.argv[1:]]
assert slurm["error"] is not None, "no error against the reference"
assert slurm["error"] == local["error"], "error numbers differ"
assert slurm["frames"] == local["frames"], "frame counts differ"
assert manifests[0]["run_id"] == manifests[1]["run_id"], "run ids differ"
assert (manifests[0]["threads"], manifests[1]["threads"]) == (1, 2), "threads per run: cpus_per_task through Slurm, --threads here"
EOF
done
echo "4 runs bit-identical between Slurm (1 thread per task) and the local sweep (2 threads)"

"$gibench" collect "$a" >/dev/null || fail "gibench collect: expected exit 0 with every run done"
deleted=$(echo "$runs" | head -n 1)
rm -rf "${a:?}/$deleted"
set +e
out=$("$gibench" collect "$T/slurm_cwd/results" --experiment slurm_smoke)
status=$?
set -e
[ $status -eq 1 ] || fail "gibench collect: expected exit 1 with a run deleted, got $status"
echo "$out" | grep -q "4 runs: 3 done, 0 failed, 1 missing" || fail "gibench collect: unexpected summary: $out"
echo "collect: 0 with every run, 1 with one deleted"
# Submitted again, only the deleted run is in the array, and it comes back the same.
out=$(cd "$T/slurm_cwd" && timeout 120 "$gibench" sweep "$sweep" --backend slurm --wait) || fail "the second submission failed: $out"
echo "$out" | grep -q "^submitted job [0-9]*: 1 of 4 runs" || fail "expected only the deleted run submitted again: $out"
cmp -s "$a/$deleted/image.exr" "$b/$deleted/image.exr" || fail "$deleted: image.exr differs after the second submission"
echo "submitted again: only $deleted ran, the same bits"
