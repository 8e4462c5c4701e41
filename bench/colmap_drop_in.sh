#!/usr/bin/env bash
# `colmap bundle_adjuster` (Debian's COLMAP 3.8) against `dba
# colmap-bundle-adjuster` with the same flags, on every COLMAP model in
# ../shared/data/colmap (CI runs the two small ones,
# tests/cli_colmap_interop.sh; softmurata_177img takes COLMAP up to 10
# minutes, so this is not part of CI). Both outputs are evaluated by one
# reader (dba solve --max-iterations 0): the final cost, its relative
# difference, and each tool's wall time (every core, both).
# Prints a Markdown table.
#
#   bash bench/colmap_drop_in.sh [COLMAP FLAGS...]    e.g. --BundleAdjustment.refine_principal_point 1
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh >/dev/null
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# COLMAP's bundle_adjuster runs Ceres on every core; dba gets as many.
export QT_QPA_PLATFORM=offscreen
threads=$(nproc)
cost() {
  ./build/dba solve "$1" -q --max-iterations 0 --report "$work/c.json" >/dev/null &&
    python3 -c 'import json, sys; print(repr(json.load(open(sys.argv[1]))["initial_cost"]))' "$work/c.json"
}
seconds() { /usr/bin/time -f %e "$@" 2>&1 >/dev/null | tail -1; }

echo "| model | COLMAP final cost | dba final cost | relative difference | COLMAP time (s) | dba time (s) | COLMAP / dba |"
echo "|---|---:|---:|---:|---:|---:|---:|"
for dir in ../shared/data/colmap/*/sparse/0; do
  model=$(basename "$(dirname "$(dirname "$dir")")")
  mkdir -p "$work/$model.c" "$work/$model.d"
  tc=$(seconds colmap bundle_adjuster --input_path "$dir" --output_path "$work/$model.c" "$@")
  td=$(seconds ./build/dba colmap-bundle-adjuster --input_path "$dir" --output_path "$work/$model.d" \
    --threads "$threads" "$@")
  c=$(cost "$work/$model.c"); d=$(cost "$work/$model.d")
  python3 -c 'import sys; m, c, d, tc, td = sys.argv[1], *map(float, sys.argv[2:])
print(f"| {m} | {c:.10g} | {d:.10g} | {(d - c) / c:.2e} | {tc:.2f} | {td:.2f} | {tc / td:.2f} |")' \
    "$model" "$c" "$d" "$tc" "$td"
done
