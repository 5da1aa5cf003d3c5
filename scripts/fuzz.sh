#!/usr/bin/env bash
# scripts/fuzz.sh TARGET [SECONDS] [RUNS]: one libFuzzer campaign (tests/fuzz/README.md).
# Builds build-fuzz/ (clang, ASan + UBSan + libFuzzer) when needed, writes the seed corpora on
# first use (build-fuzz/corpus/TARGET, which then keeps what the campaign adds), and runs
# fuzz_TARGET for SECONDS (default 600) or RUNS executions (default: unlimited), whichever comes
# first, with the target's input size and leak options; an undefined-behaviour report stops it
# (UBSAN_OPTIONS=halt_on_error=1: the readers are built with recoverable UBSan checks). Prints libFuzzer's "Done N runs" line;
# a crash, leak or sanitizer report exits 1 and leaves the input as build-fuzz/crash-TARGET-*.
# HLOD_FUZZ_FLAGS: more libFuzzer options, e.g. "-entropic=0" (the older, cheaper input scheduling:
# ~25 % of a campaign's CPU goes to entropic's feature-frequency bookkeeping on fuzz_obj).
# TARGET: skeleton blob ply obj mtl gltf glb camera_path constants calibration
set -euo pipefail
cd "$(dirname "$0")/.."
target=${1:-}
seconds=${2:-600}
runs=${3:--1}
leaks=1
case "$target" in
  skeleton) max=8192 ;;
  blob) max=16384 ;;
  ply|obj|gltf|glb) max=8192 ;;
  mtl|camera_path) max=4096 ;;
  constants|calibration) max=2048 ;;
  *) echo "usage: scripts/fuzz.sh TARGET [SECONDS] [RUNS] (TARGET: skeleton blob ply obj mtl gltf glb camera_path constants calibration)" >&2
     exit 2 ;;
esac
if [ ! -f build-fuzz/build.ninja ]; then
  CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DHLOD_FUZZ=ON \
    -DHLOD_TESTS=OFF -DHLOD_BENCH=OFF >/dev/null
fi
cmake --build build-fuzz -j "${JOBS:-$(nproc)}" --target "fuzz_$target" fuzz_corpus >/dev/null
[ -d "build-fuzz/corpus/$target" ] || build-fuzz/tests/fuzz/fuzz_corpus build-fuzz/corpus
log=build-fuzz/fuzz_$target.log
UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 ASAN_OPTIONS=detect_leaks=$leaks "build-fuzz/tests/fuzz/fuzz_$target" -max_total_time="$seconds" -runs="$runs" \
  -max_len="$max" -detect_leaks="$leaks" -print_final_stats=1 ${HLOD_FUZZ_FLAGS:-} -artifact_prefix="build-fuzz/crash-$target-" \
  "build-fuzz/corpus/$target" > "$log" 2>&1 || { tail -n 40 "$log"; echo "fuzz_$target: FAILED (log $log)"; exit 1; }
echo "fuzz_$target: $(grep -m1 '^Done' "$log"), $(ls "build-fuzz/corpus/$target" | wc -l) inputs in the corpus"
