#!/usr/bin/env bash
# The installed CMake package: `cmake --install` into a temporary prefix puts
# the library, headers and dbaConfig.cmake there; examples/ configures with
# find_package(dba) against that prefix only, builds, and bundle-adjusts the
# shipped Ladybug problem to its exact final cost (1.334432e+04, as
# src/dba/lm/bal_problems_test.cc).
# Usage: install_and_build_example.sh BUILD_DIR PROJECT_ROOT
set -uo pipefail
source "$(dirname "$0")/../lib/check.sh"
build=$1
root=$2
prefix=$tmp/prefix

cmake --install "$build" --prefix "$prefix" >"$tmp/install.log" 2>&1
check "cmake --install succeeds" test $? -eq 0
for f in lib/cmake/dba/dbaConfig.cmake lib/cmake/dba/dbaConfigVersion.cmake \
         lib/cmake/dba/dbaTargets.cmake bin/dba \
         include/dba/lm/bundle_adjust.h include/dba/io/read_problem.h; do
  check "installed $f" test -f "$prefix/$f"
done
# One static library per module (src/dba/CMakeLists.txt; problem is headers only).
for m in common bsmc camera io solver rcs lm cluster synthetic app; do
  check "installed lib/libdba_$m.a" test -f "$prefix/lib/libdba_$m.a"
done
check "test helpers are not installed" test ! -e "$prefix/include/dba/testing"
check "the test library is not installed" test ! -e "$prefix/lib/libdba_testing.a"
check "internal headers are not installed" test ! -e "$prefix/include/dba/io/colmap_model_internal.h"
check "a public header is installed beside it" test -f "$prefix/include/dba/io/colmap_model.h"

# Only the prefix: the example must not see the source or build trees.
cmake -S "$root/examples" -B "$tmp/example-build" -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_BUILD_TYPE=Release >"$tmp/configure.log" 2>&1
check "examples/ configures with find_package(dba)" test $? -eq 0 || cat "$tmp/configure.log" >&2
cmake --build "$tmp/example-build" -j2 >"$tmp/build.log" 2>&1
check "examples/ builds against dba::dba" test $? -eq 0 || cat "$tmp/build.log" >&2
check "the example includes the installed headers" \
  lacks "$tmp/example-build/CMakeFiles/bundle_adjust_bal.dir/flags.make" "$root/src"

"$tmp/example-build/bundle_adjust_bal" "$root/data/problem-49-7776-pre.txt.bz2" 2 >"$tmp/out" 2>&1
check "the example runs" test $? -eq 0
cat "$tmp/out"
final=$(awk '/^final cost/ {print $3}' "$tmp/out")
check "final cost is the exact optimum 1.334432e+04 (within 1e-5 relative)" \
  awk -v c="${final:-0}" 'BEGIN { d = c - 13344.32; if (d < 0) d = -d; exit !(d <= 0.1334432) }'
check "initial cost is the problem's 8.509125e+05" contains "$tmp/out" "initial cost 8.509125e+05"
finish
