#!/usr/bin/env bash
# The sanitizer stage of CI (issue 21): one clang build in build-sanitize/ with ASan + UBSan
# (ENABLE_SANITIZERS) and the libFuzzer targets (BUILD_FUZZERS), sharing the instrumented
# libraries. Builds only the unit-test targets of the I/O and geometry layers and the programs
# they run, runs them clean, then the fuzz smoke run (scripts/fuzz_smoke.sh, 45 s).
# -O1 and no NDEBUG: fast to compile, Eigen's and the project's asserts on.
# Usage: scripts/sanitizer_tests.sh   (ccache is used when installed)
set -euo pipefail
cd "$(dirname "$0")/.."
build=build-sanitize
launcher=()
if command -v ccache > /dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
tests=(common_test geometry_test dataset_test evaluation_test simulator_test)
fuzzers=(stereo_lines_fuzzer trajectory_fuzzer config_fuzzer)
start=$(date +%s)
cmake -S . -B "$build" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=Sanitize \
  -DCMAKE_CXX_FLAGS_SANITIZE="-O1 -g1" -DENABLE_SANITIZERS=ON -DBUILD_FUZZERS=ON \
  -DSLT_BUILD_BENCHMARKS=OFF "${launcher[@]}" > /dev/null
cmake --build "$build" -j "$(nproc)" --target "${tests[@]}" "${fuzzers[@]}"
built=$(date +%s)
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
for t in "${tests[@]}"; do
  echo "sanitizer_tests: $t"
  "$build/bin/$t" --gtest_brief=1
done
tested=$(date +%s)
bash scripts/fuzz_smoke.sh "$build"
echo "sanitizer_tests: build $((built - start)) s, tests $((tested - built)) s, fuzz $(( $(date +%s) - tested )) s"
