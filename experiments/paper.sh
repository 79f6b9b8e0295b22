#!/usr/bin/env bash
# The comparison study of configs/paper/README.md, from its sweeps to its figures, tables and
# HTML report, resumable (a second call runs only what is missing):
#   experiments/paper.sh [--quick] [--results DIR] [--jobs N | --backend slurm]
# --quick: every sweep at a tiny resolution, a 0.5 s budget and a 256-spp reference: minutes, for
# CI and for trying the pipeline; its numbers are not the study's. Default DIR: results/paper
# (results/paper_quick with --quick). --jobs N: runs at a time here (default 2). --backend slurm:
# each sweep submitted as one job array (its "slurm" block) and waited for; on one machine, inside
# experiments/slurm_private_cluster.sh. Exit 1 when a run failed (the rest still ran), 2 on bad
# input.
set -euo pipefail
cd "$(dirname "$0")/.."

quick=0 results="" jobs="" backend=local
while (($#)); do
  case "$1" in
    --quick) quick=1 ;;
    --results) results="${2:?--results needs a folder}"; shift ;;
    --jobs) jobs="${2:?--jobs needs a number}"; shift ;;
    --backend) backend="${2:?--backend needs local or slurm}"; shift ;;
    *) echo "error: $0: unknown argument \"$1\" (expected --quick, --results DIR, --jobs N, --backend local|slurm)" >&2; exit 2 ;;
  esac
  shift
done
case "$backend" in
  local) running=(--jobs "${jobs:-2}") ;;
  slurm)
    [[ -z "$jobs" ]] || { echo "error: $0: --jobs: not with --backend slurm (the sweeps' \"slurm\" blocks say what each task gets)" >&2; exit 2; }
    running=(--backend slurm --wait) ;;
  *) echo "error: $0: --backend: expected local or slurm, got \"$backend\"" >&2; exit 2 ;;
esac
[[ -n "$results" ]] || results=$([[ $quick == 1 ]] && echo results/paper_quick || echo results/paper)
gibench=build/gibench
[[ -x "$gibench" ]] || { echo "error: $0: $gibench is missing: run ./dev.sh build first" >&2; exit 2; }

sets=()
if [[ $quick == 1 ]]; then
  sets=(--set 'camera.resolution=[48,32]' --set budget.seconds=0.5 --set 'checkpoints.seconds=[0.125,0.25,0.5]' --set reference.spp=256)
fi
# Every sweep is checked before any runs: a typo in the last one should not wait for the first.
for sweep in configs/paper/*.json; do
  "$gibench" sweep "$sweep" --dry-run --results "$results" "${sets[@]}" > /dev/null
done
start=$SECONDS status=0
for sweep in configs/paper/*.json; do
  "$gibench" sweep "$sweep" "${running[@]}" --quiet --results "$results" "${sets[@]}" || status=$?
  ((status < 2)) || exit "$status"
done
echo "paper sweeps: $((SECONDS - start)) s"
"$gibench" report "$results"
exit "$status"
