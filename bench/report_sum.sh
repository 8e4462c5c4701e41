#!/usr/bin/env bash
# The report's time against the wall time of the process: runs `dba solve`
# under /usr/bin/time, with the shell's microsecond clock ($EPOCHREALTIME)
# read just before and after, and prints a Markdown table per run: the wall
# time (/usr/bin/time's %e, 10 ms steps, and the clock around it), the
# report's phases (`seconds`: from the process's start to the report), their
# sum against the report's total, the total against the wall time, and the
# time from the report to the process's end (the wall time less the total:
# the report's own writing, the commit, the printed summary, the exit).
# Method and figures: bench/README.md, "The report's time against the wall
# time".
#
#   bash bench/report_sum.sh [--repeats N] INPUT [DBA SOLVE OPTIONS...]
#   env: DBA (default build/dba beside this script's bench/), WORK (default a new temporary directory,
#        removed at the end; the report and the outputs are written there)
set -euo pipefail
repeats=1
if [ "${1:-}" = --repeats ]; then repeats=$2; shift 2; fi
[ $# -ge 1 ] || { sed -n '2,15p' "$0"; exit 2; }
input=$1
shift
dba=${DBA:-$(cd "$(dirname "$0")/.." && pwd)/build/dba}
work=${WORK:-}
if [ -z "$work" ]; then
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
fi
mkdir -p "$work"

echo "| run | wall, time (s) | wall, around (s) | report total (s) | total / wall | report to exit (s) | start-up | read | checks | solve | write | other | phases = total | peak (MiB) |"
echo "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|"
for r in $(seq "$repeats"); do
  rm -f "$work/report.json"
  t0=$EPOCHREALTIME
  /usr/bin/time -f '%e %M' -o "$work/time" "$dba" solve "$input" --report "$work/report.json" "$@" \
    >"$work/out" 2>"$work/err" || { echo "run $r failed:" >&2; cat "$work/err" >&2; exit 1; }
  t1=$EPOCHREALTIME
  python3 - "$r" "$work/report.json" "$work/time" "$t0" "$t1" "$work/out" <<'PY'
import json, re, sys
run, report, timefile, t0, t1, out = sys.argv[1:]
s = json.load(open(report))["seconds"]
wall, kib = open(timefile).read().split()[-2:]
wall, around = float(wall), float(t1) - float(t0)
solve = sum(s[k] for k in ("distribution", "setup", "rcs_formation", "linear_solve", "back_substitution"))
phases = ("startup", "read", "load", "distribution", "setup", "rcs_formation", "linear_solve",
          "back_substitution", "write", "other")
json_sum_ok = abs(sum(s[k] for k in phases) - s["total"]) <= 1e-9 * max(1.0, s["total"])
# The printed summary: its milliseconds add up to its total exactly.
text = open(out).read()
m = re.search(r"time \(s\)(.*?)total ([0-9.]+)", text, re.S)
printed = [float(x) for x in re.findall(r"-?[0-9]+\.[0-9]{3}", m.group(1))]
text_sum_ok = round(1000 * sum(printed)) == round(1000 * float(m.group(2)))
print(f"| {run} | {wall:.2f} | {around:.3f} | {s['total']:.3f} | {s['total'] / around:.4f} | "
      f"{around - s['total']:.3f} | {s['startup']:.3f} | {s['read']:.3f} | {s['load']:.3f} | "
      f"{solve:.3f} | {s['write']:.3f} | {s['other']:.3f} | "
      f"{'yes' if json_sum_ok and text_sum_ok else 'NO'} | {int(kib) / 1024:.0f} |")
PY
done
