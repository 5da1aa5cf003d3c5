#!/usr/bin/env bash
# The README's test command: install dependencies, build (Release), run the whole test suite,
# then the threaded player tests under ThreadSanitizer (build-tsan/).
# Then AddressSanitizer + UndefinedBehaviorSanitizer (build-asan/, Debug): by default a
# representative subset, test_formats (every database reader and writer, and every subcommand's
# bad-input paths through an instrumented `hlod`) and the player's (selection, policies,
# loader, faults, `hlod play`/`compare`);
# HLOD_SANITIZE=1 runs the whole suite instead (except tests labelled `slow`), which on 2 cores
# takes about as long again as the first pass.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
jobs=$(nproc)

cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$jobs"
ctest --test-dir build --output-on-failure -j "$jobs"

# The README's main command on the embedded sample, end to end (build, validate, stats, replay,
# plots), with a check that each output it announces exists.
bash scripts/run-sample.sh > build/run-sample.log 2>&1 || { tail -n 30 build/run-sample.log; echo "run-sample: FAILED"; exit 1; }
for f in out/city/city.hlod out/city/stats.json out/city/walk.csv out/city/walk-summary.json out/city/plots/fig6_6.png; do
  [ -s "$f" ] || { echo "run-sample: $f missing"; exit 1; }
done
echo "run-sample: main command OK (outputs under out/city/)"

# ThreadSanitizer: the threaded loader and player tests (the render thread, the loading thread
# and their shared queue), and the build's nodes of one block built in parallel (build_tree.cpp:
# their shared texture cache, progress, ordered records and spilled blobs), rebuilt with -fsanitize=thread; any
# reported race fails the script. Only their files and the libraries are built (tests/tsan/).
# -g1: line tables only, enough for the sanitizers' stack traces (the largest file compiles ~14 %
# faster; the ASan `hlod` is 166 MB instead of 296).
cmake -S . -B build-tsan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" \
  -DHLOD_TSAN=ON -DHLOD_BENCH=OFF >/dev/null
cmake --build build-tsan -j "$jobs" --target test_threads
TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1" \
  build-tsan/tests/tsan/test_threads --gtest_filter='Loader*:PlayerEndToEnd.ThreadedLoaderHoldsTarget'
# (libtbb is not instrumented: pipeline/tbb_sync.h and scripts/tsan.supp; the two runs ~1.5 minutes on 2 cores)
TSAN_OPTIONS="halt_on_error=1 second_deadlock_stack=1 suppressions=$PWD/scripts/tsan.supp" \
  build-tsan/tests/tsan/test_threads --gtest_filter='BlockParallel.*:BlobSpill.*'

# libFuzzer smoke run of every reader (tests/fuzz/README.md, scripts/fuzz.sh): the database
# skeleton and blobs, PLY, OBJ, MTL, glTF, GLB, camera path, constants and calibration files,
# built with clang + ASan/UBSan, 15 s each (2.5 CPU-minutes in all, one campaign per core at a
# time) from freshly generated seed corpora; any crash, leak in hlod code or sanitizer report
# fails the script.
if command -v clang++ >/dev/null; then
  rm -rf build-fuzz/corpus
  bash scripts/fuzz.sh skeleton,blob,ply,obj,mtl,gltf,glb,camera_path,constants,calibration 15
fi

cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG=-g1 -DHLOD_SANITIZE=ON -DHLOD_BENCH=OFF >/dev/null
export ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1
if [ "${HLOD_SANITIZE:-0}" = 1 ]; then
  cmake --build build-asan -j "$jobs"
  ctest --test-dir build-asan --output-on-failure -j "$jobs" -LE slow
else
  cmake --build build-asan -j "$jobs" --target test_formats test_player test_player_cli
  ctest --test-dir build-asan/tests/formats --output-on-failure -j "$jobs" -LE slow
  ctest --test-dir build-asan/tests/player --output-on-failure -j "$jobs" -LE slow
  echo "asan+ubsan: the formats and player tests passed (HLOD_SANITIZE=1 runs the whole suite)"
fi
