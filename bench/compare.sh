#!/usr/bin/env bash
# dba against Ceres, side by side on the same machine in the same run
# (issue 3). For every BAL problem given (default: ../shared/data/bal/*.bz2)
# and synthetic problems made on the fly at growing sizes, runs dba and the
# Ceres baseline (bench/ceres_bal.cc) alternately under /usr/bin/time -v,
# several times each, and writes to bench/results/ (or --out DIR):
#   compare.md          the tables: final costs and whether they agree to
#                       0.1% (and why not), median wall time, time to reach
#                       the best final cost, median peak memory, ratios
#                       Ceres/dba, the background load during the runs; and
#                       where each solver's time goes
#   cost_vs_time.png    cost against time of both solvers on one problem
#   <problem>.{dba,ceres}.json   the reports of each solver's median run
# Needs about 14 minutes in the default mode on 2 cores: not part of CI.
#
#   bash bench/compare.sh [options] [PROBLEM...]
#     --repeats N        runs per solver and problem (default 3)
#     --quick            one run each: the real problems and uav:1000
#     --threads N        threads for both solvers (default: all cores)
#     --synthetic LIST   synthetic problems, space separated (default
#                        "copies:16 uav:250 uav:1000 uav:4000"):
#                          uav:N[:F]  dba generate, N images, F features
#                                     per image (default 300), .dba
#                          copies:K   K disjoint copies of Dubrovnik-16
#                                     (scripts/replicate-bal.sh; optimum
#                                     K x the original's)
#                        "" for none
#     --plot NAME        problem of the cost-versus-time plot (default: the
#                        last one, uav-4000 in the default mode)
#     --plot-only NAME   only redraw the plot from DIR/NAME.{dba,ceres}.json
#     --max-wait S       before each run, wait up to S seconds (default 60)
#                        for other processes to use less than 0.3 cores
#     --out DIR          output directory (default bench/results)
#     --target-gap X     "to best" columns: time to within X of the lowest
#                        final cost (default 1e-3, the 0.1% of agreement)
#     --max-iterations N, --function-tolerance X   for both (100, 1e-6)
# PROBLEM: BAL text (plain or .bz2) or .dba files; given, they replace the
# default real problems (the synthetic ones are still added unless
# --synthetic "").
set -euo pipefail
cd "$(dirname "$0")/.."
repeats=3
quick=0
threads=$(nproc)
synthetic="copies:16 uav:250 uav:1000 uav:4000"
synthetic_set=0
plot=""
plot_only=0
max_wait=60
out=bench/results
max_iterations=100
target_gap=1e-3
function_tolerance=1e-6
problems=()
while [ $# -gt 0 ]; do
  case "$1" in
    --repeats) repeats=$2; shift 2 ;;
    --quick) quick=1; shift ;;
    --threads) threads=$2; shift 2 ;;
    --synthetic) synthetic=$2; synthetic_set=1; shift 2 ;;
    --plot) plot=$2; shift 2 ;;
    --plot-only) plot=$2; plot_only=1; shift 2 ;;
    --max-wait) max_wait=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --target-gap) target_gap=$2; shift 2 ;;
    --max-iterations) max_iterations=$2; shift 2 ;;
    --function-tolerance) function_tolerance=$2; shift 2 ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d'; exit 0 ;;
    -*) echo "compare.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
    *) problems+=("$1"); shift ;;
  esac
done
if [ "$quick" = 1 ]; then
  repeats=1
  [ "$synthetic_set" = 1 ] || synthetic="uav:1000"
fi

work=$(mktemp -d /tmp/dba-compare.XXXXXX)
trap 'rm -rf "$work"' EXIT
mkdir -p "$out"

