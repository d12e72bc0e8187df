#!/usr/bin/env bash
# Installs what is missing, builds linx and runs the whole test suite twice: a plain optimized
# build, then AddressSanitizer + UndefinedBehaviorSanitizer.
# Usage: scripts/test.sh [--plain | --sanitize]   (default: both)
set -euo pipefail
cd "$(dirname "$0")/.."

mode=${1:-all}
jobs=$(nproc)
scripts/install-deps.sh

run() {  # run BUILD_DIR CMAKE_ARGS...
  local dir=$1
  shift
  # Tests on explicitly: the demo script configures the same build directory without them.
  cmake -S . -B "$dir" -G Ninja -DLINX_BUILD_TESTS=ON "$@" >/dev/null
  cmake --build "$dir" -j "$jobs"
  ctest --test-dir "$dir" -j "$jobs" --output-on-failure --no-tests=error
}

if [[ $mode == all || $mode == --plain ]]; then
  echo "== plain (Release) =="
  run build -DCMAKE_BUILD_TYPE=Release
  scripts/python-venv.sh build  # python3 -c "import linx" in build/venv, as after the demo
fi
if [[ $mode == all || $mode == --sanitize ]]; then
  echo "== AddressSanitizer + UBSan =="
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    LSAN_OPTIONS=suppressions=$PWD/tests/lsan.supp:print_suppressions=0 \
    run build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLINX_SANITIZE=ON
fi
