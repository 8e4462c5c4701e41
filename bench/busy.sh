#!/usr/bin/env bash
# dba on a busy machine against the same machine idle (issue 44's "at most
# 2.5x its idle time with --busy 2"): for each problem, runs of dba with its
# default options alternate idle / with N busy processes (shell loops at
# normal priority, started before and stopped after each busy run), and the
# medians (min-max) and their ratio are printed as a Markdown table.
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
wall() { /usr/bin/time -f %e "$dba" solve "$1" -q 2>&1 >/dev/null | tail -1; }

echo "$(date -u '+%F %T') UTC, $(nproc) cores, $busy busy processes in the busy runs, $repeats runs each, alternating; load before: $(cut -d' ' -f1 /proc/loadavg)"
echo
echo "| problem (shuffled) | idle wall s | busy wall s | busy / idle |"
echo "|---|---|---|---|"
for p in "${problems[@]}"; do
  if [[ "$p" == uavtxt:* ]]; then
    name=uavtxt-${p#uavtxt:}
    "$dba" generate "$work/$name.txt" --images "${p#uavtxt:}" >/dev/null
    p=$work/$name.txt
  fi
  name=$(basename "$p"); name=${name%%.*}
  /usr/bin/python3 "$root/bench/shuffle_bal.py" "$p" "$work/$name-shuffled1.txt" 1 >/dev/null
  idle=() loaded=()
  for ((r = 0; r < repeats; r++)); do
    idle+=("$(wall "$work/$name-shuffled1.txt")")
    for ((b = 0; b < busy; b++)); do (while :; do :; done) & pids+=($!); done
    loaded+=("$(wall "$work/$name-shuffled1.txt")")
    stop
  done
  i=$(printf '%s\n' "${idle[@]}" | median); l=$(printf '%s\n' "${loaded[@]}" | median)
  ratio=$(awk -v a="${i%% *}" -v b="${l%% *}" 'BEGIN {printf "%.2f", b / a}')
  echo "| $name | $i | $l | $ratio |"
done
