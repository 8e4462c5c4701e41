#!/usr/bin/env bash
# dba against Ceres, side by side on the same machine in the same run
# (issue 3). For every BAL problem given (default: ../shared/data/bal/*.bz2)
# and synthetic problems made on the fly (disjoint copies of Dubrovnik-16,
# up to 512 cameras and 2.7M observations), runs dba and Ceres alternately
# under /usr/bin/time -v, several times each, and writes:
#   bench/results/compare.md      the table (medians of time and peak memory)
#   bench/results/cost_vs_time.png cost against time of both on one problem
# Needs minutes (about 15 in the default mode on 2 cores): not part of CI.
#
#   bash bench/compare.sh [--repeats N] [--quick] [--threads N] [PROBLEM...]
#     --quick      one run each, real problems only
#     --repeats N  runs per solver and problem (default 3)
#     --threads N  threads for both solvers (default: all cores)
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
repeats=3
quick=0
threads=$(nproc)
problems=()
while [ $# -gt 0 ]; do
  case "$1" in
    --repeats) repeats=$2; shift 2 ;;
    --quick) quick=1; repeats=1; shift ;;
    --threads) threads=$2; shift 2 ;;
    -h|--help) sed -n 2,16p "$0"; exit 0 ;;
    *) problems+=("$1"); shift ;;
  esac
done

# Install what is missing (idempotent), then build with the Ceres baseline.
bash scripts/install-deps.sh
missing=()
for p in libceres-dev gnuplot-nox; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  DEBIAN_FRONTEND=noninteractive apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target dba ceres_bal >/dev/null

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
if [ ${#problems[@]} -eq 0 ]; then
  problems=(../shared/data/bal/*.bz2)
  if [ "$quick" = 0 ]; then
    for k in 4 32; do
      scripts/replicate-bal.sh ../shared/data/bal/problem-16-22106-pre.txt.bz2 "$k" "$work/dubrovnik16x$k.txt"
      problems+=("$work/dubrovnik16x$k.txt")
    done
  fi
fi

json() { grep -m1 "\"$2\"" "$1" | sed -E 's/.*: "?([^",]*)"?,?/\1/'; }
median() { sort -g | awk '{a[NR] = $1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }
seconds_of() { awk -F': ' '/Elapsed \(wall clock\)/ {n = split($2, t, ":"); s = 0; for (i = 1; i <= n; ++i) s = s * 60 + t[i]; print s}' "$1"; }
kib_of() { awk -F': ' '/Maximum resident set size/ {print $2}' "$1"; }

mkdir -p bench/results
table=bench/results/compare.md
{
  echo "# dba vs Ceres ($(date -u +%Y-%m-%d), commit $(git rev-parse --short HEAD), $(nproc) cores, $(free -g | awk '/Mem:/ {print $2}') GiB, $threads threads each, median of $repeats runs)"
  echo
  echo "| problem | cameras | points | observations | dba final cost | Ceres final cost | agree (0.1%) | dba time (s) | Ceres time (s) | Ceres/dba time | dba peak (MiB) | Ceres peak (MiB) | Ceres/dba memory |"
  echo "|---|---:|---:|---:|---:|---:|:---:|---:|---:|---:|---:|---:|---:|"
} >"$table"

for problem in "${problems[@]}"; do
  name=$(basename "$problem"); name=${name%%.txt*}
  : >"$work/dba_t"; : >"$work/dba_m"; : >"$work/ceres_t"; : >"$work/ceres_m"
  for r in $(seq "$repeats"); do
    /usr/bin/time -v ./build/dba solve "$problem" -q -t "$threads" --report "$work/dba.json" \
      >/dev/null 2>"$work/dba.time"
    seconds_of "$work/dba.time" >>"$work/dba_t"; kib_of "$work/dba.time" >>"$work/dba_m"
    /usr/bin/time -v ./build/bench/ceres_bal "$problem" -t "$threads" --report "$work/ceres.json" \
      >/dev/null 2>"$work/ceres.time"
    seconds_of "$work/ceres.time" >>"$work/ceres_t"; kib_of "$work/ceres.time" >>"$work/ceres_m"
  done
  cp "$work/dba.json" "bench/results/$name.dba.json"
  cp "$work/ceres.json" "bench/results/$name.ceres.json"
  dc=$(json "$work/dba.json" final_cost); cc=$(json "$work/ceres.json" final_cost)
  agree=$(awk -v a="$dc" -v b="$cc" 'BEGIN { d = (a - b) / b; if (d < 0) d = -d; print (d <= 1e-3) ? "yes" : sprintf("no (%.2f%%)", 100 * d) }')
  dt=$(median <"$work/dba_t"); ct=$(median <"$work/ceres_t")
  dm=$(median <"$work/dba_m"); cm=$(median <"$work/ceres_m")
  awk -v n="$name" -v c="$(json "$work/dba.json" num_cameras)" -v p="$(json "$work/dba.json" num_points)" \
      -v o="$(json "$work/dba.json" num_observations)" -v dc="$dc" -v cc="$cc" -v ag="$agree" \
      -v dt="$dt" -v ct="$ct" -v dm="$dm" -v cm="$cm" 'BEGIN {
    printf "| %s | %d | %d | %d | %.6e | %.6e | %s | %.2f | %.2f | %.2fx | %.1f | %.1f | %.2fx |\n",
      n, c, p, o, dc, cc, ag, dt, ct, ct / dt, dm / 1024, cm / 1024, cm / dm }' >>"$table"
  echo "$name: dba $dt s, Ceres $ct s"
done
{
  echo
  echo "Times are wall clock of the whole program (loading included), memory the peak"
  echo "resident set, both from /usr/bin/time -v. Ceres: ITERATIVE_SCHUR + SCHUR_JACOBI,"
  echo "same threads, iteration limit (100) and function tolerance (1e-6) as dba."
} >>"$table"

# Cost against time on one problem, both solvers.
plot_problem=problem-49-7776-pre
if [ -f "bench/results/$plot_problem.dba.json" ]; then
  awk '/"history"/ {h = 1} h && /"cost":/ {gsub(/[",]/, ""); c = $2} h && /"seconds": [0-9]/ {gsub(/,/, ""); t += $2; print t, c}' \
    "bench/results/$plot_problem.dba.json" >"$work/dba.dat"
  awk '/"history"/ {h = 1} h && /"cost":/ {gsub(/[",]/, ""); c = $2} h && /"cumulative_seconds":/ {gsub(/,/, ""); print $2, c}' \
    "bench/results/$plot_problem.ceres.json" >"$work/ceres.dat"
  gnuplot <<GP
set terminal pngcairo size 900,600 noenhanced
set output "bench/results/cost_vs_time.png"
set title "$plot_problem: cost against time ($threads threads)"
set xlabel "seconds (solver loop)"
set ylabel "cost (1/2 sum r^2)"
set logscale y
set grid
plot "$work/dba.dat" using 1:2 with linespoints title "dba (exact LM, BSMC + PCG)", \
     "$work/ceres.dat" using 1:2 with linespoints title "Ceres ITERATIVE_SCHUR"
GP
fi
cat "$table"
