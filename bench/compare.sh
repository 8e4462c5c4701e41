#!/usr/bin/env bash
# dba against Ceres, side by side on the same machine in the same run
# (the yardstick of "fast by default at every scale"). For every
# BAL problem given (default: ../shared/data/bal/*.bz2) and synthetic
# problems made on the fly, runs under /usr/bin/time -v, alternately and
# several times each:
#   - dba with its default options: dba solve FILE -t N -q --report R.json
#   - Ceres 2.2.0 (../shared/peers/ceres-2.2.0/build.sh, once per machine,
#     into $HOME/.cache/ceres-2.2.0) and Debian's Ceres 2.1 (libceres-dev),
#     each with DENSE_SCHUR (only under 200 cameras), SPARSE_SCHUR and
#     ITERATIVE_SCHUR + SCHUR_JACOBI (bench/ceres_bal.cc, built once against
#     each version in build-bench-ceres22/ and build-bench-ceres21/),
# and writes to bench/results/ (or --out DIR):
#   compare.md          the tables: dba against the fastest Ceres 2.2
#                       configuration (among those ending within 0.1% of the
#                       best cost) and the fastest Ceres 2.1 one: final
#                       costs and whether they agree to 0.1% (and why not),
#                       wall time (median, min-max), time to reach the best
#                       final cost, peak memory (median, min-max), ratios,
#                       the background load during the runs; every
#                       configuration's figures; where the time goes
#   cost_vs_time.png    cost against time of dba and the fastest Ceres
#                       configurations on one problem
#   <problem>.dba.json, <problem>.ceres<V>-<solver>.json   the reports of
#                       each configuration's median run; <problem>.ceres.json
#                       and <problem>.ceres21.json: the fastest 2.2 and 2.1
# The default mode takes an estimated 2-3 hours on 2 cores: not part of CI.
#
#   bash bench/compare.sh [options] [PROBLEM...]
#     --repeats N        runs per configuration and problem (default 3)
#     --quick            one run each: the real problems and uav:1000
#     --threads N        threads for every solver (default: all cores)
#     --synthetic LIST   synthetic problems, space separated (default
#                        "copies:16 uav:250 uav:1000 uav:4000 uavtxt:2500
#                        uavtxt:10000 uavtxt-sparse:10000"):
#                          uav:N[:F]  dba generate, N images, F features
#                                     per image (default 300), .dba
#                          uavtxt:N[:F]  dba generate, N images (F features,
#                                     default dba generate's), BAL text
#                                     (.txt), 80% forward / 60% side overlap
#                          uavtxt-sparse:N[:F]  the same with 60% forward /
#                                     30% side overlap
#                          copies:K   K disjoint copies of Dubrovnik-16
#                                     (scripts/replicate-bal.sh; optimum
#                                     K x the original's)
#                        "" for none
#     --ceres LIST       Ceres versions, "2.2 2.1" (default) or "2.2"
#     --ceres-solvers LIST  Ceres configurations (default "dense_schur
#                        sparse_schur iterative_schur"; dense_schur only
#                        under 200 cameras)
#     --plot NAME        problem of the cost-versus-time plot (default: the
#                        last one)
#     --plot-only NAME   only redraw the plot from DIR/NAME.{dba,ceres}.json
#     --max-wait S       before each run, wait up to S seconds (default 60)
#                        for other processes to use less than 0.3 cores
#     --out DIR          output directory (default bench/results)
#     --target-gap X     "to best" columns, and which Ceres configurations
#                        may be the fastest: within X of the lowest final
#                        cost (default 1e-3, the 0.1% of agreement)
#     --max-iterations N, --function-tolerance X   for dba and Ceres (default:
#                        dba's own defaults; Ceres 100 and 1e-6)
#     --loss NAME, --loss-scale A   a robust loss for dba (--loss) and Ceres
#                        (its own loss of that name; default: none); costs
#                        are then the robust ½ Σ ρ
#     --shuffle SEED     every problem renumbered (points and cameras) by a
#                        random permutation seeded by SEED, its observations
#                        sorted camera by camera, and written as a new BAL
#                        text input (bench/shuffle_bal.py; a .dba is first
#                        converted to BAL text): an order dba did not choose.
#                        Named <problem>-shuffled<SEED>
#     --busy N           N busy processes (shell loops at normal priority)
#                        run beside every solver, dba and Ceres alike, from
#                        the first run to the last; the wait for an idle
#                        machine and the "others' load" column do not count
#                        them
#     --timeout S        stop any run after S seconds (default 1800); the
#                        configuration is left out of that problem
#     --prune X          stop a Ceres run once it takes X times (default 3;
#                        0: never) as long as the fastest run so far of a
#                        configuration of the same Ceres version that ended
#                        within --target-gap of the best cost so far (never
#                        before 60 s): it cannot be the fastest; left out of
#                        that problem, like a run stopped by --timeout
# PROBLEM: BAL text (plain or .bz2) or .dba files; given, they replace the
# default real problems (the synthetic ones are still added unless
# --synthetic "").
set -euo pipefail
cd "$(dirname "$0")/.."
repeats=3
quick=0
threads=$(nproc)
synthetic="copies:16 uav:250 uav:1000 uav:4000 uavtxt:2500 uavtxt:10000 uavtxt-sparse:10000"
synthetic_set=0
ceres_versions="2.2 2.1"
ceres_solvers="dense_schur sparse_schur iterative_schur"
dense_max_cameras=200  # DENSE_SCHUR only for fewer cameras than this
plot=""
plot_only=0
max_wait=60
out=bench/results
max_iterations=""
target_gap=1e-3
function_tolerance=""
loss="" loss_scale=1
timeout=1800
prune=3
shuffle=""
busy=0
prune_floor=60  # no run is stopped by --prune before this many seconds
problems=()
while [ $# -gt 0 ]; do
  case "$1" in
    --repeats) repeats=$2; shift 2 ;;
    --quick) quick=1; shift ;;
    --threads) threads=$2; shift 2 ;;
    --synthetic) synthetic=$2; synthetic_set=1; shift 2 ;;
    --ceres) ceres_versions=$2; shift 2 ;;
    --ceres-solvers) ceres_solvers=$2; shift 2 ;;
    --plot) plot=$2; shift 2 ;;
    --plot-only) plot=$2; plot_only=1; shift 2 ;;
    --max-wait) max_wait=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --target-gap) target_gap=$2; shift 2 ;;
    --max-iterations) max_iterations=$2; shift 2 ;;
    --function-tolerance) function_tolerance=$2; shift 2 ;;
    --loss) loss=$2; shift 2 ;;
    --loss-scale) loss_scale=$2; shift 2 ;;
    --timeout) timeout=$2; shift 2 ;;
    --prune) prune=$2; shift 2 ;;
    --shuffle) shuffle=$2; shift 2 ;;
    --busy) busy=$2; shift 2 ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d'; exit 0 ;;
    -*) echo "compare.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
    *) problems+=("$1"); shift ;;
  esac