problem_name() { local n; n=$(basename "$1"); n=${n%.bz2}; n=${n%.txt}; n=${n%.dba}; echo "$n"; }
median() { sort -g | awk '{a[NR] = $1} END {if (NR == 0) print "nan"; else print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }
seconds_of() { awk -F': ' '/Elapsed \(wall clock\)/ {n = split($2, t, ":"); s = 0; for (i = 1; i <= n; ++i) s = s * 60 + t[i]; print s}' "$1"; }
kib_of() { awk -F': ' '/Maximum resident set size/ {print $2}' "$1"; }
cpu_of() { awk -F': ' '/User time|System time/ {s += $2} END {print s}' "$1"; }
# Jiffies all CPUs spent busy so far (user nice system irq softirq steal).
busy_jiffies() { awk '/^cpu / {print $2 + $3 + $4 + $7 + $8 + $9}' /proc/stat; }
hz=$(getconf CLK_TCK)
# Cores used by other processes over the next second, in bg_cores; the start
# of that second in sample_jiffies / sample_time. (No subshell: it sets them.)
background() {
  sample_time=$(date +%s.%N); sample_jiffies=$(busy_jiffies); sleep 1
  bg_cores=$(awk -v a="$sample_jiffies" -v b="$(busy_jiffies)" -v hz="$hz" -v t0="$sample_time" \
    -v t1="$(date +%s.%N)" 'BEGIN {printf "%.2f", (b - a) / hz / (t1 - t0)}')
}
wait_quiet() {
  local waited=0
  while :; do
    background
    awk -v x="$bg_cores" 'BEGIN {exit !(x < 0.3)}' && return 0
    [ "$waited" -ge "$max_wait" ] && { echo "  (machine busy: $bg_cores cores in use by others; running anyway)"; return 0; }
    sleep 4; waited=$((waited + 5))
  done
}

# run SOLVER PROBLEM TAG: one timed run; leaves $work/TAG.{json,time,bg}.
run() {
  local solver=$1 problem=$2 tag=$3
  wait_quiet
  if [ "$solver" = dba ]; then
    /usr/bin/time -v $dba solve "$problem" -q -t "$threads" --max-iterations "$max_iterations" \
      --function-tolerance "$function_tolerance" --report "$work/$tag.json" >"$work/$tag.out" 2>"$work/$tag.time"
  else
    /usr/bin/time -v $ceres "$problem" -t "$threads" --max-iterations "$max_iterations" \
      --function-tolerance "$function_tolerance" --report "$work/$tag.json" >"$work/$tag.out" 2>"$work/$tag.time"
  fi
  # Background load: CPU time of the whole machine from the start of the
  # last quiet check (one idle second) to the end of the run, minus the
  # solver's own, per second of that window.
  awk -v a="$sample_jiffies" -v b="$(busy_jiffies)" -v hz="$hz" -v own="$(cpu_of "$work/$tag.time")" \
      -v t0="$sample_time" -v t1="$(date +%s.%N)" \
    'BEGIN {x = ((b - a) / hz - own) / (t1 - t0); printf "%.2f\n", x < 0 ? 0 : x}' >"$work/$tag.bg"
}

# Time (s since the program started, loading included) at which a report's
# cost first reaches TARGET; "none" if never. dba's history gives the cost at
# the start of each iteration and the candidate's; Ceres's the cost at the end.
dba_curve() {
  jq -r '((.seconds.load // 0) + (.seconds.distribution // 0) + (.seconds.setup // 0)) as $s0
    | ([$s0, .initial_cost], (foreach .history[] as $h ($s0; . + $h.seconds;
        [., (if $h.accepted then $h.candidate_cost else $h.cost end)])), [.seconds.total, .final_cost])
    | "\(.[0]) \(.[1])"' "$1"
}
# Ceres does not report its last iteration (the step that meets the function
# tolerance is computed, found too small and dropped): the curve ends with
# the final cost at the total time, as dba's does.
ceres_curve() {
  jq -r '((.seconds.load // 0) + (.seconds.build_problem // 0)) as $s0
    | ((.history[] | [$s0 + .cumulative_seconds, .cost]), [.seconds.total, .final_cost]) | "\(.[0]) \(.[1])"' "$1"
}
# Median time to the target over the runs, "none" if a run never reached it.
tt_of() { if grep -q none "$work/$1.tt"; then echo none; else median <"$work/$1.tt"; fi; }
time_to() {  # CURVE_FILE TARGET
  awk -v t="$2" '$2 <= t {print $1; found = 1; exit} END {if (!found) print "none"}' "$1"
}

# Cost against time on one problem, both solvers (their median runs), from
# the reports in $out: cost, and the gap to the best cost either reached.
draw_plot() {
  local name=$1 best s
  [ -f "$out/$name.dba.json" ] && [ -f "$out/$name.ceres.json" ] || { echo "compare.sh: no reports of $name in $out" >&2; return 1; }
  dba_curve "$out/$name.dba.json" >"$work/dba.curve"
  ceres_curve "$out/$name.ceres.json" >"$work/ceres.curve"
  best=$(cat "$work/dba.curve" "$work/ceres.curve" | awk 'NR == 1 || $2 < b {b = $2} END {printf "%.17g", b}')
  for s in dba ceres; do
    awk -v b="$best" '{g = ($2 - b) / b; print $1, $2, (g > 1e-9 ? g : 1e-9)}' "$work/$s.curve" >"$work/$s.dat"
  done
  gnuplot <<GP
set terminal pngcairo size 1200,500 noenhanced font ",10"
set output "$out/cost_vs_time.png"
set multiplot layout 1,2 title "$name: cost against time, $(jq .threads "$out/$name.dba.json") threads each ($now, $commit)"
set xlabel "seconds since the program started"
set grid
set logscale y
set key top right
set ylabel "cost (1/2 sum r^2)"
plot "$work/dba.dat" using 1:2 with linespoints pt 7 ps 0.6 title "dba (exact LM, BSMC + PCG)", \
     "$work/ceres.dat" using 1:2 with linespoints pt 5 ps 0.6 title "Ceres ITERATIVE_SCHUR + SCHUR_JACOBI"
set ylabel "(cost - best) / best"
set format y "%.0e"
plot "$work/dba.dat" using 1:3 with linespoints pt 7 ps 0.6 title "dba", \
     "$work/ceres.dat" using 1:3 with linespoints pt 5 ps 0.6 title "Ceres", \
     $target_gap with lines dt 2 lc "gray" title "$gap_label"
unset multiplot
GP
  echo "compare.sh: plot of $name in $out/cost_vs_time.png"
}

now=$(date -u +%Y-%m-%d)
gap_label=$(awk -v g="$target_gap" 'BEGIN {printf "%g%%", 100 * g}')
commit=$(git rev-parse --short HEAD)
[ -z "$(git status --porcelain -- bench 2>/dev/null)" ] || commit="$commit + uncommitted bench/ changes"
if [ "$plot_only" = 1 ]; then draw_plot "$plot"; exit 0; fi

# Install what is missing (idempotent), then build dba and the Ceres baseline.
bash scripts/install-deps.sh
missing=()
for p in libceres-dev gnuplot-nox jq time; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "compare.sh: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
echo "compare.sh: building"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target dba ceres_bal >/dev/null
dba=./build/dba
ceres=./build/bench/ceres_bal

# The problems: real ones, then synthetic ones made here.
if [ ${#problems[@]} -eq 0 ]; then problems=(../shared/data/bal/*.bz2); fi
for s in $synthetic; do
  IFS=: read -r kind a b <<<"$s"
  case "$kind" in
    uav)
      f=${b:-300}
      name=uav-$a; [ "$f" = 300 ] || name=uav-$a-f$f
      echo "compare.sh: dba generate $name"
      $dba generate "$work/$name.dba" --images "$a" --features "$f" >/dev/null
      problems+=("$work/$name.dba") ;;
    copies)
      name=dubrovnik16x$a
      echo "compare.sh: $name (replicate-bal.sh)"
      scripts/replicate-bal.sh ../shared/data/bal/problem-16-22106-pre.txt.bz2 "$a" "$work/$name.txt"
      $dba convert "$work/$name.txt" "$work/$name.dba" >/dev/null
      rm -f "$work/$name.txt"
      problems+=("$work/$name.dba") ;;
    *) echo "compare.sh: unknown synthetic problem '$s'" >&2; exit 2 ;;
  esac
