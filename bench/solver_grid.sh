#!/usr/bin/env bash
# The linear-solver grid of bench/README.md ("Linear solvers"): every problem
# with each setting of the grid fixed below, then the best setting per
# problem re-timed alternately with the defaults (medians of --repeats).
# Writes a markdown table to stdout (and the reports to --out DIR):
#   problem x setting -> LM iterations, PCG iterations, seconds per phase,
#   final cost; then per problem: the defaults against the best setting.
# About 15 minutes for the default problems on 2 cores: not part of CI.
#
#   bash bench/solver_grid.sh [--repeats N] [--threads N] [--timeout S] [--out DIR] PROBLEM...
# --timeout S: a run of the grid stopped after S seconds (default 300) is
# reported as "timed out" (u2500 dense takes 13 minutes).
# PROBLEM: anything dba solve reads. Default: problem-49-7776 and
# problem-73-11032 from ../shared/data/bal, and two generated surveys
# (dba generate --images 2500, and --images 10000 --seed 3).
set -euo pipefail
cd "$(dirname "$0")/.."
repeats=3
threads=$(nproc)
time_limit=300
out=$(mktemp -d)
problems=()
while [ $# -gt 0 ]; do
  case "$1" in
    --repeats) repeats=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --timeout) time_limit=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    -h|--help) sed -n '2,15p' "$0"; exit 0 ;;
    *) problems+=("$1"); shift ;;
  esac
done
mkdir -p "$out"
dba=./build/dba
[ -x "$dba" ] || bash scripts/build.sh >/dev/null
if [ ${#problems[@]} -eq 0 ]; then
  problems=(../shared/data/bal/problem-49-7776-pre.txt.bz2 ../shared/data/bal/problem-73-11032-pre.txt.bz2)
  [ -f "$out/u2500.txt" ] || "$dba" generate "$out/u2500.txt" --images 2500 >/dev/null
  [ -f "$out/s10k.dba" ] || "$dba" generate "$out/s10k.dba" --images 10000 --seed 3 >/dev/null
  problems+=("$out/u2500.txt" "$out/s10k.dba")
fi

# The grid, fixed in advance: name and dba solve options.
grid=(
  "defaults|"
  "dense|--linear-solver dense"
  "sparse|--linear-solver sparse"
  "pcg jacobi eta 0.1|--linear-solver pcg --preconditioner jacobi --eta 0.1"
  "pcg two-level eta 0.1|--linear-solver pcg --preconditioner two-level --eta 0.1"
  "pcg two-level rigid eta 0.1|--linear-solver pcg --preconditioner two-level --coarse-basis rigid --eta 0.1"
  "pcg two-level eta 0.3|--linear-solver pcg --preconditioner two-level --eta 0.3"
  "pcg two-level 32 eta 0.1|--linear-solver pcg --preconditioner two-level --coarse-size 32 --eta 0.1"
)

run() {  # run PROBLEM OPTIONS REPORT -> wall seconds
  local start end status=0
  start=$(date +%s.%N)
  # shellcheck disable=SC2086
  timeout "$time_limit" "$dba" solve "$1" -t "$threads" -q $2 --report "$3" >/dev/null 2>&1 || status=$?
  if [ "$status" -eq 124 ]; then echo "timed_out"; return; fi
  if [ "$status" -ne 0 ]; then echo "failed"; return; fi
  end=$(date +%s.%N)
  echo "$end - $start" | bc
}
row() {  # row REPORT -> table cells
  jq -r '[.linear_solver.type, .iterations, .pcg_iterations, .seconds.rcs_formation, .seconds.linear_solve,
    .seconds.back_substitution, .seconds.total, (.final_cost | tostring),
    ([.history[] | select(.linear_stop == "iteration_limit")] | length)] | @tsv' "$1" |
    awk -F'\t' '{printf "%s | %s | %s | %.2f | %.2f | %.2f | %.2f | %s | %s", $1, $2, $3, $4, $5, $6, $7, $8, $9}'
}
median() { sort -g | awk '{a[NR]=$1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }

echo "| problem | setting | solver | LM iterations | PCG iterations | formation s | linear solve s | back-substitution s | total s | final cost | PCG at cap |"
echo "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|"
declare -A best_name best_opts
for p in "${problems[@]}"; do
  name=$(basename "$p"); name=${name%%.*}
  best=""
  for entry in "${grid[@]}"; do
    label=${entry%%|*}; opts=${entry#*|}
    report="$out/$name.${label// /_}.json"
    wall=$(run "$p" "$opts" "$report")
    if [ "$wall" = failed ] || [ "$wall" = timed_out ]; then echo "| $name | $label | ${wall/_/ } |"; continue; fi
    echo "| $name | $label | $(row "$report") |"
    if [ "$label" != defaults ] && { [ -z "$best" ] || (( $(echo "$wall < $best" | bc) )); }; then
      best=$wall; best_name[$name]=$label; best_opts[$name]=$opts
    fi
  done
done
echo
echo "Defaults against the best setting of the grid, alternating, medians of $repeats runs (wall seconds):"
echo
echo "| problem | best setting | defaults s | best s | defaults / best |"
echo "|---|---|---:|---:|---:|"
for p in "${problems[@]}"; do
  name=$(basename "$p"); name=${name%%.*}
  d=(); b=()
  for ((i = 0; i < repeats; i++)); do
    d+=("$(run "$p" "" "$out/$name.d$i.json")")
    b+=("$(run "$p" "${best_opts[$name]}" "$out/$name.b$i.json")")
  done
  dm=$(printf '%s\n' "${d[@]}" | median); bm=$(printf '%s\n' "${b[@]}" | median)
  printf "| %s | %s | %.2f | %.2f | %.2f |\n" "$name" "${best_name[$name]}" "$dm" "$bm" "$(echo "$dm / $bm" | bc -l)"
done
