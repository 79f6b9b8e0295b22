#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, -DGIBENCH_FUZZ=ON) and runs each for SECONDS (default 60),
# then prints per target the inputs executed and the inputs that crashed. Exits 1 when any target
# crashed, leaked, ran out of memory or timed out on an input. tests/fuzz/README.md explains more.
#   tests/fuzz/run_fuzzers.sh [SECONDS]
# Environment:
#   GIBENCH_FUZZ_BUILD  build folder (default build-fuzz); it keeps the grown corpus of each target
#                       in fuzz/corpus/<target>/ and what crashed in fuzz/findings/<target>/
#   FUZZ_TARGETS        the targets to run (default: all four)
#   FUZZ_RUNS           also stop a target after this many inputs (the long pass: 1000000)
#   FUZZ_SEED           the fuzzers' random seed (default: a new one each run); with FUZZ_RUNS and
#                       a time that is not reached, a run is repeatable (what .ci/run does)
#   FUZZ_KEEP_GOING=1   run in a child process that restarts after a crash (-fork=1), so that one
#                       known crash does not end the run; every crash still counts
set -euo pipefail
cd "$(dirname "$0")/../.."

seconds="${1:-60}"
build="${GIBENCH_FUZZ_BUILD:-build-fuzz}"
read -r -a targets <<< "${FUZZ_TARGETS:-fuzz_config fuzz_scene fuzz_obj fuzz_image}"

cmake -S . -B "$build" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGIBENCH_FUZZ=ON >/dev/null
cmake --build "$build" -j"$(nproc)" --target "${targets[@]}"

# The fuzzers' $TMPDIR, where each keeps its private folder: removed here even after a crash.
work="$(mktemp -d "${TMPDIR:-/tmp}/gibench_fuzz.XXXXXX")"
trap 'rm -rf "$work"' EXIT
tests/fuzz/generated_seeds.py "$work/seeds"

# Memory: in a fuzz build an image may hold 2^22 values (core/util/image_limits.h), 48 MiB read and
# converted (core/util/pixel_read.h), but OpenEXR allocates its decompression buffers inside
# open(), from the header's width times its lines per block, before any check of ours can run:
# 1.5-2 GiB for a 597-byte file claiming 16777218 x 1 pixels. Beyond 8 GiB an input is a finding.
options=(-max_total_time="$seconds" -rss_limit_mb=14336 -malloc_limit_mb=8448 -timeout=20 -print_final_stats=1 -print_funcs=0)
[ -n "${FUZZ_RUNS:-}" ] && options+=(-runs="$FUZZ_RUNS")
[ -n "${FUZZ_SEED:-}" ] && options+=(-seed="$FUZZ_SEED")
[ "${FUZZ_KEEP_GOING:-0}" = 1 ] && options+=(-fork=1 -ignore_crashes=1 -ignore_ooms=1 -ignore_timeouts=1)

failed=0
summary=()
for target in "${targets[@]}"; do
  corpus="$build/fuzz/corpus/$target"
  findings="$build/fuzz/findings/$target"
  mkdir -p "$corpus" "$findings"
  seeds=("tests/fuzz/corpus/$target")
  [ -d "$work/seeds/$target" ] && seeds+=("$work/seeds/$target")
  [ "$target" = fuzz_scene ] && seeds+=(configs/scenes)
  log="$findings/last_run.log"
  stamp="$work/$target.start"
  touch "$stamp"
  echo "== $target: fuzzing for $seconds s (log: $log)"
  # New inputs go to the first folder, the corpus that grows; the seed folders are only read.
  TMPDIR="$work" \
  ASAN_OPTIONS="detect_leaks=1" \
  LSAN_OPTIONS="suppressions=$PWD/tests/fuzz/lsan.supp" \
  UBSAN_OPTIONS="print_stacktrace=1" \
    "$build/tests/fuzz/$target" "${options[@]}" -artifact_prefix="$findings/" "$corpus" "${seeds[@]}" >"$log" 2>&1 && rc=0 || rc=$?

  executions="$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | tail -n1 | grep -o '[0-9]*$' || true)"
  [ -n "$executions" ] || executions="$(grep -o '^#[0-9]*' "$log" | tail -n1 | tr -d '#' || true)"
  mapfile -t crashes < <(find "$findings" -newer "$stamp" -type f \( -name 'crash-*' -o -name 'leak-*' -o -name 'oom-*' -o -name 'timeout-*' \) | sort)
  if [ "$rc" -ne 0 ] || [ "${#crashes[@]}" -gt 0 ]; then
    failed=1
    summary+=("$target: ${executions:-?} executions, FOUND ${#crashes[@]} crashing input(s) (exit code $rc): ${crashes[*]:-see $log}")
  else
    summary+=("$target: ${executions:-?} executions, no crash")
  fi
done

echo "== fuzzing summary ($seconds s per target)"
printf '%s\n' "${summary[@]}"
exit "$failed"
