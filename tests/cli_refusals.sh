#!/usr/bin/env bash
# Every refusal of `dba solve` as a table: the arguments, the exit status
# (2: arguments, also those that do not fit the input; 1: input or
# environment), a part of the message (naming the flag or the file), and
# that nothing is left behind (no -o output, no report, no temporary).
# Usage: cli_refusals.sh PATH_TO_DBA PROJECT_ROOT
set -uo pipefail
source "$(dirname "$0")/lib/check.sh"
dba=$1
root=$2
bal=$root/data/problem-49-7776-pre.txt.bz2
colmap=$root/../shared/data/colmap/mithunnallana_6img/sparse/0
need_shared "$colmap" "$root/../shared/data/bal"
printf '2 1 2\n0 0 1.0 2.0\n1 0 1.0 abc\n' >"$tmp/malformed.txt"
printf '2 2 4\n0 0 1.0 2.0\n1 0 1.5 2.0\n0 1 1.0 1e200\n1 1 3.0 2.0\n0 0 0 0 0 -5 500 0 0\n0.01 0 0 0 0 -5 500 0 0\n0 0 1\n0.1 0.1 0.5\n' >"$tmp/nonfinite.txt"
"$dba" generate "$tmp/photo.dba" --model photo --images 20 >/dev/null

n=0
# refuse STATUS MESSAGE [no-o] ARGS...: runs `dba solve ARGS... --report R`
# (and -o O unless ARGS has its own or no-o), checks status, message and what
# is left.
refuse() {
  local status=$1 message=$2; shift 2
  n=$((n + 1))
  local out=$tmp/out_$n.txt report=$tmp/report_$n.json
  local extra=(-o "$out")
  for a in "$@"; do [ "$a" = "-o" ] && extra=(); done
  if [ "$1" = "no-o" ]; then extra=(); shift; fi
  "$dba" solve "$@" "${extra[@]}" --report "$report" >"$tmp/log" 2>&1
  local got=$?
  local name="[$n] dba solve $*"
  check "$name: exit $status (got $got)" test "$got" -eq "$status"
  check "$name: says '$message'" contains "$tmp/log" "$message"
  check "$name: no output" test ! -e "$out"
  check "$name: no report" test ! -e "$report"
  check "$name: no temporary" test -z "$(find "$tmp" -name '*.tmp.*')"
}

# Arguments (exit 2).
refuse 2 "missing INPUT" -q
refuse 2 "more than one input file" "$bal" "$bal"
refuse 2 "unknown option '--bogus'" "$bal" --bogus
refuse 2 "--threads" "$bal" --threads zero
refuse 2 "[1, 1024]" "$bal" -t 100000
refuse 2 "--main-rank" "$bal" --main-rank boss
refuse 2 "--intrinsics: expected shared or per-image" "$bal" --intrinsics some
refuse 2 "--linear-solver" "$bal" --linear-solver qr
refuse 2 "--loss" "$bal" --loss l1
refuse 2 "--partition" "$bal" --partition random
refuse 2 "--colmap-format: no -o output" no-o "$bal" --colmap-format text
# Arguments that do not fit the input (exit 2, found after reading it).
refuse 2 "--fix-images" "$bal" --fix-images 99
refuse 2 "COLMAP models only" "$bal" --intrinsics per-image
refuse 2 "--fix-intrinsics" "$bal" --fix-intrinsics f
refuse 2 "expected a .txt, .bz2 or .dba file" "$bal" -o "$tmp/out.xyz"
refuse 2 "BAL text cannot hold shared intrinsics" "$tmp/photo.dba" -o "$tmp/photo_out.txt"
refuse 2 "--truth" "$bal" --truth "$root/../shared/data/bal/problem-21-11315-pre.txt.bz2"
refuse 2 "not a COLMAP model directory" "$colmap" -o "$tmp/x.dba" --colmap-format text
# Input and environment (exit 1).
refuse 1 "$tmp/none.txt" "$tmp/none.txt"
refuse 1 "$tmp/malformed.txt:3" "$tmp/malformed.txt"
refuse 1 "observation 2 (camera 0, point 1)" "$tmp/nonfinite.txt"
refuse 1 "$tmp/no_truth.txt" "$bal" --truth "$tmp/no_truth.txt"
refuse 1 "does not exist" "$bal" -o "$tmp/no_dir/out.txt"
refuse 1 "does not exist" "$bal" --ply "$tmp/no_dir/p.ply"
finish
