#!/usr/bin/env bash
# The test command: installs the dependencies, builds, and runs the whole test suite with CTest.
# Then the sanitizer and fuzzing stage (scripts/sanitizer_tests.sh: clang ASan + UBSan build of
# the I/O and geometry unit tests and the libFuzzer targets, 45 s fuzz smoke run; about 6.5 min on
# a bare 2-core machine); SLT_SANITIZERS=0 skips it.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
ctest --test-dir build --output-on-failure -j "$(nproc)"
if [ "${SLT_SANITIZERS:-1}" = 1 ]; then
  bash scripts/sanitizer_tests.sh
fi