done

cpu=$(awk -F': ' '/model name/ {print $2; exit}' /proc/cpuinfo)
mem=$(awk '/MemTotal/ {printf "%.0f", $2 / 1048576}' /proc/meminfo)
rows=$work/rows.md
phases=$work/phases.md
notes=$work/notes.md
: >"$rows"; : >"$phases"; : >"$notes"

for problem in "${problems[@]}"; do
  name=$(problem_name "$problem")
  echo "compare.sh: $name ($repeats runs each)"
  for r in $(seq "$repeats"); do
    # Alternate, and alternate who goes first, so slow drifts of the machine
    # hit both solvers alike.
    if [ $((r % 2)) = 1 ]; then order="dba ceres"; else order="ceres dba"; fi
    for s in $order; do
      run "$s" "$problem" "$name.$s.$r"
      echo "  run $r $s: $(seconds_of "$work/$name.$s.$r.time") s, $(kib_of "$work/$name.$s.$r.time") KiB, others $(cat "$work/$name.$s.$r.bg") cores"
    done
  done
  # Target: within target_gap (0.1%) of the lowest final cost of any run.
  best=$(for f in "$work/$name".*.json; do jq .final_cost "$f"; done | sort -g | head -1)
  target=$(awk -v b="$best" -v g="$target_gap" 'BEGIN {printf "%.17g", b * (1 + g)}')
  for s in dba ceres; do
    : >"$work/$s.t"; : >"$work/$s.m"; : >"$work/$s.tt"; : >"$work/$s.bg"
    for r in $(seq "$repeats"); do
      tag=$name.$s.$r
      seconds_of "$work/$tag.time" >>"$work/$s.t"
      kib_of "$work/$tag.time" >>"$work/$s.m"
      cat "$work/$tag.bg" >>"$work/$s.bg"
      "${s}_curve" "$work/$tag.json" >"$work/$tag.curve"
      time_to "$work/$tag.curve" "$target" >>"$work/$s.tt"
    done
    # Keep the report of the median-time run.
    med=$(median <"$work/$s.t")
    r=$(awk -v m="$med" '{d = $1 - m; if (d < 0) d = -d; if (NR == 1 || d < bd) {bd = d; r = NR}} END {print r}' "$work/$s.t")
    cp "$work/$name.$s.$r.json" "$out/$name.$s.json"
    cp "$work/$name.$s.$r.curve" "$work/$name.$s.curve"
  done
  dj=$out/$name.dba.json; cj=$out/$name.ceres.json
  dc=$(jq .final_cost "$dj"); cc=$(jq .final_cost "$cj")
  dtt=$(tt_of dba); ctt=$(tt_of ceres)
  # Agreement to 0.1%; where not, a direct solve (Ceres SPARSE_SCHUR) says
  # which solver found the optimum, and the terminations say why.
  agree=$(awk -v a="$dc" -v b="$cc" 'BEGIN {d = (a - b) / (a < b ? a : b); if (d < 0) d = -d; print (d <= 1e-3) ? "yes" : sprintf("no (%.2f%%)", 100 * d)}')
  if [ "$agree" != yes ]; then
    echo "  costs differ: reference solve with Ceres SPARSE_SCHUR"
    $ceres "$problem" -t "$threads" --solver sparse_schur --max-iterations "$max_iterations" \
      --function-tolerance "$function_tolerance" --report "$work/$name.ref.json" >/dev/null 2>&1 || true
    ref=$(jq .final_cost "$work/$name.ref.json" 2>/dev/null || echo nan)
    high=dba; high_j=$dj; low=Ceres; [ "$(awk -v a="$dc" -v b="$cc" 'BEGIN {print (a > b)}')" = 1 ] || { high=Ceres; high_j=$cj; low=dba; }
    awk -v n="$name" -v h="$high" -v l="$low" -v ref="$ref" -v dc="$dc" -v cc="$cc" \
        -v term="$(jq -r .termination "$high_j")" -v it="$(jq .iterations "$high_j")" 'BEGIN {
      lo = (dc < cc) ? dc : cc; hi = (dc < cc) ? cc : dc
      printf "- %s: %s stops %.2f%% above %s (%s after %d iterations).", n, h, 100 * (hi - lo) / lo, l, term, it
      if (ref == "nan") { print " The direct solve failed."; exit }
      printf " Ceres SPARSE_SCHUR (a direct solve of each step) ends at %.6e, ", ref
      if ((ref - lo) / lo <= 1e-3 && (ref - lo) / lo >= -1e-3) printf "the cost %s reaches: %s stopped early.\n", l, h
      else if ((ref - hi) / hi <= 1e-3 && (ref - hi) / hi >= -1e-3) printf "the cost %s reaches.\n", h
      else printf "neither solver'"'"'s.\n"
    }' >>"$notes"
    agree="$agree, see note"
  fi
  awk -v n="$name" -v c="$(jq .num_cameras "$dj")" -v p="$(jq .num_points "$dj")" -v o="$(jq .num_observations "$dj")" \
      -v dc="$dc" -v cc="$cc" -v ag="$agree" \
      -v dt="$(median <"$work/dba.t")" -v ct="$(median <"$work/ceres.t")" -v dtt="$dtt" -v ctt="$ctt" \
      -v dm="$(median <"$work/dba.m")" -v cm="$(median <"$work/ceres.m")" \
      -v dbg="$(median <"$work/dba.bg")" -v cbg="$(median <"$work/ceres.bg")" 'BEGIN {
    ratio = (dtt != "none" && ctt != "none") ? sprintf("%.2fx", ctt / dtt) : "-"
    printf "| %s | %d | %d | %d | %.6e | %.6e | %s | %.2f | %.2f | %.2fx | %s | %s | %s | %.1f | %.1f | %.2fx | %.2f / %.2f |\n",
      n, c, p, o, dc, cc, ag, dt, ct, ct / dt,
      dtt == "none" ? "not reached" : sprintf("%.2f", dtt), ctt == "none" ? "not reached" : sprintf("%.2f", ctt), ratio,
      dm / 1024, cm / 1024, cm / dm, dbg, cbg }' >>"$rows"
  # Where the time goes (median runs).
  {
    jq -r '.seconds as $s | [$s.total, ($s.load + ($s.distribution // 0)), $s.setup, $s.rcs_formation, $s.pcg,
      $s.back_substitution, .iterations, .pcg_iterations] | @tsv' "$dj"
    jq -r '.seconds as $s | [$s.total, ($s.load + $s.build_problem + $s.preprocessor), $s.jacobian_evaluation,
      $s.linear_solver, $s.residual_evaluation, .iterations, .linear_solver_iterations] | @tsv' "$cj"
  } | awk -F'\t' -v n="$name" '
    NR == 1 { for (i = 1; i <= NF; ++i) d[i] = $i }
    NR == 2 { for (i = 1; i <= NF; ++i) c[i] = $i }
    END {
      printf "| %s | %.2f | %.2f | %.2f | %.2f (%.0f%%) | %.2f (%.0f%%) | %.2f (%.0f%%) | %d | %d | %.2f | %.2f | %.2f (%.0f%%) | %.2f (%.0f%%) | %.2f | %d | %d |\n",
        n, d[1], d[2], d[3], d[4], 100 * d[4] / d[1], d[5], 100 * d[5] / d[1], d[6], 100 * d[6] / d[1], d[7], d[8],
        c[1], c[2], c[3], 100 * c[3] / c[1], c[4], 100 * c[4] / c[1], c[5], c[6], c[7] }' >>"$phases"
