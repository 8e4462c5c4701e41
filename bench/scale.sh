#!/usr/bin/env bash
# Scale on one machine : generates UAV surveys of growing size with
# `dba generate` and solves them with `dba solve --truth`, both under
# /usr/bin/time -v, and prints a Markdown table: generation time and memory,
# cameras/points/observations, solve time (total and per LM iteration),
# iterations, peak memory, bytes per observation, RMS against the noise-free
# observations. Needs minutes to hours (1M images): not part of CI.
#
#   bash bench/scale.sh [IMAGES...]   (default: 10000 100000)
#   env: FEATURES (300), FORWARD (0.6), SIDE (0.3), WORK (/tmp/dba-scale),
#        SOLVE_ARGS (extra `dba solve` options, e.g. "--pcg-tolerance 1e-2")
set -euo pipefail
cd "$(dirname "$0")/.."
sizes=("$@")
[ ${#sizes[@]} -gt 0 ] || sizes=(10000 100000)
features=${FEATURES:-300}
forward=${FORWARD:-0.6}
side=${SIDE:-0.3}
work=${WORK:-/tmp/dba-scale}
read -r -a solve_args <<<"${SOLVE_ARGS:-}"
mkdir -p "$work"
bash scripts/install-deps.sh
bash scripts/build.sh >/dev/null

json() { grep -m1 "\"$2\"" "$1" | sed -E 's/.*: "?([^",]*)"?,?/\1/'; }
seconds_of() { awk -F': ' '/Elapsed \(wall clock\)/ {n = split($2, t, ":"); s = 0; for (i = 1; i <= n; ++i) s = s * 60 + t[i]; print s}' "$1"; }
mib_of() { awk -F': ' '/Maximum resident set size/ {printf "%.0f", $2 / 1024}' "$1"; }

echo "| images | points | observations | generate (s) | generate peak (MiB) | solve (s) | s / iteration | iterations | solve peak (MiB) | bytes / observation | final RMS (px) | RMS to noise-free (px) |"
echo "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
for n in "${sizes[@]}"; do
  p=$work/uav-$n.dba
  /usr/bin/time -v ./build/dba generate "$p" --images "$n" --features "$features" \
    --forward-overlap "$forward" --side-overlap "$side" --truth "$work/uav-$n.truth.dba" \
    >"$work/gen-$n.out" 2>"$work/gen-$n.time"
  /usr/bin/time -v ./build/dba solve "$p" -q "${solve_args[@]}" --truth "$work/uav-$n.truth.dba" \
    --report "$work/solve-$n.json" >"$work/solve-$n.out" 2>"$work/solve-$n.time"
  r=$work/solve-$n.json
  iters=$(json "$r" iterations)
  solve_s=$(seconds_of "$work/solve-$n.time")
  peak=$(mib_of "$work/solve-$n.time")
  obs=$(json "$r" num_observations)
  awk -v n="$n" -v p="$(json "$r" num_points)" -v o="$obs" -v gs="$(seconds_of "$work/gen-$n.time")" \
      -v gm="$(mib_of "$work/gen-$n.time")" -v ss="$solve_s" -v it="$iters" -v pk="$peak" \
      -v rms="$(json "$r" final_rms_px)" -v nf="$(json "$r" rms_to_noise_free_px)" 'BEGIN {
    printf "| %d | %d | %d | %.1f | %d | %.1f | %.1f | %d | %d | %.1f | %.3f | %.3f |\n",
      n, p, o, gs, gm, ss, ss / (it > 0 ? it : 1), it, pk, pk * 1048576 / o, rms, nf }'
  rm -f "$p" "$work/uav-$n.truth.dba"
done