done
if [ "$quick" = 1 ]; then
  repeats=1
  [ "$synthetic_set" = 1 ] || synthetic="uav:1000"
fi
[[ "$busy" =~ ^[0-9]+$ ]] || { echo "compare.sh: --busy takes a count of processes, not '$busy'" >&2; exit 2; }
[ -z "$shuffle" ] || [[ "$shuffle" =~ ^[0-9]+$ ]] || { echo "compare.sh: --shuffle takes an integer seed, not '$shuffle'" >&2; exit 2; }
case " $ceres_versions " in *" 2.2 "*) ;; *) echo "compare.sh: --ceres must include 2.2 (the yardstick)" >&2; exit 2 ;; esac
for v in $ceres_versions; do
  case "$v" in 2.2|2.1) ;; *) echo "compare.sh: unknown Ceres version '$v' (2.2 or 2.1)" >&2; exit 2 ;; esac
done
for s in $ceres_solvers; do
  case "$s" in dense_schur|sparse_schur|iterative_schur) ;;
    *) echo "compare.sh: unknown Ceres configuration '$s'" >&2; exit 2 ;; esac
done
# Options both solvers get; by default none for dba (its defaults), and
# ceres_bal's own defaults (100 iterations, function tolerance 1e-6).
dba_args=(); ceres_args=()
if [ -n "$max_iterations" ]; then dba_args+=(--max-iterations "$max_iterations"); ceres_args+=(--max-iterations "$max_iterations"); fi
if [ -n "$function_tolerance" ]; then dba_args+=(--function-tolerance "$function_tolerance"); ceres_args+=(--function-tolerance "$function_tolerance"); fi
if [ -n "$loss" ]; then dba_args+=(--loss "$loss" --loss-scale "$loss_scale"); ceres_args+=(--loss "$loss" --loss-scale "$loss_scale"); fi

work=$(mktemp -d /tmp/dba-compare.XXXXXX)
busy_pids=()
stop_busy() { [ ${#busy_pids[@]} -eq 0 ] || kill "${busy_pids[@]}" 2>/dev/null || true; }
trap 'stop_busy; rm -rf "$work"' EXIT
mkdir -p "$out"

problem_name() { local n; n=$(basename "$1"); n=${n%.bz2}; n=${n%.txt}; n=${n%.dba}; echo "$n"; }
median() { sort -g | awk '{a[NR] = $1} END {if (NR == 0) print "nan"; else print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }
# "median min max" of the numbers in a file.
spread() { printf '%s %s %s\n' "$(median <"$1")" "$(sort -g "$1" | head -1)" "$(sort -g "$1" | tail -1)"; }
# "median (min–max)" with FORMAT for each; the median alone for one run.
show_spread() {  # FORMAT "median min max"
  awk -v f="$1" -v s="$2" 'BEGIN {split(s, x, " ");
    if (sprintf(f, x[2]) == sprintf(f, x[3])) printf f, x[1]; else printf f " (" f "–" f ")", x[1], x[2], x[3]}'
}
# Wall seconds of a run: to the microsecond around it (TAG.wall, beside
# TAG.time), else /usr/bin/time's, to the hundredth (too coarse for the
# small problems' tens of milliseconds).
seconds_of() {
  if [ -f "${1%.time}.wall" ]; then cat "${1%.time}.wall"; return; fi
  awk -F': ' '/Elapsed \(wall clock\)/ {n = split($2, t, ":"); s = 0; for (i = 1; i <= n; ++i) s = s * 60 + t[i]; print s}' "$1"
}
kib_of() { awk -F': ' '/Maximum resident set size/ {print $2}' "$1"; }
cpu_of() { awk -F': ' '/User time|System time/ {s += $2} END {print s}' "$1"; }
# Configuration ids: dba, ceres2.2-sparse_schur, ...
version_of() { local v=${1#ceres}; echo "${v%%-*}"; }
solver_of() { echo "${1#*-}"; }
display_of() {
  case "$1" in
    dba) echo "dba (defaults)" ;;
    *dense_schur) echo "$(version_of "$1") DENSE_SCHUR" ;;
    *sparse_schur) echo "$(version_of "$1") SPARSE_SCHUR" ;;
    *iterative_schur) echo "$(version_of "$1") ITERATIVE_SCHUR + SCHUR_JACOBI" ;;
  esac
}
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
    awk -v x="$bg_cores" -v n="$busy" 'BEGIN {exit !(x - n < 0.3)}' && return 0
    [ "$waited" -ge "$max_wait" ] && { echo "  (machine busy: $bg_cores cores in use by others; running anyway)"; return 0; }
    sleep 4; waited=$((waited + 5))
  done
}

