#!/usr/bin/env bash
# Makes a larger BAL problem from a real one: K disjoint copies (cameras and
# points renumbered, values unchanged), so the solution is K copies of the
# original's and the final cost is K times the original's.
# Assumes the usual BAL layout of one parameter value per line.
# Usage: replicate-bal.sh INPUT(.bz2) K OUTPUT.txt
set -euo pipefail
in=$1; k=$2; out=$3
cat_cmd=cat; case "$in" in *.bz2) cat_cmd=bzcat ;; esac
$cat_cmd "$in" | awk -v K="$k" '
  NR == 1 { nc = $1; np = $2; no = $3; print nc * K, np * K, no * K; next }
  { line[++n] = $0 }
  END {
    for (r = 0; r < K; ++r)
      for (i = 1; i <= no; ++i) { split(line[i], f, " "); print f[1] + r * nc, f[2] + r * np, f[3], f[4] }
    cam_end = no + 9 * nc
    for (r = 0; r < K; ++r) for (i = no + 1; i <= cam_end; ++i) print line[i]
    for (r = 0; r < K; ++r) for (i = cam_end + 1; i <= n; ++i) print line[i]
  }' > "$out.tmp.$$"
mv "$out.tmp.$$" "$out"
