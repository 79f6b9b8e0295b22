#!/usr/bin/env bash
# Runs every config of an experiment folder (configs/experiments/<name>/*.json): the reference
# first (rendered once, then reused), then each run, then the error-against-time analysis.
#   experiments/run_experiment.sh configs/experiments/cornell_stores [--threads N]
set -euo pipefail
folder=${1:?usage: $0 CONFIG_FOLDER [gibench options]}
shift
cd "$(dirname "$0")/.."
gibench=build/gibench
[ -x "$gibench" ] || { echo "error: $gibench is missing; run ./dev.sh build" >&2; exit 2; }
configs=("$folder"/*.json)
[ -e "${configs[0]}" ] || { echo "error: $folder: no *.json configs" >&2; exit 2; }
experiment=""
for config in "${configs[@]}"; do
  "$gibench" reference --quiet "$@" "$config"
  "$gibench" run --quiet "$@" "$config"
  experiment=$(/usr/bin/python3 -c 'import json,sys; print(json.load(open(sys.argv[1])).get("experiment","default"))' "$config")
done
/usr/bin/python3 analysis/error_vs_time.py "results/$experiment" && /usr/bin/python3 analysis/paper_outputs.py "results/$experiment" --out "results/$experiment/paper"
