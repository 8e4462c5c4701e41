#!/usr/bin/env bash
# The unit tests and the command-line refusal checks under AddressSanitizer
# and UndefinedBehaviorSanitizer (-DDBA_SANITIZE=ON, in build-sanitize/): any
# report aborts the test that made it. Not part of scripts/test.sh: the
# sanitized build and run take about 15 minutes on 2 cores, beside the
# suite's 5 (CI's budget is 20).
# Usage: bash scripts/test-sanitizers.sh
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build-sanitize -DDBA_SANITIZE=ON -DDBA_BUILD_BENCHMARKS=OFF -DDBA_PYTHON=OFF >/dev/null
cmake --build build-sanitize -j"$(nproc 2>/dev/null || echo 2)" --target dba dba_tests >/dev/null
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
OMP_NUM_THREADS=2 build-sanitize/dba_tests --gtest_brief=1
bash tests/cli_refusals.sh "$PWD/build-sanitize/dba" "$PWD"
