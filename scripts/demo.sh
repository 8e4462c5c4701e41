#!/usr/bin/env bash
# The main job: installs what is missing, builds, and bundle-adjusts the
# Ladybug problem shipped in data/ (49 cameras, 7776 points, 31843
# observations), writing the result and a JSON report to out/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
mkdir -p out
./build/dba solve data/problem-49-7776-pre.txt.bz2 \
  -o out/problem-49-7776-adjusted.txt --report out/problem-49-7776-report.json "$@"
