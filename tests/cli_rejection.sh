#!/usr/bin/env bash
# --reject-outliers with its defaults on a generated 300-image photogrammetric
# survey (seed 6) with 1%, 3% and 10% uniform mismatches: the first solve
# starts robust (Cauchy at 2 PX), the rounds drop at least 99.5% of the
# mismatches and at most 2% of the true inliers, and the cameras land within
# 1.15x of the outlier-free solve's error. With 40% mismatches, a squared
# first solve or an unconverged one, the guard stops the run: exit 1, the
# share the round would drop and the option to raise, nothing written (an
# existing output left byte for byte). An explicit --loss is kept.
# Usage: cli_rejection.sh PATH_TO_DBA PROJECT_ROOT
set -uo pipefail
source "$(dirname "$0")/lib/check.sh"
dba=$1

survey() {  # NAME [FRACTION]
  local extra=()
  [ $# -gt 1 ] && extra=(--outliers "$2")
  "$dba" generate "$tmp/$1.dba" --model photo --images 300 --seed 6 "${extra[@]}" \
    --truth "$tmp/$1.truth.dba" >/dev/null
}
cameras() { json_value "$1" ground_truth | python3 -c 'import sys; print(eval(sys.stdin.read())["camera_centre_rms"])'; }

survey clean
"$dba" solve "$tmp/clean.dba" -q -t 2 --truth "$tmp/clean.truth.dba" --report "$tmp/clean.json" >/dev/null 2>&1
check "the outlier-free solve exits 0" test $? -eq 0
clean=$(cameras "$tmp/clean.json")

for f in 0.01 0.03 0.1; do
  survey "m$f" "$f"
  "$dba" solve "$tmp/m$f.dba" -q -t 2 --truth "$tmp/m$f.truth.dba" --reject-outliers 3 \
    -o "$tmp/m$f.out.dba" --report "$tmp/m$f.json" >"$tmp/m$f.log" 2>&1
  check "$f: exits 0" test $? -eq 0
  check "$f: the first solve's loss is cauchy at 6 px, the last squared" json "$tmp/m$f.json" \
    "d['loss'] == {'type': 'cauchy', 'scale_px': 6.0} and d['final_loss']['type'] == 'trivial'"
  check "$f: at least 99.5% of the mismatches dropped" json "$tmp/m$f.json" \
    "d['true_outliers']['outliers_dropped'] >= 0.995 * d['true_outliers']['outliers'] > 0"
  check "$f: at most 2% of the inliers dropped" json "$tmp/m$f.json" \
    "d['true_outliers']['inliers_dropped'] <= 0.02 * d['true_outliers']['inliers']"
  check "$f: the cameras within 1.15x of the outlier-free solve's $clean m" json "$tmp/m$f.json" \
    "d['ground_truth']['camera_centre_rms'] <= 1.15 * $clean"
  check "$f: the output written" test -s "$tmp/m$f.out.dba"
done

# An explicit --loss is the first solve's.
"$dba" solve "$tmp/m0.03.dba" -q -t 2 --reject-outliers 3 --loss huber --loss-scale 2 \
  --report "$tmp/huber.json" >/dev/null 2>&1
check "--loss huber is kept for the first solve" json "$tmp/huber.json" \
  "d['loss'] == {'type': 'huber', 'scale_px': 2.0}"
"$dba" solve "$tmp/m0.03.dba" -q -t 2 --reject-outliers 3 --loss-scale 4 --max-iterations 1 \
  --report "$tmp/scale.json" >/dev/null 2>&1
check "--loss-scale alone sets the robust start's scale" json "$tmp/scale.json" \
  "d['loss'] == {'type': 'cauchy', 'scale_px': 4.0}"

# stopped NAME MESSAGE ARGS...: exit 1 saying MESSAGE; -o over an existing
# file leaves it byte for byte, -o to a new path and --report write nothing.
stopped() {
  local name=$1 message=$2; shift 2
  printf 'existing output\n' >"$tmp/existing.dba"
  "$dba" solve "$@" -q -t 2 -o "$tmp/existing.dba" --report "$tmp/$name.json" >"$tmp/$name.log" 2>&1
  check "$name: exit 1" test $? -eq 1
  check "$name: says '$message'" contains "$tmp/$name.log" "$message"
  check "$name: the existing output left byte for byte" test "$(cat "$tmp/existing.dba")" = "existing output"
  check "$name: no report" test ! -e "$tmp/$name.json"
  "$dba" solve "$@" -q -t 2 -o "$tmp/$name.new.dba" >/dev/null 2>&1
  check "$name: no new output" test ! -e "$tmp/$name.new.dba"
  check "$name: no temporary" test -z "$(find "$tmp" -name '*.tmp.*')"
}
survey m0.4 0.4
stopped "40% mismatches" "would drop 38509 of 94501 observations (40.7%; with 1 point under --min-triangulation-angle), more than --reject-max-share 0.25: the solve before it did not settle on the inliers, the threshold is below the noise, or that many are mismatches; nothing was written. Raise --reject-max-share (1: no guard) to drop them anyway, or --reject-outliers" \
  "$tmp/m0.4.dba" --reject-outliers 3
stopped "a squared first solve" "would drop 93173 of 94501 observations (98.6%; with 93 points under --min-triangulation-angle), more than --reject-max-share 0.25: the solve before it had the squared loss, which mismatches drag, and stopped at --max-iterations unconverged" \
  "$tmp/m0.03.dba" --reject-outliers 3 --loss trivial
stopped "an unconverged first solve" "would drop 89694 of 94501 observations (94.9%), more than --reject-max-share 0.25: the solve before it stopped at --max-iterations unconverged" \
  "$tmp/m0.03.dba" --reject-outliers 3 --max-iterations 0
# The guard raised: the 40% survey goes through.
"$dba" solve "$tmp/m0.4.dba" -q -t 2 --reject-outliers 3 --reject-max-share 0.5 -o "$tmp/m0.4.out.dba" \
  >/dev/null 2>&1
check "40% mismatches with --reject-max-share 0.5: exit 0, written" test $? -eq 0 -a -s "$tmp/m0.4.out.dba"

finish
