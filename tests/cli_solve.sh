#!/usr/bin/env bash
# End-to-end checks of `dba solve`: help, argument and input errors (exit
# status, message, no output left behind), and a real solve with output and
# JSON report. Usage: cli_solve.sh PATH_TO_DBA PROJECT_ROOT
set -uo pipefail
source "$(dirname "$0")/lib/check.sh"
dba=$1
root=$2
data=$root/../shared/data/bal

# Help tells the truth: every option the parser knows is listed.
"$dba" --help >"$tmp/help" 2>&1; check "dba --help exits 0" test $? -eq 0
check "dba --help lists solve" contains "$tmp/help" "solve"
"$dba" solve --help >"$tmp/solve_help" 2>&1; check "solve --help exits 0" test $? -eq 0
for opt in --output --report --threads --max-iterations --function-tolerance \
           --gradient-tolerance --parameter-tolerance --initial-lambda \
           --pcg-tolerance --pcg-max-iterations --quiet; do
  check "solve --help lists $opt" contains "$tmp/solve_help" "$opt"
done

# Bad arguments: exit 2 and a message naming the argument.
"$dba" solve >"$tmp/out" 2>&1; check "missing input exits 2" test $? -eq 2
check "missing input is named" contains "$tmp/out" "missing INPUT"
"$dba" solve x --threads zero >"$tmp/out" 2>&1; check "bad --threads exits 2" test $? -eq 2
check "bad --threads is named" contains "$tmp/out" "--threads"
"$dba" solve x --bogus >"$tmp/out" 2>&1; check "unknown option exits 2" test $? -eq 2
"$dba" frobnicate >"$tmp/out" 2>&1; check "unknown command exits 2" test $? -eq 2

# Bad input: exit 1, file and line in the message, no output written.
"$dba" solve "$tmp/none.txt" -o "$tmp/o1.txt" >"$tmp/out" 2>&1
check "missing file exits 1" test $? -eq 1
check "missing file is named" contains "$tmp/out" "$tmp/none.txt"
printf '2 1 2\n0 0 1.0 2.0\n1 0 1.0 abc\n' >"$tmp/bad.txt"
"$dba" solve "$tmp/bad.txt" -o "$tmp/o2.txt" --report "$tmp/r2.json" >"$tmp/out" 2>&1
check "malformed file exits 1" test $? -eq 1
check "malformed file names file and line" contains "$tmp/out" "$tmp/bad.txt:3"
check "no output after failure" test ! -e "$tmp/o2.txt"
check "no report after failure" test ! -e "$tmp/r2.json"
check "no temporary left" test -z "$(ls "$tmp" | grep tmp)"

# A directory is refused with what it is.
"$dba" solve "$root/../shared/data/colmap/fountain_p11/sparse/0" >"$tmp/out" 2>&1
check "COLMAP directory exits 1" test $? -eq 1
check "COLMAP directory is recognized" contains "$tmp/out" "a COLMAP model"

# A real solve: summary, output and report.
"$dba" solve "$data/balbianello-5-544-from-bundler.txt.bz2" -t 2 \
  -o "$tmp/adjusted.txt" --report "$tmp/report.json" >"$tmp/out" 2>&1
check "solve exits 0" test $? -eq 0
for field in "initial cost" "final cost" "iterations" "termination" "time (s)" \
             "memory" "bytes/observation"; do
  check "summary has $field" contains "$tmp/out" "$field"
done
check "final cost is the exact optimum" grep -qE "final cost +1\.25169" "$tmp/out"
check "output written" test -s "$tmp/adjusted.txt"
check "report has final cost" grep -qE '"final_cost": 125\.1[67]' "$tmp/report.json"
check "report has termination" grep -q '"termination": "function_tolerance"' "$tmp/report.json"
check "report has history" grep -q '"history"' "$tmp/report.json"
# The written result is a valid BAL file already at the optimum.
"$dba" solve "$tmp/adjusted.txt" -q --max-iterations 0 >"$tmp/out2" 2>&1
check "output re-reads" test $? -eq 0
check "output is at the optimum" grep -qE "initial cost +1\.25169" "$tmp/out2"

finish
