#!/usr/bin/env bash
# A/B: one dba binary against another (an earlier commit's build against
# this one), side by side in one run: the same problems, rank counts and
# options, the two binaries alternating run by run, each run after the
# machine is idle. Reports per problem and rank count the median wall time
# and peak memory (min-max) of each binary and their ratios, and whether the
# final costs agree (1e-5: the default options). For "a change must not cost
# more than 5%".
#
#   bash bench/ab.sh --old OLD_DBA [--new NEW_DBA] [--repeats N] [--ranks "1 2"]
#                    [--threads T] [--out DIR] [PROBLEM...]
#     --old, --new   the binaries (default --new: build/dba)
#     --repeats N    runs per binary, problem and rank count (default 5)
#     --ranks LIST   rank counts (default "1 2"; >1 under mpirun)
#     --threads T    threads per rank (default: the cores / ranks)
#     --max-wait S   before each run, wait up to S s for the machine to be
#                    idle (under 0.3 cores busy; default 60)
#     --out DIR      where ab.md and the reports go (default bench/results/ab)
#     PROBLEM        BAL (.txt, .bz2), .dba or COLMAP directories; or
#                    uavtxt:N / uav:N (dba generate, made once into DIR)
# Nothing else may run while it does (it says what the load was).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
old="" new="$root/build/dba" repeats=5 ranks="1 2" threads="" max_wait=60 out="$root/bench/results/ab"
problems=()
while [ $# -gt 0 ]; do
  case "$1" in
    --old) old=$2; shift 2 ;;
    --new) new=$2; shift 2 ;;
    --repeats) repeats=$2; shift 2 ;;
    --ranks) ranks=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    --max-wait) max_wait=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    -h|--help) sed -n '2,21p' "$0"; exit 0 ;;
    -*) echo "ab.sh: unknown option $1" >&2; exit 2 ;;
    *) problems+=("$1"); shift ;;
  esac
done
[ -n "$old" ] || { echo "ab.sh: --old OLD_DBA is required" >&2; exit 2; }
for b in "$old" "$new"; do [ -x "$b" ] || { echo "ab.sh: $b is not an executable" >&2; exit 2; }; done
[ ${#problems[@]} -gt 0 ] || problems=("$root/data/problem-49-7776-pre.txt.bz2" uavtxt:2500)
mkdir -p "$out"
cores=$(nproc)

# The load of the other processes, in cores (from /proc/stat over 1 s,
# less this script's own).
busy() {
  python3 - <<'PY'
import time
def read():
    f = open("/proc/stat").readline().split()[1:]
    v = list(map(int, f))
    return sum(v), v[3] + v[4]
t0, i0 = read(); time.sleep(1); t1, i1 = read()
import os
print(f"{(1 - (i1 - i0) / max(t1 - t0, 1)) * os.cpu_count():.2f}")
PY
}
wait_idle() {
  local waited=0
  while [ "$waited" -lt "$max_wait" ]; do
    awk -v b="$(busy)" 'BEGIN { exit !(b < 0.3) }' && return
    waited=$((waited + 1))
  done
  echo "ab.sh: the machine stayed busy ($(busy) cores) for ${max_wait} s" >&2
}

input_of() {  # PROBLEM -> a file (generated ones made once)
  case "$1" in
    uavtxt:*) local f="$out/uavtxt-${1#uavtxt:}.txt"
      [ -s "$f" ] || "$new" generate "$f" --images "${1#uavtxt:}" >/dev/null; echo "$f" ;;
    uav:*) local f="$out/uav-${1#uav:}.dba"
      [ -s "$f" ] || "$new" generate "$f" --images "${1#uav:}" --model photo >/dev/null; echo "$f" ;;
    *) echo "$1" ;;
  esac
}

# run BINARY INPUT RANKS REPORT: wall seconds and peak KiB (the largest
# rank's) on one line.
run() {
  local bin=$1 input=$2 n=$3 report=$4 t=$threads
  [ -n "$t" ] || t=$(( cores / n > 0 ? cores / n : 1 ))
  local cmd=("$bin" solve "$input" -q -t "$t" --report "$report")
  [ "$n" -gt 1 ] && cmd=(mpirun --allow-run-as-root --oversubscribe --bind-to none -np "$n" "${cmd[@]}")
  wait_idle
  local start end
  start=$(date +%s.%N)
  "${cmd[@]}" >/dev/null 2>"$out/last.err" || { echo "ab.sh: $bin failed on $input (-np $n)" >&2; cat "$out/last.err" >&2; exit 1; }
  end=$(date +%s.%N)
  python3 - "$report" "$start" "$end" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
peak = d["memory"]["peak_bytes"]
for r in d.get("distributed", {}).get("ranks", []):
    peak = max(peak, r["peak_memory_bytes"])
print(f"{float(sys.argv[3]) - float(sys.argv[2]):.3f} {peak / 1024:.0f} {d['final_cost']!r}")
PY
}

{
  echo "# A/B: $(basename "$old") ($old) against $(basename "$new") ($new)"
  echo
  echo "$(date -u +%F' '%T) UTC, $cores cores, $repeats runs each, alternating; load before: $(busy) cores"
  echo
  echo "| problem | ranks | old wall s (median, min-max) | new wall s | new/old | old peak MiB | new peak MiB | new/old | costs agree (1e-5) |"
  echo "|---|---|---|---|---|---|---|---|---|"
} >"$out/ab.md"
for p in "${problems[@]}"; do
  input=$(input_of "$p")
  for n in $ranks; do
    : >"$out/old.txt"
    : >"$out/new.txt"
    for k in $(seq "$repeats"); do
      run "$old" "$input" "$n" "$out/old.json" >>"$out/old.txt"
      run "$new" "$input" "$n" "$out/new.json" >>"$out/new.txt"
    done
    python3 - "$out/old.txt" "$out/new.txt" "$(basename "$input")" "$n" >>"$out/ab.md" <<'PY'
import statistics, sys
def load(f):
    rows = [l.split() for l in open(f) if l.strip()]
    return [float(r[0]) for r in rows], [float(r[1]) / 1024 for r in rows], [float(r[2]) for r in rows]
ow, om, oc = load(sys.argv[1]); nw, nm, nc = load(sys.argv[2])
med = statistics.median
agree = all(abs(a - b) <= 1e-5 * abs(b) for a in oc for b in nc)
print(f"| {sys.argv[3]} | {sys.argv[4]} | {med(ow):.3f} ({min(ow):.3f}-{max(ow):.3f}) | "
      f"{med(nw):.3f} ({min(nw):.3f}-{max(nw):.3f}) | {med(nw) / med(ow):.3f} | "
      f"{med(om):.1f} ({min(om):.1f}-{max(om):.1f}) | {med(nm):.1f} ({min(nm):.1f}-{max(nm):.1f}) | "
      f"{med(nm) / med(om):.3f} | {'yes' if agree else 'no'} |")
PY
  done
done
echo >>"$out/ab.md"
echo "load after: $(busy) cores" >>"$out/ab.md"
cat "$out/ab.md"
