#!/usr/bin/env bash
# Configures and builds dba (Release) into build/.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)
# Ninja: it compiles a module's files while the modules below it still link
# (make waits for each library first), keeping both cores busy to the end
# (bench/README.md, "The suite's time"). A build directory made by another
# generator keeps it.
generator=()
[ -f build/CMakeCache.txt ] || generator=(-G Ninja)
cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$jobs"
