#!/bin/bash
# Robust losses and outlier rejection on a generated survey with mismatches
# (issue "Robust losses and outlier rejection"). Generates the same survey
# twice with one seed, without and with a fraction of mismatches (uniform
# random pixels at least 50 px from the true projection), solves the clean one
# with the squared loss and the one with mismatches with the squared loss and
# with robust losses plus --reject-outliers, all with --truth, and prints a
# table: RMS to the noise-free observations, camera-centre and point errors
# after a similarity, outliers caught, inliers wrongly dropped, time.
#
#   bash bench/outliers.sh [--images N] [--outliers F] [--threads T] [--out DIR]
# Defaults: 10,000 images, 5% mismatches, 2 threads; about 5 minutes here.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
images=10000 outliers=0.05 threads=2 out=""
while [ $# -gt 0 ]; do
  case "$1" in
    --images) images=$2; shift 2 ;;
    --outliers) outliers=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    *) echo "usage: bash bench/outliers.sh [--images N] [--outliers F] [--threads T] [--out DIR]" >&2; exit 2 ;;
  esac
done
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$root/build" -j"$(nproc)" --target dba >/dev/null
dba=$root/build/dba
work=${out:-$(mktemp -d)}
mkdir -p "$work"
"$dba" generate "$work/clean.dba" --images "$images" --seed 11 --truth "$work/clean.truth.dba" >/dev/null
"$dba" generate "$work/mixed.dba" --images "$images" --seed 11 --outliers "$outliers" \
  --truth "$work/mixed.truth.dba" >/dev/null

run() {  # name input truth args...
  local name=$1 input=$2 truth=$3; shift 3
  /usr/bin/time -f "%e" -o "$work/$name.time" "$dba" solve "$input" -t "$threads" -q --truth "$truth" \
    --report "$work/$name.json" "$@" >"$work/$name.log" 2>&1 || { echo "$name failed:" >&2; tail "$work/$name.log" >&2; return 1; }
  python3 - "$name" "$work/$name.json" "$work/$name.time" "$*" <<'PY'
import json, sys
name, path, tpath, args = sys.argv[1:5]
r = json.load(open(path))
g = r["ground_truth"]
t = r.get("true_outliers")
caught = f'{100.0 * t["outliers_dropped"] / max(t["outliers"], 1):.2f}%' if t else "-"
wrong = f'{100.0 * t["inliers_dropped"] / max(t["inliers"], 1):.3f}%' if t else "-"
print(f'| {name} | `{args or "(defaults)"}` | {r["final_rms_px"]:.4f} | {g["rms_to_noise_free_px"]:.4f} | '
      f'{g["camera_centre_rms"]:.4f} | {g["point_rms"]:.4f} | {caught} | {wrong} | '
      f'{r["iterations"]} | {float(open(tpath).read()):.1f} |')
PY
}
echo "| run | options | final RMS px | RMS to noise-free px | camera centres (RMS, m) | points (RMS, m) | true outliers dropped | true inliers dropped | LM iterations | wall s |"
echo "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|"
run clean "$work/clean.dba" "$work/clean.truth.dba"
run squared "$work/mixed.dba" "$work/mixed.truth.dba"
run cauchy "$work/mixed.dba" "$work/mixed.truth.dba" --loss cauchy --loss-scale 2
run cauchy-reject "$work/mixed.dba" "$work/mixed.truth.dba" --loss cauchy --loss-scale 2 --reject-outliers 4
run huber-reject "$work/mixed.dba" "$work/mixed.truth.dba" --loss huber --loss-scale 2 --reject-outliers 4
[ -n "$out" ] || rm -rf "$work"
