#!/usr/bin/env bash
# Builds the libFuzzer harnesses (fuzz/) with clang, AddressSanitizer and UBSan, and runs each for
# SECONDS (default 30) from a seed corpus of the repository's own inputs (examples/, test data,
# the bad inputs of tests/bad_inputs/).
# Prints each harness's executions; a crash, a sanitizer report or a leak fails the script and
# leaves the input that caused it in build-fuzz/findings/. Usage: scripts/fuzz.sh [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-30}
scripts/install-deps.sh

CXX=clang++ CC=clang cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DLINX_FUZZ=ON -DLINX_BUILD_TESTS=OFF -DLINX_BUILD_APPS=OFF -DLINX_BUILD_BENCH=OFF >/dev/null
cmake --build build-fuzz -j "$(nproc)" --target fuzz_scene fuzz_mesh fuzz_model fuzz_state

# Seed corpora: every scene, mesh and model of the repository (a model's first byte picks the
# format in fuzz_mesh and fuzz_model: 0 OBJ or URDF, 1 STL or MJCF).
corpus=build-fuzz/corpus
rm -rf "$corpus"
mkdir -p "$corpus"/{scene,mesh,model,state} build-fuzz/findings
cp examples/*.json tests/bad_inputs/*.json "$corpus/scene/"
for f in $(find examples tests/data tests/bad_inputs -name '*.obj' -o -name '*.stl' 2>/dev/null); do
  kind=0; [[ $f == *.stl ]] && kind=1
  { printf "\\x$(printf %02x $kind)"; cat "$f"; } >"$corpus/mesh/$(basename "$f")"
done
for f in $(find examples tests/data tests/bad_inputs -name '*.urdf' -o -name '*.xml' 2>/dev/null); do
  kind=0; [[ $f == *.xml ]] && kind=1
  { printf "\\x$(printf %02x $kind)"; cat "$f"; } >"$corpus/model/$(basename "$f")"
done

status=0
for name in scene mesh model state; do
  log=build-fuzz/fuzz_$name.log
  if ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    build-fuzz/fuzz/fuzz_$name "$corpus/$name" -max_total_time="$seconds" -max_len=65536 \
      -timeout=20 -rss_limit_mb=2048 -artifact_prefix=build-fuzz/findings/${name}- \
      -print_final_stats=1 >"$log" 2>&1; then
    echo "fuzz_$name: $(grep -m1 -o 'stat::number_of_executed_units: *[0-9]*' "$log" |
      grep -o '[0-9]*$') executions in ${seconds} s, corpus $(ls "$corpus/$name" | wc -l), no findings"
  else
    echo "fuzz_$name: FINDING (see $log and build-fuzz/findings/):"
    grep -m3 -E "ERROR|runtime error|SUMMARY" "$log" || tail -5 "$log"
    status=1
  fi
done
exit $status
