#!/usr/bin/env bash
# Every COLMAP model in ../shared/data/colmap solved in both forms of the
# photogrammetric model: shared intrinsics (one group per COLMAP
# camera) and one intrinsic group per image. Prints a Markdown table: images,
# groups, points, observations, unknowns, initial and final RMS
# (sqrt(2F/observations), pixels), iterations, termination and time.
# About a minute; not part of CI.
#
#   bash bench/colmap.sh [EXTRA dba solve OPTIONS...]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh >/dev/null
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
json() { grep -m1 "\"$2\"" "$1" | sed -E 's/.*: "?([^",]*)"?,?/\1/'; }

echo "| model | intrinsics | images | groups | points | observations | unknowns (camera-side) | initial RMS (px) | final RMS (px) | iterations | termination | time (s) |"
echo "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|"
for dir in ../shared/data/colmap/*/sparse/0; do
  model=$(basename "$(dirname "$(dirname "$dir")")")
  for form in shared per-image; do
    r=$work/$model-$form.json
    ./build/dba solve "$dir" -q --intrinsics "$form" --report "$r" "$@" >/dev/null
    printf "| %s | %s | %s | %s | %s | %s | %s (%s) | %.4f | %.4f | %s | %s | %.2f |\n" \
      "$model" "$form" "$(json "$r" num_cameras)" "$(json "$r" num_intrinsic_groups)" \
      "$(json "$r" num_points)" "$(json "$r" num_observations)" "$(json "$r" unknowns)" \
      "$(json "$r" camera_unknowns)" "$(json "$r" initial_rms_px)" "$(json "$r" final_rms_px)" \
      "$(json "$r" iterations)" "$(json "$r" termination)" "$(json "$r" total)"
  done
done
