#!/bin/bash
# --reject-outliers with its defaults on generated photogrammetric surveys
# with uniform mismatches (bench/README.md, "Rejection that starts robust"):
# one survey per fraction, the same seed (the mismatches come from their own
# stream, so the inliers are the outlier-free survey's), solved with
# --reject-outliers PX and --truth; a table of the mismatches and inliers
# dropped, the first round's share, the camera centres' RMS after a
# similarity against the outlier-free solve's, and the exit status (the guard
# stops a survey whose round would drop more than --reject-max-share).
#
#   bash bench/rejection.sh [--images N] [--seed S] [--fractions "0.01 0.03 0.1 0.4"]
#                           [--threshold PX] [--threads T] [--out DIR] [-- SOLVE_ARGS...]
# SOLVE_ARGS go to every solve, the outlier-free one too (e.g. the exact
# optima: -- --linear-solver sparse --function-tolerance 1e-10).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
images=2500 seed=11 fractions="0.01 0.03 0.1 0.4" threshold=3 threads=2 out=""
while [ $# -gt 0 ]; do
  case "$1" in
    --images) images=$2; shift 2 ;;
    --seed) seed=$2; shift 2 ;;
    --fractions) fractions=$2; shift 2 ;;
    --threshold) threshold=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --) shift; break ;;
    *) echo "usage: bash bench/rejection.sh [--images N] [--seed S] [--fractions LIST] [--threshold PX] [--threads T] [--out DIR] [-- SOLVE_ARGS...]" >&2; exit 2 ;;
  esac
done
dba=${DBA:-$root/build/dba}
work=${out:-$(mktemp -d)}
mkdir -p "$work"

survey() {  # fraction -> its files' prefix (generated once)
  local p=$work/s$images.$seed.$1
  if [ ! -e "$p.dba" ]; then
    local extra=()
    [ "$1" = 0 ] || extra=(--outliers "$1")
    "$dba" generate "$p.dba" --model photo --images "$images" --seed "$seed" "${extra[@]}" \
      --truth "$p.truth.dba" >/dev/null
  fi
  echo "$p"
}

clean=$(survey 0)
"$dba" solve "$clean.dba" -q -t "$threads" --truth "$clean.truth.dba" --report "$clean.json" "$@" \
  >/dev/null
echo "outlier-free: camera centres $(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["ground_truth"]["camera_centre_rms"])' "$clean.json") m"
echo "| mismatches | exit | mismatches dropped | inliers dropped | round 1 drops | rounds | camera centres (RMS, m) | against outlier-free |"
echo "|---:|---:|---:|---:|---:|---:|---:|---:|"
for f in $fractions; do
  p=$(survey "$f")
  rm -f "$p.json"
  status=0
  "$dba" solve "$p.dba" -q -t "$threads" --truth "$p.truth.dba" --reject-outliers "$threshold" \
    --report "$p.json" "$@" >"$p.log" 2>&1 || status=$?
  python3 - "$f" "$status" "$p.json" "$clean.json" "$p.log" <<'PY'
import json, os, re, sys
f, status, path, clean, log = sys.argv[1:6]
if not os.path.exists(path):
    m = re.search(r"would drop \d+ of \d+ observations \(([\d.]+%)\)", open(log).read())
    print(f"| {float(f):.0%} | {status} | - | - | {m.group(1) if m else '?'} (stopped) | - | - | - |")
    sys.exit()
r, c = json.load(open(path)), json.load(open(clean))
t, rounds = r["true_outliers"], r["outlier_rejection"]["rounds"]
first = rounds[0]["observations_dropped"] / (rounds[0]["observations_dropped"] + rounds[0]["observations_left"])
cam, ref = r["ground_truth"]["camera_centre_rms"], c["ground_truth"]["camera_centre_rms"]
print(f"| {float(f):.0%} | {status} | {100 * t['outliers_dropped'] / t['outliers']:.3f}% "
      f"({t['outliers_dropped']:,} of {t['outliers']:,}) | {100 * t['inliers_dropped'] / t['inliers']:.3f}% | "
      f"{100 * first:.2f}% | {len(rounds)} | {cam:.4f} | {cam / ref:.3f}x |")
PY
done
