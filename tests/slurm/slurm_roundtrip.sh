#!/usr/bin/env bash
# The Slurm backend through a real cluster (issue 10 item 4): inside a private single-node
# cluster (experiments/slurm_private_cluster.sh, which stops every daemon and job it started and
# checks them gone), the 4-run sweep configs/sweeps/slurm_smoke.json submitted with
# `gibench sweep --backend slurm --wait`, the same sweep run locally; every run's image.exr and
# metrics.json's errors must be bit-identical, `gibench collect` must say 0 with every run there
# and 1 with one deleted, and a second submission must run only the deleted run.
#
#   tests/slurm/slurm_roundtrip.sh [GIBENCH]   (default: build/gibench; run by .ci/run)
#
# Skips with exit 0 and a "SKIP" line only where no cluster can be started (the packages cannot
# be installed, or the hostname does not resolve to 127.x). Exit 1 on any failure.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
gibench=$(realpath "${1:-$root/build/gibench}")
sweep=$root/configs/sweeps/slurm_smoke.json
[ -x "$gibench" ] || { echo "FAIL slurm round trip: no gibench executable at $gibench (build first)" >&2; exit 1; }

if [ "${2:-}" != --inside-cluster ]; then
  set +e
  "$root/experiments/slurm_private_cluster.sh" "$0" "$gibench" --inside-cluster
  status=$?
  set -e
  case $status in
    0) echo "PASS slurm round trip" ;;
    77) echo "SKIP slurm round trip: no private cluster here (reason above)"; exit 0 ;;
    *) echo "FAIL slurm round trip (exit $status)" >&2; exit 1 ;;
  esac
  exit 0
fi

now_ms() { echo $(( $(date +%s%N) / 1000000 )); }
seconds_since() { local ms=$(( $(now_ms) - $1 )); printf '%d.%d' $((ms / 1000)) $((ms % 1000 / 100)); }
fail() { echo "FAIL slurm round trip: $*" >&2; exit 1; }
T=$(mktemp -d /tmp/gibench-slurm-sweeps.XXXXXX)
trap 'rm -rf "$T"' EXIT
mkdir -p "$T"/{slurm_cwd,local_cwd}
ready=$(now_ms)

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
