#!/usr/bin/env bash
# dba on a busy machine against the same machine idle (the target:
# at most 2.5x its idle time with --busy 2): for each problem, runs of dba with its
# default options alternate idle / with N busy processes (shell loops at
# normal priority, started before and stopped after each busy run), and the
# medians (min-max) and their ratio are printed as a Markdown table, with
# the busy/idle ratio of each phase's median (RCS formation, linear solve,
# back-substitution: the report's seconds) and of PCG's time per iteration.
# Problems are shuffled first (bench/shuffle_bal.py, seed 1): an order dba
# did not choose. Takes about 2 x repeats x (idle + busy time) per problem.
#
#   bash bench/busy.sh [--busy N] [--repeats R] PROBLEM|uavtxt:N ...
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
dba=$root/build/dba busy=2 repeats=3 problems=()
while [ $# -gt 0 ]; do
  case "$1" in
    --busy) busy=$2; shift 2 ;;
    --repeats) repeats=$2; shift 2 ;;
    -h|--help) sed -n '2,10p' "$0"; exit 0 ;;
    -*) echo "busy.sh: unknown option $1" >&2; exit 2 ;;
    *) problems+=("$1"); shift ;;
  esac
done
[ ${#problems[@]} -gt 0 ] || { echo "busy.sh: name a problem (a BAL file or uavtxt:N)" >&2; exit 2; }
work=$(mktemp -d)
pids=()
stop() { [ ${#pids[@]} -eq 0 ] || kill "${pids[@]}" 2>/dev/null || true; pids=(); }
trap 'stop; rm -rf "$work"' EXIT
median() { sort -g | awk '{v[NR] = $1} END {m = NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2; printf "%.2f (%.2f-%.2f)", m, v[1], v[NR]}'; }
# wall FILE KIND RUN: the wall time of one default solve; its report kept
# as $work/r<RUN>.<KIND>.json.
wall() { /usr/bin/time -f %e "$dba" solve "$1" -q --report "$work/r$3.$2.json" 2>&1 >/dev/null | tail -1; }
# phases: busy/idle of each phase's median over the reports of this problem.
phases() {
  /usr/bin/python3 - "$work" <<'PY'
import glob, json, statistics, sys
def med(kind, f):
    return statistics.median(f(json.load(open(p))) for p in glob.glob(f"{sys.argv[1]}/r*.{kind}.json"))
out = []
for name, f in [("formation", lambda d: d["seconds"]["rcs_formation"]),
                ("linear solve", lambda d: d["seconds"]["linear_solve"]),
                ("back-substitution", lambda d: d["seconds"]["back_substitution"]),
                ("PCG per iteration", lambda d: d["seconds"]["linear_solve"] / max(1, d.get("pcg_iterations", 0)))]:
    out.append(f"{name} {med('busy', f) / med('idle', f):.2f}x")
print(", ".join(out))
PY
}

echo "$(date -u '+%F %T') UTC, $(nproc) cores, $busy busy processes in the busy runs, $repeats runs each, alternating; load before: $(cut -d' ' -f1 /proc/loadavg)"
echo
echo "| problem (shuffled) | idle wall s | busy wall s | busy / idle | busy / idle by phase |"
echo "|---|---|---|---|---|"
for p in "${problems[@]}"; do
  if [[ "$p" == uavtxt:* ]]; then
    name=uavtxt-${p#uavtxt:}
    "$dba" generate "$work/$name.txt" --images "${p#uavtxt:}" >/dev/null
    p=$work/$name.txt
  fi
  name=$(basename "$p"); name=${name%%.*}
  /usr/bin/python3 "$root/bench/shuffle_bal.py" "$p" "$work/$name-shuffled1.txt" 1 >/dev/null
  idle=() loaded=()
  rm -f "$work"/r*.json
  for ((r = 0; r < repeats; r++)); do
    idle+=("$(wall "$work/$name-shuffled1.txt" idle "$r")")
    for ((b = 0; b < busy; b++)); do (while :; do :; done) & pids+=($!); done
    loaded+=("$(wall "$work/$name-shuffled1.txt" busy "$r")")
    stop
  done
  i=$(printf '%s\n' "${idle[@]}" | median); l=$(printf '%s\n' "${loaded[@]}" | median)
  ratio=$(awk -v a="${i%% *}" -v b="${l%% *}" 'BEGIN {printf "%.2f", b / a}')
  echo "| $name | $i | $l | $ratio | $(phases) |"
done
