#!/usr/bin/env bash
# CI job (make check): one clang build with ASan+UBSan and libFuzzer coverage instrumentation,
# shared by the unit tests of the parsers and the engine and by the fuzz targets (fuzz/README.md).
#   1. the unit tests of libs/tree, stages/import and the engine (recipes, graph, cache, builds,
#      their bad-input and mutation tests) under ASan+UBSan, stopping at the first report;
#   2. every fuzz target over its committed corpus (fuzz/corpus/<target>/: valid and bad inputs);
#   3. every fuzz target for FUZZ_SECONDS (default 20) of new inputs.
# Any sanitizer report, crash, broken target contract, leak, timeout (> 10 s per input) or
# allocation above 2 GiB fails the job; libFuzzer saves the input in out/fuzz-artifacts/.
# usage: .ci/sanitize.sh [BUILD_DIR]   (default out/build-san; JOBS, FUZZ_SECONDS from the env)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-out/build-san}
jobs=${JOBS:-2}
seconds=${FUZZ_SECONDS:-20}
fuzzers=(fuzz_recipe fuzz_qsm fuzz_skeleton fuzz_sylt fuzz_gltf fuzz_camera fuzz_lodchain fuzz_mesh_gltf fuzz_mesh_assimp)
tests=(sylva_tree_tests sylva_import_tests sylva_engine_test)
start=$(date +%s)

if [ ! -f "$build/build.ninja" ]; then
  CC=clang CXX=clang++ cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=None \
    -DCMAKE_CXX_FLAGS="-O1 -gline-tables-only" -DSYLVA_SANITIZE=address,undefined -DSYLVA_FUZZ=ON \
    >"$build.configure.log" 2>&1 || { cat "$build.configure.log" >&2; exit 1; }
  rm -f "$build.configure.log"
fi
cmake --build "$build" -j "$jobs" --target "${tests[@]}" "${fuzzers[@]}"
echo "sanitize: built in $(($(date +%s) - start)) s"

export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
# Leaks inside third-party libraries sylva cannot fix (Debian's Assimp): fuzz/lsan-suppressions.txt.
export LSAN_OPTIONS="suppressions=$PWD/fuzz/lsan-suppressions.txt:print_suppressions=0"
for t in "${tests[@]}"; do
  bin=$(find "$build" -name "$t" -type f -perm -u+x | head -n 1)
  echo "sanitize: $t"
  "$bin" --gtest_brief=1
done
echo "sanitize: unit tests passed under ASan+UBSan ($(($(date +%s) - start)) s)"

mkdir -p out/fuzz-artifacts
for f in "${fuzzers[@]}"; do
  name=${f#fuzz_}
  corpus=fuzz/corpus/$name
  [ -d "$corpus" ] || { echo "sanitize: no corpus $corpus for $f" >&2; exit 1; }
  scratch=$(mktemp -d "${TMPDIR:-/tmp}/sylva-fuzz-$name.XXXXXX")
  echo "sanitize: $f: $(ls "$corpus" | wc -l) committed inputs, then ${seconds} s of fuzzing"
  # New inputs go to the scratch directory (first), the committed corpus is read only.
  set +e
  "$build/fuzz/$f" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=2048 \
    -print_final_stats=1 -artifact_prefix="out/fuzz-artifacts/$name-" "$scratch" "$corpus" \
    >"out/fuzz-artifacts/$name.log" 2>&1
  rc=$?
  set -e
  rm -rf "$scratch"
  if [ $rc -ne 0 ]; then
    tail -n 60 "out/fuzz-artifacts/$name.log" >&2
    echo "sanitize: $f FAILED (exit $rc); the input is in out/fuzz-artifacts/$name-*" >&2
    exit 1
  fi
  grep -E '^stat::number_of_executed_units' "out/fuzz-artifacts/$name.log" || true
done
echo "sanitize: all passed in $(($(date +%s) - start)) s"
