#!/usr/bin/env bash
# Runs every config of an experiment folder (configs/experiments/<name>/*.json) and analyses
# exactly the runs it made: each config's reference (rendered once, then reused; an external
# reference file is used as it is), its run, then per experiment the configs name, in the results
# root the runs went to (--results or output.root), the error-against-time analysis
# (analysis/error_vs_time.py) and the figures and tables over seeds (<experiment>/paper/).
# Runs in that experiment's folder that no config of this folder made (a config since removed)
# are left out of both.
#   experiments/run_experiment.sh CONFIG_FOLDER [--threads N] [--results DIR] [--set KEY=VALUE ...]
# GIBENCH names the executable (default build/gibench).
set -euo pipefail
folder=${1:?usage: $0 CONFIG_FOLDER [gibench run options]}
shift
cd "$(dirname "$0")/.."
gibench=${GIBENCH:-build/gibench}
[ -x "$gibench" ] || { echo "error: $gibench is missing; run ./dev.sh build" >&2; exit 2; }
configs=("$folder"/*.json)
[ -e "${configs[0]}" ] || { echo "error: $folder: no *.json configs" >&2; exit 2; }

# The analysis reads a view of the results: one folder per experiment holding links to this
# script's runs only.
view=$(mktemp -d)
trap 'rm -rf "$view"' EXIT
declare -A experimentFolder
for config in "${configs[@]}"; do
  "$gibench" reference --quiet "$@" "$config"
  output=$("$gibench" run --quiet "$@" "$config")
  echo "$output"
  run=$(sed -n 's#^wrote \(.*\)/ (.*#\1#p' <<< "$output")
  [ -d "$run" ] || { echo "error: $config: gibench run said no run folder" >&2; exit 1; }
  experiment=$(basename "$(dirname "$run")")
  experimentFolder[$experiment]=$(cd "$(dirname "$run")" && pwd)
  mkdir -p "$view/$experiment"
  ln -s "$(cd "$run" && pwd)" "$view/$experiment/$(basename "$run")"
done
for experiment in "${!experimentFolder[@]}"; do
  /usr/bin/python3 analysis/error_vs_time.py "$view/$experiment"
  find "$view/$experiment" -maxdepth 1 -type f -exec mv -t "${experimentFolder[$experiment]}" {} +
  /usr/bin/python3 analysis/paper_outputs.py "$view/$experiment" --out "${experimentFolder[$experiment]}/paper"
done
