#!/usr/bin/env bash
# One entry point for setting up, building and checking gibench on Debian 12.
#   ./dev.sh demo   install what is missing, build, render the default scene (Cornell box)
#   ./dev.sh test   install what is missing, build, run the test suite
#   ./dev.sh build  install what is missing, build
#   ./dev.sh bench  install what is missing, build, run the benchmarks
#   ./dev.sh sanitize  build under AddressSanitizer + UndefinedBehaviorSanitizer in build-sanitize/
#                      ($GIBENCH_SANITIZE_BUILD) and run the test suite there
#   ./dev.sh fuzz [SECONDS]  build the libFuzzer targets with clang in build-fuzz/ ($GIBENCH_FUZZ_BUILD)
#                      and run each for SECONDS (default 60); tests/fuzz/README.md
set -euo pipefail
cd "$(dirname "$0")"

packages=(
  build-essential cmake pkg-config git
  libembree-dev libopenimageio-dev openimageio-tools libopenexr-dev libimath-dev
  nlohmann-json3-dev libglm-dev libbenchmark-dev libgtest-dev libgmock-dev
  libtbb-dev libtinyobjloader-dev libcli11-dev libssl-dev libabsl-dev
  python3-numpy python3-matplotlib python3-pandas python3-openimageio chromium
  clang libclang-rt-14-dev
)

install_missing() {
  local missing=()
  for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return
  echo "installing: ${missing[*]}"
  local sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
}

build() {
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build build -j"$(nproc)"
}

# The whole suite under ASan + UBSan (leaks included), any report a failure, but for the tests
# tests/sanitizers/slow_tests.txt leaves out. Embree, TBB and OpenImageIO are not instrumented
# and need no suppressions.
sanitize() {
  local dir="${GIBENCH_SANITIZE_BUILD:-build-sanitize}"
  cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGIBENCH_SANITIZE=ON >/dev/null
  cmake --build "$dir" -j"$(nproc)"
  ASAN_OPTIONS="detect_leaks=1:abort_on_error=1" \
  UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1" \
    ctest --test-dir "$dir" --output-on-failure -j"$(nproc)" -E "$(grep -v '^#' tests/sanitizers/slow_tests.txt | paste -sd'|')"
}

cmd="${1:-}"
case "$cmd" in
  build) install_missing; build ;;
  demo)
    install_missing; build
    build/gibench run configs/cornell_box.json
    ;;
  test)
    install_missing; build
    ctest --test-dir build --output-on-failure -j"$(nproc)"
    ;;
  bench)
    install_missing; build
    build/gibench_bench
    ;;
  sanitize)
    install_missing; sanitize
    ;;
  fuzz)
    install_missing
    exec tests/fuzz/run_fuzzers.sh "${2:-60}"
    ;;
  *) echo "usage: $0 demo|test|build|bench|sanitize|fuzz [SECONDS]" >&2; exit 2 ;;
esac
