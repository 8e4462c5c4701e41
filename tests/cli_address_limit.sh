#!/usr/bin/env bash
# The sparse factorization under a limit on the address space (ulimit -v):
# at every limit from 250 to 400 MB it solves or says why, and never hangs.
# OpenBLAS retries a refused buffer forever; between 290 and 310 MB with -t 2
# the room for it was there when checked, and CHOLMOD's OpenMP threads took
# it before BLAS ran (common/blas_threads.h).
# Usage: cli_address_limit.sh PATH_TO_DBA PROJECT_ROOT
set -uo pipefail
source "$(dirname "$0")/lib/check.sh"
dba=$1
root=$2
bal=$root/data/problem-49-7776-pre.txt.bz2

solved=0
for kb in $(seq 250000 10000 400000); do
  for t in 1 2; do
    (ulimit -v "$kb"; timeout -k 5 60 "$dba" solve "$bal" -q --linear-solver sparse -t "$t") \
      >"$tmp/log" 2>&1
    status=$?
    name="ulimit -v $kb, -t $t"
    check "$name: ends (status $status)" test "$status" -eq 0 -o "$status" -eq 1
    if [ "$status" -eq 0 ]; then
      solved=$((solved + 1))
      check "$name: the exact optimum" grep -qE "final cost +1\.33443" "$tmp/log"
    else
      check "$name: says why" contains "$tmp/log" \
        "the address-space limit (ulimit -v, RLIMIT_AS) leaves"
    fi
  done
done
# Where it solves depends on the build's start-up footprint (the reader's
# per-thread bzip2 buffers among it): at least the highest limits do.
check "the solve runs at the higher limits ($solved of 32)" test "$solved" -ge 4
finish
