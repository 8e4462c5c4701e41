#!/usr/bin/env bash
# Peak memory per rank of a distributed solve, with the RCS spread over the
# ranks (--rcs distributed) and gathered on rank 0 (--rcs gather), for
# N = 1, 2, 4, 8 ranks on one machine; the issue's bound is checked per run:
# largest rank <= 1.3 x (one rank's peak) / N + 60 MiB, rank 0 <= 1.2 x the
# median rank. Minutes per survey on 2 cores (ranks share the cores: times
# are not speeds). Not part of CI.
#
# Usage: [RANKS="2 4 8"] [PLACEMENTS="distributed gather"] \
#        bench/distributed_memory.sh DBA PROBLEM.dba OUT_DIR [dba solve options...]
# e.g.   bench/distributed_memory.sh build/dba s100k.dba /tmp/dm --max-iterations 3
set -euo pipefail
dba=$1; problem=$2; out=$3; shift 3
extra=("$@")
mkdir -p "$out"
run() {  # ranks placement
  timeout -k 10 7200 mpirun --allow-run-as-root --oversubscribe --bind-to none -np "$1" \
    "$dba" solve "$problem" -q --rcs "$2" --report "$out/$2-$1.json" "${extra[@]}" >"$out/$2-$1.log" 2>&1
}
"$dba" solve "$problem" -q --report "$out/single.json" "${extra[@]}" >"$out/single.log" 2>&1
for n in ${RANKS:-2 4 8}; do
  for placement in ${PLACEMENTS:-distributed gather}; do run "$n" "$placement"; done
done
python3 - "$out" <<'PY'
import json, statistics, sys, os
out = sys.argv[1]
one = json.load(open(f"{out}/single.json"))
peak1 = one["memory"]["peak_bytes"]
MiB = 2**20
print(f"one process: peak {peak1/MiB:.0f} MiB, final cost {one['final_cost']:.6e}")
print("| ranks | RCS | rank peaks (MiB) | largest | bound 1.3*P1/N+60 | rank 0 / median | final cost rel. to one |")
print("|---:|---|---|---:|---:|---:|---:|")
for n in (2, 4, 8):
    for placement in ("distributed", "gather"):
        path = f"{out}/{placement}-{n}.json"
        if not os.path.exists(path):
            continue
        r = json.load(open(path))
        peaks = [k["peak_memory_bytes"] / MiB for k in r["distributed"]["ranks"]]
        bound = 1.3 * peak1 / MiB / n + 60
        med = statistics.median(peaks)
        rel = abs(r["final_cost"] - one["final_cost"]) / one["final_cost"]
        print(f"| {n} | {placement} | {' '.join(f'{p:.0f}' for p in peaks)} | {max(peaks):.0f} | "
              f"{bound:.0f} {'ok' if max(peaks) <= bound else 'MISSED'} | {peaks[0]/med:.2f} | {rel:.1e} |")
PY