# The lowest final cost of the runs on problem $name that finished so far.
best_cost() {
  local f
  for f in "$work/$name".*.rc; do
    if [ -f "$f" ] && [ "$(cat "$f")" = 0 ]; then jq .final_cost "${f%.rc}.json"; fi
  done | sort -g | head -1
}
# Time limit (s) of the next run of CONFIG on problem $name: --timeout, and
# for Ceres --prune times the fastest run of the same Ceres version that
# ended within target_gap of the best cost so far (at least prune_floor).
limit_for() {
  local c=$1 v f b lim=$timeout
  if [ "$c" != dba ] && [ "$prune" != 0 ]; then
    v=$(version_of "$c"); b=$(best_cost)
    for f in "$work/$name.ceres$v-"*.rc; do
      [ -f "$f" ] && [ -n "$b" ] && [ "$(cat "$f")" = 0 ] || continue
      if awk -v x="$(jq .final_cost "${f%.rc}.json")" -v b="$b" -v g="$target_gap" 'BEGIN {exit !(x <= b * (1 + g))}'; then
        lim=$(awk -v l="$lim" -v t="$(seconds_of "${f%.rc}.time")" -v p="$prune" -v m="$prune_floor" \
          'BEGIN {x = p * t; if (x < m) x = m; x = int(x + 1); print (x < l) ? x : l}')
      fi
    done
  fi
  echo "$lim"
}

# run CONFIG PROBLEM TAG LIMIT: one timed run, stopped after LIMIT seconds;
# leaves $work/TAG.{json,time,bg,rc,limit} (rc: the exit status, 124 or 137
# when stopped; only a run with rc 0 has a usable report).
run() {
  local cfg=$1 problem=$2 tag=$3 limit=$4 rc=0
  echo "$limit" >"$work/$tag.limit"
  wait_quiet
  local t0=$EPOCHREALTIME
  if [ "$cfg" = dba ]; then
    /usr/bin/time -v timeout -k 10 "$limit" "$dba" solve "$problem" -t "$threads" -q ${dba_args[@]+"${dba_args[@]}"} \
      --report "$work/$tag.json" >"$work/$tag.out" 2>"$work/$tag.time" || rc=$?
  else
    /usr/bin/time -v timeout -k 10 "$limit" "${ceres_bin[$(version_of "$cfg")]}" "$problem" -t "$threads" --solver "$(solver_of "$cfg")" \
      ${ceres_args[@]+"${ceres_args[@]}"} --report "$work/$tag.json" >"$work/$tag.out" 2>"$work/$tag.time" || rc=$?
  fi
  echo "$rc" >"$work/$tag.rc"
  awk -v a="$t0" -v b="$EPOCHREALTIME" 'BEGIN {printf "%.4f\n", b - a}' >"$work/$tag.wall"
  # Background load: CPU time of the whole machine from the start of the
  # last quiet check (one idle second) to the end of the run, minus the
  # solver's own, per second of that window.
  awk -v a="$sample_jiffies" -v b="$(busy_jiffies)" -v hz="$hz" -v own="$(cpu_of "$work/$tag.time")" \
      -v t0="$sample_time" -v t1="$(date +%s.%N)" -v n="$busy" \
    'BEGIN {x = ((b - a) / hz - own) / (t1 - t0) - n; printf "%.2f\n", x < 0 ? 0 : x}' >"$work/$tag.bg"
}

