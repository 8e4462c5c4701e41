#!/usr/bin/env bash
# The report's time (`seconds`): phases from the process's start to the
# report that add up to its total, against the wall time measured around
# the process; the start counted from before the exec; the end of a solved
# run (a fast exit, session/solve_outputs.h, app/solve_command.cc) leaving
# its outputs committed and its printed summary whole, with one process
# and over MPI ranks. Usage: cli_report_time.sh PATH_TO_DBA PROJECT_ROOT
set -uo pipefail
source "$(dirname "$0")/lib/check.sh"
dba=$1
root=$2
data=$root/../shared/data/bal
need_shared "$data"
p49=$data/problem-49-7776-pre.txt.bz2
small=$data/balbianello-5-544-from-bundler.txt.bz2
# The kernel records a process's start in clock ticks (common/process_start.h):
# its age is known to half a tick, so a total may pass the wall time around
# the process by that much (measured: 2 ms at 100 ticks a second).
tick=$(python3 -c 'import os; print(1.0 / os.sysconf("SC_CLK_TCK"))')

# timed OUT COMMAND...: runs COMMAND with stdout and stderr in OUT; the wall
# time around it in $wall (seconds), its status in $status.
timed() {
  local out=$1 t0
  shift
  t0=$EPOCHREALTIME
  "$@" >"$out" 2>&1
  status=$?
  wall=$(python3 -c 'import sys; print(float(sys.argv[2]) - float(sys.argv[1]))' "$t0" "$EPOCHREALTIME")
}

# sums REPORT OUT: the report's phases add up to its total (to rounding), the
# printed summary's milliseconds to its printed total exactly, and the
# printed total is the report's.
sums() {
  python3 - "$1" "$2" <<'PY'
import json, re, sys
s = json.load(open(sys.argv[1]))["seconds"]
phases = ["startup", "read", "load", "distribution", "setup", "rcs_formation", "linear_solve",
          "back_substitution", "analysis", "write", "other"]
ok = abs(sum(s[k] for k in phases) - s["total"]) <= 1e-9 * max(1.0, s["total"])
ok = ok and all(s[k] >= 0 for k in phases[:-1]) and s["other"] > -1e-3
text = open(sys.argv[2]).read()
m = re.search(r"time \(s\) (.*?) total ([0-9.]+) \(wall time from the start\)", text, re.S)
if not m:
    sys.exit("no time line in " + sys.argv[2])
printed = [round(1000 * float(x)) for x in re.findall(r"-?[0-9]+\.[0-9]{3}", m.group(1))]
ok = ok and len(printed) == 11 and sum(printed) == round(1000 * float(m.group(2)))
ok = ok and round(1000 * float(m.group(2))) == round(1000 * s["total"])
if not ok:
    print(s, printed, m.group(2), file=sys.stderr)
sys.exit(0 if ok else 1)
PY
}

# One process: the total is the wall time from the start to the report,
# within 25% + 0.3 s of the wall time around the process (which adds the
# report's writing and the exit), never above it by more than the tick; reading a .bz2 is most of
# the time before the solve.
timed "$tmp/p49.out" "$dba" solve "$p49" -o "$tmp/p49.txt" --report "$tmp/p49.json"
check "problem-49 solves (exit 0)" test "$status" -eq 0
check "problem-49's phases add up to its total (report and summary)" sums "$tmp/p49.json" "$tmp/p49.out"
check "problem-49's total is the wall time around the process, within 25% + 0.3 s" json "$tmp/p49.json" \
  "$wall * 0.75 - 0.3 <= d['seconds']['total'] <= $wall + $tick"
check "problem-49's read and start-up are counted" json "$tmp/p49.json" \
  "d['seconds']['read'] > 0.05 and d['seconds']['startup'] > 0"
# The fast exit leaves the outputs committed and the summary printed whole
# into a file (a buffered stream).
check "the output is committed" test -s "$tmp/p49.txt"
check "no temporary is left" test -z "$(ls "$tmp" | grep '\.tmp\.')"
check "the summary printed into a file is whole" test "$(tail -1 "$tmp/p49.out")" = "  report              $tmp/p49.json"

# The start is the process's: a shell that sleeps 1 s, then execs dba (which
# starts itself again, tools/dba_main.cc), is the same process: its start-up
# holds the second.
timed "$tmp/late.out" sh -c 'sleep 1; exec "$0" solve "$1" -q --report "$2"' "$dba" "$small" "$tmp/late.json"
check "dba exec'd after 1 s solves (exit 0)" test "$status" -eq 0
check "the start-up counts from the process's start, before its exec" json "$tmp/late.json" \
  "d['seconds']['startup'] >= 0.99 and d['seconds']['total'] <= $wall + $tick"
check "the late start's phases add up to its total" sums "$tmp/late.json" "$tmp/late.out"

# Over MPI ranks: the main rank's report adds up the same; every rank ends.
if command -v mpirun >/dev/null; then
  timed "$tmp/mpi.out" timeout -k 10 300 mpirun --allow-run-as-root --oversubscribe --bind-to none \
    -np 2 "$dba" solve "$small" --report "$tmp/mpi.json" -o "$tmp/mpi.txt"
  check "2 ranks solve (exit 0)" test "$status" -eq 0
  check "2 ranks: the phases add up to the total" sums "$tmp/mpi.json" "$tmp/mpi.out"
  check "2 ranks: the total is within the wall time around mpirun" json "$tmp/mpi.json" \
    "0 < d['seconds']['total'] <= $wall + $tick and d['ranks'] == 2"
  check "2 ranks: the output is committed" test -s "$tmp/mpi.txt"
fi

finish
