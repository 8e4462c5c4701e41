#!/usr/bin/env bash
# Where `dba colmap-bundle-adjuster` leaves the model against `colmap
# bundle_adjuster` (Debian's COLMAP 3.8), both with COLMAP's defaults, on
# every COLMAP model in ../shared/data/colmap (CI runs the two small ones,
# tests/cli_colmap_gauge.sh; softmurata_177img takes COLMAP minutes). Of
# dba's centres against COLMAP's (tests/lib/gauge_check.py): the farthest
# apart, the centroids apart, the RMS spreads' ratio - 1, the mean
# orientations' angle, all but the angle over COLMAP's RMS spread; and both
# final costs (one reader: dba solve --max-iterations 0). Prints a Markdown
# table. `--dba PATH` compares another build's drop-in.
#
#   bash bench/colmap_drop_in_gauge.sh [--dba PATH]
set -euo pipefail
cd "$(dirname "$0")/.."
dba=./build/dba
[ "${1:-}" = --dba ] && dba=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export QT_QPA_PLATFORM=offscreen
cost() {
  ./build/dba solve "$1" -q --max-iterations 0 --report "$work/c.json" >/dev/null &&
    python3 -c 'import json, sys; print(repr(json.load(open(sys.argv[1]))["initial_cost"]))' "$work/c.json"
}
echo "| model | farthest centre apart | centroids apart | spread ratio - 1 | orientation (rad) | COLMAP final cost | dba final cost |"
echo "|---|---:|---:|---:|---:|---:|---:|"
for dir in ../shared/data/colmap/*/sparse/0; do
  model=$(basename "$(dirname "$(dirname "$dir")")")
  mkdir -p "$work/$model.c" "$work/$model.d"
  colmap bundle_adjuster --input_path "$dir" --output_path "$work/$model.c" >/dev/null 2>&1
  "$dba" colmap-bundle-adjuster --input_path "$dir" --output_path "$work/$model.d" >/dev/null 2>&1
  for side in c d; do
    ./build/dba solve "$work/$model.$side" -q --max-iterations 0 --gauge free -o "$work/$model.$side.t" \
      --colmap-format text >/dev/null
  done
  read -r _ centroid _ spread _ orientation _ overlay < <(/usr/bin/python3 tests/lib/gauge_check.py overlay \
    "$work/$model.c.t" "$work/$model.d.t" 0 --print)
  echo "| $model | $overlay | $centroid | $spread | $orientation | $(cost "$work/$model.c") | $(cost "$work/$model.d") |"
done