# Time (s since the program started, loading included) at which a report's
# cost first reaches TARGET; "none" if never. dba's history gives the cost at
# the start of each iteration and the candidate's; Ceres's the cost at the end.
dba_curve() {
  jq -r '((.seconds.startup // 0) + (.seconds.read // 0) + (.seconds.load // 0) + (.seconds.distribution // 0)
      + (.seconds.setup // 0)) as $s0
    | ([$s0, .initial_cost], (foreach (.history // [])[] as $h ($s0; . + $h.seconds;
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
curve_of() { if [ "$1" = dba ]; then dba_curve "$2"; else ceres_curve "$2"; fi; }
# Median time to the target over the runs, "none" if a run never reached it.
tt_of() { if grep -q none "$work/$1.tt"; then echo none; else median <"$work/$1.tt"; fi; }
time_to() {  # CURVE_FILE TARGET
  awk -v t="$2" '$2 <= t {print $1; found = 1; exit} END {if (!found) print "none"}' "$1"
}
ceres_label() {  # REPORT
  jq -r '"Ceres \(.ceres_version // "2.1.0") " + (.solver | sub("^ceres "; "") | ascii_upcase
    | if . == "ITERATIVE_SCHUR" then . + " + SCHUR_JACOBI" else . end)' "$1"
}

# Cost against time on one problem, dba and the fastest Ceres configurations
# (their median runs), from the reports in $out: cost, and the gap to the
# best cost any of them reached.
draw_plot() {
  local name=$1 best s files=() labels=() points=(7 5 9) p1="" p2="" i
  [ -f "$out/$name.dba.json" ] && [ -f "$out/$name.ceres.json" ] || { echo "compare.sh: no reports of $name in $out" >&2; return 1; }
  files=("$out/$name.dba.json" "$out/$name.ceres.json"); labels=("dba (defaults)" "$(ceres_label "$out/$name.ceres.json")")
  if [ -f "$out/$name.ceres21.json" ]; then files+=("$out/$name.ceres21.json"); labels+=("$(ceres_label "$out/$name.ceres21.json")"); fi
  dba_curve "${files[0]}" >"$work/plot0.curve"
  for i in $(seq 1 $((${#files[@]} - 1))); do ceres_curve "${files[$i]}" >"$work/plot$i.curve"; done
  best=$(cat "$work"/plot*.curve | awk 'NR == 1 || $2 < b {b = $2} END {printf "%.17g", b}')
  for i in $(seq 0 $((${#files[@]} - 1))); do
    awk -v b="$best" '{g = ($2 - b) / b; print $1, $2, (g > 1e-9 ? g : 1e-9)}' "$work/plot$i.curve" >"$work/plot$i.dat"
    p1+="${p1:+, }\"$work/plot$i.dat\" using 1:2 with linespoints pt ${points[$i]} ps 0.6 title \"${labels[$i]}\""
    p2+="${p2:+, }\"$work/plot$i.dat\" using 1:3 with linespoints pt ${points[$i]} ps 0.6 title \"${labels[$i]}\""
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
plot $p1
set ylabel "(cost - best) / best"
set format y "%.0e"
plot $p2, $target_gap with lines dt 2 lc "gray" title "$gap_label"
unset multiplot
GP
  echo "compare.sh: plot of $name in $out/cost_vs_time.png"
}

now=$(date -u +%Y-%m-%d)
gap_label=$(awk -v g="$target_gap" 'BEGIN {printf "%g%%", 100 * g}')
commit=$(git rev-parse --short HEAD)
[ -z "$(git status --porcelain -- bench 2>/dev/null)" ] || commit="$commit + uncommitted bench/ changes"
if [ "$plot_only" = 1 ]; then draw_plot "$plot"; exit 0; fi

# Install what is missing (idempotent), Ceres 2.2.0 (once per machine), then
# build dba and the Ceres baseline against each Ceres version.
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
ceres22_prefix=$HOME/.cache/ceres-2.2.0
if [ ! -f "$ceres22_prefix/lib/cmake/Ceres/CeresConfig.cmake" ]; then
  echo "compare.sh: building Ceres 2.2.0 into $ceres22_prefix (once per machine, about 10-20 minutes)"
fi
bash ../shared/peers/ceres-2.2.0/build.sh "$ceres22_prefix" >/dev/null
echo "compare.sh: building"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DDBA_CERES_BASELINE=OFF >/dev/null
cmake --build build -j"$(nproc)" --target dba >/dev/null
dba=./build/dba
declare -A ceres_bin
build_ceres_bal() {  # VERSION BUILD_DIR CERES_DIR
  local v=$1 dir=$2 got
  cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=Release -DDBA_BUILD_TESTS=OFF -DDBA_CERES_BASELINE=ON \
    -DCeres_DIR="$3" >"$work/cmake-$v.log" 2>&1 || { tail -20 "$work/cmake-$v.log" >&2; exit 1; }
  cmake --build "$dir" -j"$(nproc)" --target ceres_bal >"$work/build-$v.log" 2>&1 || { tail -20 "$work/build-$v.log" >&2; exit 1; }
  got=$("$dir/bench/ceres_bal" --version)
  case "$got" in "$v".*) ;; *) echo "compare.sh: $dir/bench/ceres_bal is built against Ceres $got, not $v" >&2; exit 1 ;; esac
  ceres_bin[$v]=$dir/bench/ceres_bal
}
for v in $ceres_versions; do
  case "$v" in
    2.2) build_ceres_bal 2.2 build-bench-ceres22 "$ceres22_prefix/lib/cmake/Ceres" ;;
    2.1) build_ceres_bal 2.1 build-bench-ceres21 "$(dirname "$(dpkg -L libceres-dev | grep '/CeresConfig.cmake$' | head -1)")" ;;
  esac
done
ceres_full_versions=$(for v in $ceres_versions; do "${ceres_bin[$v]}" --version; done | paste -sd/)

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
    uavtxt|uavtxt-sparse)
      name=$kind-$a; gen=(--images "$a")
      if [ -n "$b" ]; then name=$name-f$b; gen+=(--features "$b"); fi
      if [ "$kind" = uavtxt-sparse ]; then gen+=(--forward-overlap 0.6 --side-overlap 0.3); fi
      echo "compare.sh: dba generate $name.txt ${gen[*]}"
      $dba generate "$work/$name.txt" "${gen[@]}" >/dev/null
      problems+=("$work/$name.txt") ;;
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

# --shuffle: each problem renumbered, as a new BAL text input.
if [ -n "$shuffle" ]; then
  shuffled=()
  for p in "${problems[@]}"; do
    name=$(problem_name "$p")-shuffled$shuffle
    src=$p
    if [[ "$p" == *.dba ]]; then
      $dba convert "$p" "$work/$name.in.txt" >/dev/null
      src=$work/$name.in.txt
    fi
    echo "compare.sh: $name (bench/shuffle_bal.py, seed $shuffle)"
    /usr/bin/python3 bench/shuffle_bal.py "$src" "$work/$name.txt" "$shuffle"
    rm -f "$work/$name.in.txt"
    shuffled+=("$work/$name.txt")
  done
  problems=("${shuffled[@]}")
fi
# --busy: the busy processes, from here to the end.
for ((i = 0; i < busy; ++i)); do
  bash -c 'while :; do :; done' &
  busy_pids+=($!)
done
[ "$busy" = 0 ] || echo "compare.sh: $busy busy processes beside every run (pids ${busy_pids[*]})"

cpu=$(awk -F': ' '/model name/ {print $2; exit}' /proc/cpuinfo)
mem=$(awk '/MemTotal/ {printf "%.0f", $2 / 1048576}' /proc/meminfo)
rows=$work/rows.md
configs=$work/configs.md
phases=$work/phases.md
notes=$work/notes.md
: >"$rows"; : >"$configs"; : >"$phases"; : >"$notes"

# pick VERSION: the fastest (median wall time) Ceres configuration of that
# version on the current problem among those whose final cost is within
# target_gap of the best; if none is, the fastest of all (pick_within=no).
# "" if every configuration of the version failed.
pick() {
  local v=$1 c t within
  pick_cfg=""; pick_within=no
  local fast_any="" t_any="" fast_in="" t_in=""
  for c in "${ok[@]}"; do
    [ "$c" != dba ] && [ "$(version_of "$c")" = "$v" ] || continue
    t=$(median <"$work/$c.t")
    within=$(awk -v x="$(jq .final_cost "$out/$name.$c.json")" -v t="$target" 'BEGIN {print (x <= t) ? 1 : 0}')
    if [ -z "$fast_any" ] || awk -v a="$t" -v b="$t_any" 'BEGIN {exit !(a < b)}'; then fast_any=$c; t_any=$t; fi
    if [ "$within" = 1 ] && { [ -z "$fast_in" ] || awk -v a="$t" -v b="$t_in" 'BEGIN {exit !(a < b)}'; }; then fast_in=$c; t_in=$t; fi
  done
  if [ -n "$fast_in" ]; then pick_cfg=$fast_in; pick_within=yes; else pick_cfg=$fast_any; fi
}

for problem in "${problems[@]}"; do
  name=$(problem_name "$problem")
  nc=$($dba info "$problem" | awk '$1 == "cameras" {print $2; exit}')
  cfgs=(dba)
  for v in $ceres_versions; do
    for s in $ceres_solvers; do
      [ "$s" = dense_schur ] && [ "$nc" -ge "$dense_max_cameras" ] && continue
      cfgs+=("ceres$v-$s")
    done
  done
  echo "compare.sh: $name, $nc cameras (${#cfgs[@]} configurations, $repeats runs each)"
  for r in $(seq "$repeats"); do
    # Alternate, and reverse the order every other repeat, so slow drifts of
    # the machine hit every configuration alike.
    if [ $((r % 2)) = 1 ]; then order=("${cfgs[@]}"); else order=(); for c in "${cfgs[@]}"; do order=("$c" ${order[@]+"${order[@]}"}); done; fi
    for c in "${order[@]}"; do
      # A configuration that failed or was stopped is not run again.
      [ -z "$(cat "$work/$name.$c".*.rc 2>/dev/null | grep -v '^0$')" ] || continue
      limit=$(limit_for "$c")
      run "$c" "$problem" "$name.$c.$r" "$limit"
      rc=$(cat "$work/$name.$c.$r.rc")
      if [ "$rc" = 0 ]; then
        echo "  run $r $c: $(seconds_of "$work/$name.$c.$r.time") s, $(kib_of "$work/$name.$c.$r.time") KiB, others $(cat "$work/$name.$c.$r.bg") cores"
      elif [ "$rc" = 124 ] || [ "$rc" = 137 ]; then
        echo "  run $r $c: stopped after $limit s"
      else
        echo "  run $r $c: FAILED (exit $rc); $(grep -v '^\s' "$work/$name.$c.$r.time" | tail -1)"
      fi
    done
  done
  # The configurations every run of which succeeded; the others get a note.
  ok=(); not_ok=$work/not_ok.md; : >"$not_ok"
  for c in "${cfgs[@]}"; do
    bad=$(cat "$work/$name.$c".*.rc | grep -v '^0$' | head -1 || true)
    if [ -z "$bad" ]; then ok+=("$c"); continue; fi
    tag=$(grep -lx "$bad" "$work/$name.$c".*.rc | head -1); tag=$(basename "$tag" .rc)
    if [ "$bad" = 124 ] || [ "$bad" = 137 ]; then
      limit=$(cat "$work/$tag.limit")
      if awk -v l="$limit" -v t="$timeout" 'BEGIN {exit !(l < t)}'; then
        echo "- $name: $(display_of "$c") stopped after $limit s, $prune times the time of a faster Ceres $(version_of "$c") configuration that reached the best cost; left out." >>"$notes"
      else
        echo "- $name: $(display_of "$c") stopped at the time limit ($limit s, \`--timeout\`); left out." >>"$notes"
      fi
      echo "| $name | $(display_of "$c") | > $limit | | | | | | | stopped after $limit s | | |" >>"$not_ok"
    else
      echo "- $name: $(display_of "$c") failed (exit status $bad); left out." >>"$notes"
      echo "| $name | $(display_of "$c") | - | | | | | | | failed (exit status $bad) | | |" >>"$not_ok"
    fi
  done
  if [ "${ok[0]:-}" != dba ]; then echo "compare.sh: dba did not finish on $name; no row" >&2; continue; fi
  # Target: within target_gap (0.1%) of the lowest final cost of any run.
  best=$(best_cost)
  target=$(awk -v b="$best" -v g="$target_gap" 'BEGIN {printf "%.17g", b * (1 + g)}')
  for c in "${ok[@]}"; do
    : >"$work/$c.t"; : >"$work/$c.m"; : >"$work/$c.tt"; : >"$work/$c.bg"; : >"$work/$c.r"
    for r in $(seq "$repeats"); do
      tag=$name.$c.$r
      [ -f "$work/$tag.rc" ] || continue
      echo "$r" >>"$work/$c.r"
      seconds_of "$work/$tag.time" >>"$work/$c.t"
      kib_of "$work/$tag.time" >>"$work/$c.m"
      cat "$work/$tag.bg" >>"$work/$c.bg"
      curve_of "$c" "$work/$tag.json" >"$work/$tag.curve"
      time_to "$work/$tag.curve" "$target" >>"$work/$c.tt"
    done
    # Keep the report of the median-time run.
    med=$(median <"$work/$c.t")
    r=$(paste "$work/$c.t" "$work/$c.r" | awk -v m="$med" '{d = $1 - m; if (d < 0) d = -d; if (NR == 1 || d < bd) {bd = d; r = $2}} END {print r}')
    cp "$work/$name.$c.$r.json" "$out/$name.$c.json"
  done
  pick 2.2; c22=$pick_cfg; c22_within=$pick_within
  c21=""; c21_within=no
  case " $ceres_versions " in *" 2.1 "*) pick 2.1; c21=$pick_cfg; c21_within=$pick_within ;; esac
  if [ -z "$c22" ]; then
    echo "compare.sh: no Ceres 2.2 configuration finished on $name; no row" >&2
    echo "- $name: no Ceres 2.2 configuration finished; no row above." >>"$notes"
    continue
  fi
  cp "$out/$name.$c22.json" "$out/$name.ceres.json"
  if [ -n "$c21" ]; then cp "$out/$name.$c21.json" "$out/$name.ceres21.json"; else rm -f "$out/$name.ceres21.json"; fi
  for v in 2.2 2.1; do
    c=$c22; w=$c22_within; [ "$v" = 2.2 ] || { c=$c21; w=$c21_within; }
    if [ -n "$c" ] && [ "$w" = no ]; then
      echo "- $name: no Ceres $v configuration ends within $gap_label of the best cost ($(printf '%.6e' "$best")); the fastest of all, $(display_of "$c"), is shown." >>"$notes"
    fi
  done
  dj=$out/$name.dba.json; cj=$out/$name.$c22.json
  dc=$(jq .final_cost "$dj"); cc=$(jq .final_cost "$cj")
  dtt=$(tt_of dba); ctt=$(tt_of "$c22")
  # Agreement to 0.1%; where not, a direct solve (Ceres 2.2 SPARSE_SCHUR)
  # says which solver found the optimum, and the terminations say why.
  agree=$(awk -v a="$dc" -v b="$cc" 'BEGIN {d = (a - b) / (a < b ? a : b); if (d < 0) d = -d; print (d <= 1e-3) ? "yes" : sprintf("no (%.2f%%)", 100 * d)}')
  if [ "$agree" != yes ]; then
    if [ -f "$out/$name.ceres2.2-sparse_schur.json" ] && [[ " ${ok[*]} " == *" ceres2.2-sparse_schur "* ]]; then
      ref=$(jq .final_cost "$out/$name.ceres2.2-sparse_schur.json")
    else
      echo "  costs differ: reference solve with Ceres 2.2 SPARSE_SCHUR"
      "${ceres_bin[2.2]}" "$problem" -t "$threads" --solver sparse_schur ${ceres_args[@]+"${ceres_args[@]}"} \
        --report "$work/$name.ref.json" >/dev/null 2>&1 || true
      ref=$(jq .final_cost "$work/$name.ref.json" 2>/dev/null || echo nan)
    fi
    high=dba; high_j=$dj; low="Ceres $(display_of "$c22")"
    if [ "$(awk -v a="$dc" -v b="$cc" 'BEGIN {print (a > b)}')" != 1 ]; then high="Ceres $(display_of "$c22")"; high_j=$cj; low=dba; fi
    awk -v n="$name" -v h="$high" -v l="$low" -v ref="$ref" -v dc="$dc" -v cc="$cc" \
        -v term="$(jq -r .termination "$high_j")" -v it="$(jq .iterations "$high_j")" 'BEGIN {
      lo = (dc < cc) ? dc : cc; hi = (dc < cc) ? cc : dc
      printf "- %s: %s stops %.2f%% above %s (%s after %d iterations).", n, h, 100 * (hi - lo) / lo, l, term, it
      if (ref == "nan") { print " The direct solve failed."; exit }
      printf " Ceres 2.2 SPARSE_SCHUR (a direct solve of each step) ends at %.6e, ", ref
      if ((ref - lo) / lo <= 1e-3 && (ref - lo) / lo >= -1e-3) printf "the cost %s reaches: %s stopped early.\n", l, h
      else if ((ref - hi) / hi <= 1e-3 && (ref - hi) / hi >= -1e-3) printf "the cost %s reaches.\n", h
      else printf "neither solver'"'"'s.\n"
    }' >>"$notes"
    agree="$agree, see note"
  fi
  dt=$(median <"$work/dba.t"); ct=$(median <"$work/$c22.t")
  c21_time=-; c21_name=-; c21_ratio=-
  if [ -n "$c21" ]; then
    c21_time=$(show_spread %.3f "$(spread "$work/$c21.t")")
    c21_name=$(display_of "$c21" | sed 's/^2\.1 //'); [ "$c21_within" = yes ] || c21_name="$c21_name (see note)"
    c21_ratio=$(awk -v a="$(median <"$work/$c21.t")" -v b="$dt" 'BEGIN {printf "%.2fx", a / b}')
  fi
  c22_name=$(display_of "$c22" | sed 's/^2\.2 //'); [ "$c22_within" = yes ] || c22_name="$c22_name (see note)"
  awk -v n="$name" -v c="$(jq .num_cameras "$dj")" -v p="$(jq .num_points "$dj")" -v o="$(jq .num_observations "$dj")" \
      -v dc="$dc" -v cc="$cc" -v ag="$agree" -v dt="$dt" -v ct="$ct" -v dtt="$dtt" -v ctt="$ctt" \
      -v dts="$(show_spread %.3f "$(spread "$work/dba.t")")" -v cts="$(show_spread %.3f "$(spread "$work/$c22.t")")" \
      -v cfg="$c22_name" -v dm="$(median <"$work/dba.m")" -v cm="$(median <"$work/$c22.m")" \
      -v dms="$(show_spread %.1f "$(spread "$work/dba.m" | awk '{printf "%.1f %.1f %.1f", $1 / 1024, $2 / 1024, $3 / 1024}')")" \
      -v cms="$(show_spread %.1f "$(spread "$work/$c22.m" | awk '{printf "%.1f %.1f %.1f", $1 / 1024, $2 / 1024, $3 / 1024}')")" \
      -v t21="$c21_time" -v cfg21="$c21_name" -v r21="$c21_ratio" \
      -v dbg="$(median <"$work/dba.bg")" -v cbg="$(median <"$work/$c22.bg")" 'BEGIN {
    ratio = (dtt != "none" && ctt != "none") ? sprintf("%.2fx", ctt / dtt) : "-"
    printf "| %s | %d | %d | %d | %.6e | %.6e | %s | %s | %s | %s | %.2fx | %s | %s | %s | %s | %s | %.2fx | %s | %s | %s | %.2f / %.2f |\n",
      n, c, p, o, dc, cc, ag, dts, cts, cfg, ct / dt,
      dtt == "none" ? "not reached" : sprintf("%.2f", dtt), ctt == "none" ? "not reached" : sprintf("%.2f", ctt), ratio,
      dms, cms, cm / dm, t21, cfg21, r21, dbg, cbg }' >>"$rows"
  # Every configuration.
  for c in "${ok[@]}"; do
    j=$out/$name.$c.json
    mark=""; [ "$c" = "$c22" ] && mark="fastest 2.2"; [ "$c" = "$c21" ] && mark="fastest 2.1"
    lin=$(jq '.pcg_iterations // .linear_solver_iterations // 0' "$j")
    awk -v n="$name" -v s="$(display_of "$c")" -v ts="$(show_spread %.3f "$(spread "$work/$c.t")")" \
        -v t="$(median <"$work/$c.t")" -v dt="$dt" \
        -v ms="$(show_spread %.1f "$(spread "$work/$c.m" | awk '{printf "%.1f %.1f %.1f", $1 / 1024, $2 / 1024, $3 / 1024}')")" \
        -v cost="$(jq .final_cost "$j")" -v best="$best" -v it="$(jq .iterations "$j")" -v lin="$lin" \
        -v term="$(jq -r .termination "$j")" -v bg="$(median <"$work/$c.bg")" -v mark="$mark" 'BEGIN {
      printf "| %s | %s | %s | %.2fx | %s | %.6e | %.2g%% | %d | %d | %s | %.2f | %s |\n",
        n, s, ts, t / dt, ms, cost, 100 * (cost - best) / best, it, lin, term, bg, mark }' >>"$configs"
  done
  cat "$not_ok" >>"$configs"
  # Where the time goes (median runs).
  {
    jq -r '.seconds as $s | [$s.total, (($s.startup // 0) + ($s.read // 0) + ($s.load // 0) + ($s.distribution // 0)), ($s.setup // 0), ($s.rcs_formation // 0),
      ($s.linear_solve // $s.pcg // 0), ($s.back_substitution // 0), .iterations, (.pcg_iterations // 0)] | @tsv' "$dj"
    jq -r '.seconds as $s | [$s.total, ($s.load + $s.build_problem + $s.preprocessor), $s.jacobian_evaluation,
      $s.linear_solver, $s.residual_evaluation, .iterations, .linear_solver_iterations] | @tsv' "$cj"
  } | awk -F'\t' -v n="$name" -v cfg="$c22_name" '
    NR == 1 { for (i = 1; i <= NF; ++i) d[i] = $i }
    NR == 2 { for (i = 1; i <= NF; ++i) c[i] = $i }
    END {
      printf "| %s | %.2f | %.2f | %.2f | %.2f (%.0f%%) | %.2f (%.0f%%) | %.2f (%.0f%%) | %d | %d | %s | %.2f | %.2f | %.2f (%.0f%%) | %.2f (%.0f%%) | %.2f | %d | %d |\n",
        n, d[1], d[2], d[3], d[4], 100 * d[4] / d[1], d[5], 100 * d[5] / d[1], d[6], 100 * d[6] / d[1], d[7], d[8],
        cfg, c[1], c[2], c[3], 100 * c[3] / c[1], c[4], 100 * c[4] / c[1], c[5], c[6], c[7] }' >>"$phases"
done

table=$out/compare.md
spread_note="median of $repeats run(s)"; [ "$repeats" = 1 ] || spread_note="median (min–max) of $repeats runs"
dba_options="its default options"; [ ${#dba_args[@]} -eq 0 ] || dba_options="its defaults but ${dba_args[*]}"
ceres_options="iteration limit 100, function tolerance 1e-6"; [ ${#ceres_args[@]} -eq 0 ] || ceres_options="${ceres_args[*]}"
{
  echo "# dba vs Ceres"
  echo
  echo "$now, commit $commit; $(nproc) cores ($cpu), $mem GiB; $threads threads for each solver;"
  echo "$spread_note, every configuration in turn. dba: $dba_options (\`dba solve FILE -t $threads -q\`)."
  echo "Ceres $ceres_full_versions ($ceres_options): configurations $(for s in $ceres_solvers; do display_of "x-$s" | sed 's/^x //'; done | paste -sd, | sed 's/,/, /g')"
  echo "(DENSE_SCHUR under $dense_max_cameras cameras only); per problem and version the fastest whose final cost is within $gap_label of the"
  echo "best cost of all runs is compared. Runs were stopped after $timeout s (\`--timeout\`), Ceres runs also after"
  [ "$prune" = 0 ] && echo "no other limit." || echo "$prune times the fastest run of the same version that reached the best cost, if over $prune_floor s (\`--prune\`); see the notes."
  [ -z "$shuffle" ] || echo "Inputs shuffled (\`--shuffle $shuffle\`): points and cameras renumbered at random, observations sorted by camera."
  [ "$busy" = 0 ] || echo "With $busy busy processes at normal priority beside every run (\`--busy $busy\`; not counted in others' load)."
  echo "Generated by \`bash bench/compare.sh\`."
  echo
  echo "| problem | cameras | points | observations | dba final cost | Ceres 2.2 final cost | agree (0.1%) | dba time (s) | Ceres 2.2 time (s) | fastest Ceres 2.2 | Ceres 2.2/dba time | dba to best+$gap_label (s) | Ceres 2.2 to best+$gap_label (s) | Ceres 2.2/dba to best+$gap_label | dba peak (MiB) | Ceres 2.2 peak (MiB) | Ceres 2.2/dba memory | Ceres 2.1 time (s) | fastest Ceres 2.1 | Ceres 2.1/dba time | others' load dba / Ceres 2.2 (cores) |"
  echo "|---|---:|---:|---:|---:|---:|:---|---:|---:|:---|---:|---:|---:|---:|---:|---:|---:|---:|:---|---:|---:|"
  cat "$rows"
  echo
  if [ -s "$notes" ]; then
    echo "Notes:"
    echo
    cat "$notes"
    echo
  fi
  echo "- *to best+$gap_label*: seconds from the program's start until the solver's cost"
  echo "  first comes within $gap_label of the lowest final cost any configuration reached on"
  echo "  that problem (from the per-iteration histories; \"not reached\" if never)."
  cat <<'EOF'
- *time*: wall clock of the whole program (loading included; to the
  microsecond around `/usr/bin/time` and `timeout`, the same for every
  configuration) and *peak*:
  maximum resident set size (`/usr/bin/time -v`).
- *others' load*: cores used by other processes during the runs (whole
  machine CPU time from /proc/stat minus the solver's own, per wall second,
  over the run and the idle second before it; median over the runs). This
  machine is shared; rows with a load above about 0.3 are slowed down, dba
  more than Ceres (see bench/README.md).

## Every configuration

| problem | solver | time (s) | time / dba's | peak (MiB) | final cost | above the best | iterations | linear iterations (dba: PCG) | termination | others' load (cores) | chosen |
|---|---|---:|---:|---:|---:|---:|---:|---:|---|---:|---|
EOF
  cat "$configs"
  cat <<'EOF'

## Where the time goes (median runs, seconds; Ceres: the fastest 2.2 configuration)

| problem | dba total | load | setup | RCS formation | linear solve | back-substitution | LM iterations | PCG iterations | Ceres 2.2 | Ceres total | load + build + preprocess | Jacobians | linear solver | residuals | LM iterations | linear iterations |
|---|---:|---:|---:|---:|---:|---:|---:|---:|:---|---:|---:|---:|---:|---:|---:|---:|
EOF
  cat "$phases"
} >"$table"

if [ -z "$plot" ]; then plot=$(problem_name "${problems[${#problems[@]} - 1]}"); fi
draw_plot "$plot"
cat "$table"
