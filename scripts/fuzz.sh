#!/usr/bin/env bash
# scripts/fuzz.sh TARGET[,TARGET...] [SECONDS] [RUNS]: libFuzzer campaigns (tests/fuzz/README.md).
# Builds build-fuzz/ (clang, ASan + UBSan + libFuzzer) when needed, writes the seed corpora on
# first use (build-fuzz/corpus/TARGET, which then keeps what the campaign adds), and runs
# fuzz_TARGET for SECONDS (default 600) or RUNS executions (default: unlimited), whichever comes
# first, with the target's input size and leak options; an undefined-behaviour report stops it
# (UBSAN_OPTIONS=halt_on_error=1: the readers are built with recoverable UBSan checks). Prints libFuzzer's "Done N runs" line;
# a crash, leak or sanitizer report exits 1 and leaves the input as build-fuzz/crash-TARGET-*.
# HLOD_FUZZ_FLAGS: more libFuzzer options, e.g. "-entropic=0" (the older, cheaper input scheduling:
# ~25 % of a campaign's CPU goes to entropic's feature-frequency bookkeeping on fuzz_obj).
# TARGET: skeleton blob ply obj mtl gltf glb camera_path constants calibration. Several targets,
# comma-separated, are built together and then fuzzed FUZZ_PARALLEL at a time (default: the number
# of cores; a campaign uses one), each for SECONDS: the test command's smoke run of all ten.
set -euo pipefail
cd "$(dirname "$0")/.."
IFS=, read -ra targets <<< "${1:-}"
seconds=${2:-600}
runs=${3:--1}
leaks=1
usage="usage: scripts/fuzz.sh TARGET[,TARGET...] [SECONDS] [RUNS] (TARGET: skeleton blob ply obj mtl gltf glb camera_path constants calibration)"
maxLength() {
  case "$1" in
    skeleton) echo 8192 ;;
    blob) echo 16384 ;;
    ply|obj|gltf|glb) echo 8192 ;;
    mtl|camera_path) echo 4096 ;;
    constants|calibration) echo 2048 ;;
    *) return 1 ;;
  esac
}
[ ${#targets[@]} -gt 0 ] || { echo "$usage" >&2; exit 2; }
for target in "${targets[@]}"; do maxLength "$target" >/dev/null || { echo "$usage" >&2; exit 2; }; done
if [ ! -f build-fuzz/build.ninja ]; then
  CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DHLOD_FUZZ=ON \
    -DHLOD_TESTS=OFF -DHLOD_BENCH=OFF >/dev/null
fi
# Quiet when it builds; the build's own lines when it does not (a link error failed the script
# without a word until stop 46).
cmake --build build-fuzz -j "${JOBS:-$(nproc)}" --target "${targets[@]/#/fuzz_}" fuzz_corpus > build-fuzz/build.log 2>&1 ||
  { tail -n 40 build-fuzz/build.log; echo "fuzz: the build failed (log build-fuzz/build.log)"; exit 1; }
for target in "${targets[@]}"; do
  [ -d "build-fuzz/corpus/$target" ] || { build-fuzz/tests/fuzz/fuzz_corpus build-fuzz/corpus; break; }
done

campaign() {
  local target=$1 log=build-fuzz/fuzz_$1.log
  UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 ASAN_OPTIONS=detect_leaks=$leaks "build-fuzz/tests/fuzz/fuzz_$target" \
    -max_total_time="$seconds" -runs="$runs" -max_len="$(maxLength "$target")" -detect_leaks="$leaks" -print_final_stats=1 \
    ${HLOD_FUZZ_FLAGS:-} -artifact_prefix="build-fuzz/crash-$target-" "build-fuzz/corpus/$target" > "$log" 2>&1 ||
    { printf '%s\nfuzz_%s: FAILED (log %s)\n' "$(tail -n 40 "$log")" "$target" "$log"; return 1; }
  echo "fuzz_$target: $(grep -m1 '^Done' "$log"), $(ls "build-fuzz/corpus/$target" | wc -l) inputs in the corpus"
}
parallel=${FUZZ_PARALLEL:-$(nproc)}
status=0
running=()
for target in "${targets[@]}"; do
  campaign "$target" &
  running+=($!)
  if [ ${#running[@]} -ge "$parallel" ]; then
    wait "${running[0]}" || status=1
    running=("${running[@]:1}")
  fi
done
for pid in "${running[@]}"; do wait "$pid" || status=1; done
exit $status
