#!/usr/bin/env bash
# Reading a large .bz2 on every thread (docs/design.md §4.3): `dba info FILE`
# (decode, parse, the problem's statistics) against `bzcat FILE >/dev/null`
# (decode alone, one thread) on the same file, runs alternating, each pair
# starting with the other; wall times as medians (min-max), their ratio, dba's
# peak memory, and the load average before and after. The target: dba at least
# 1.7x faster than bzcat on 2 idle cores. FILE is a BAL problem replicated K
# times (scripts/replicate-bal.sh) and compressed by `bzip2 -9`, made once in
# DIR (default /work/big; K 850 of problem-16-22106: 1.03 GB, 4.1 GB of text,
# 71M observations; making it takes about 20 minutes, a bzcat run minutes).
#
#   bash bench/read_bz2.sh [--copies K] [--repeats R] [--dir DIR] [--threads T] [BAL.bz2]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
dba=$root/build/dba copies=850 repeats=3 dir=/work/big threads=""
problem=$root/../shared/data/bal/problem-16-22106-pre.txt.bz2
while [ $# -gt 0 ]; do
  case "$1" in
    --copies) copies=$2; shift 2 ;;
    --repeats) repeats=$2; shift 2 ;;
    --dir) dir=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    -h|--help) sed -n '2,12p' "$0"; exit 0 ;;
    -*) echo "read_bz2.sh: unknown option $1" >&2; exit 2 ;;
    *) problem=$1; shift ;;
  esac
done
name=$(basename "$problem" .bz2)
name=${name%.txt}
file=$dir/$name-x$copies.txt.bz2
if [ ! -f "$file" ]; then
  mkdir -p "$dir"
  bash "$root/scripts/replicate-bal.sh" "$problem" "$copies" "$dir/$name-x$copies.txt"
  bzip2 -9 "$dir/$name-x$copies.txt"
fi
[ -z "$threads" ] || export OMP_NUM_THREADS=$threads
median() { sort -g | awk '{v[NR] = $1} END {m = NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2; printf "%.1f (%.1f-%.1f)", m, v[1], v[NR]}'; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
run_bzcat() { /usr/bin/time -f "%e" -o "$work/t" bzcat "$file" >/dev/null; cat "$work/t" >>"$work/bzcat"; }
run_dba() {
  /usr/bin/time -f "%e %M" -o "$work/t" "$dba" info "$file" >"$work/info"
  cut -d' ' -f1 "$work/t" >>"$work/dba"
  cut -d' ' -f2 "$work/t" >>"$work/peak"
}
load_before=$(cut -d' ' -f1-3 /proc/loadavg)
for ((r = 0; r < repeats; ++r)); do
  if ((r % 2 == 0)); then run_bzcat; run_dba; else run_dba; run_bzcat; fi
done
load_after=$(cut -d' ' -f1-3 /proc/loadavg)
b=$(median <"$work/bzcat")
d=$(median <"$work/dba")
ratio=$(awk -v b="${b%% *}" -v d="${d%% *}" 'BEGIN { printf "%.2f", b / d }')
peak=$(sort -g "$work/peak" | tail -1)
echo "$(basename "$file"): $(stat -c %s "$file") bytes; $(grep -E "^  (cameras|points|observations)" "$work/info" | tr -s ' ' | tr '\n' ';')"
echo
echo "| threads | bzcat (s) | dba info (s) | bzcat / dba | dba peak (MB) | load average before / after |"
echo "|---|---|---|---|---|---|"
echo "| ${threads:-$(nproc)} | $b | $d | $ratio | $((peak / 1024)) | $load_before / $load_after |"