done

table=$out/compare.md
{
  echo "# dba vs Ceres"
  echo
  echo "$now, commit $commit; $(nproc) cores ($cpu), $mem GiB; $threads threads for each solver;"
  echo "median of $repeats run(s), dba and Ceres alternating; iteration limit $max_iterations, function tolerance $function_tolerance."
  echo "Ceres: ITERATIVE_SCHUR + SCHUR_JACOBI. Generated by \`bash bench/compare.sh\`."
  echo
  echo "| problem | cameras | points | observations | dba final cost | Ceres final cost | agree (0.1%) | dba time (s) | Ceres time (s) | Ceres/dba time | dba to best+$gap_label (s) | Ceres to best+$gap_label (s) | Ceres/dba to best+$gap_label | dba peak (MiB) | Ceres peak (MiB) | Ceres/dba memory | others' load dba / Ceres (cores) |"
  echo "|---|---:|---:|---:|---:|---:|:---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
  cat "$rows"
  echo
  if [ -s "$notes" ]; then
    echo "Where the final costs differ by more than 0.1%:"
    echo
    cat "$notes"
    echo
  fi
  echo "- *to best+$gap_label*: seconds from the program's start until the solver's cost"
  echo "  first comes within $gap_label of the lowest final cost either solver reached on"
  echo "  that problem (from the per-iteration histories; \"not reached\" if never)."
  cat <<'EOF'
- *time*: wall clock of the whole program (loading included) and *peak*:
  maximum resident set size, both from `/usr/bin/time -v`.
- *others' load*: cores used by other processes during the runs (whole
  machine CPU time from /proc/stat minus the solver's own, per wall second,
  over the run and the idle second before it; median over the runs). This
  machine is shared; rows with a load above about 0.3 are slowed down, dba
  more than Ceres (see bench/README.md).

## Where the time goes (median runs, seconds)

| problem | dba total | load | setup | RCS formation | PCG | back-substitution | LM iterations | PCG iterations | Ceres total | load + build + preprocess | Jacobians | linear solver | residuals | LM iterations | CG iterations |
|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|
EOF
  cat "$phases"
} >"$table"

if [ -z "$plot" ]; then plot=$(problem_name "${problems[${#problems[@]} - 1]}"); fi
draw_plot "$plot"
cat "$table"
