#!/usr/bin/env bash
# Time per LM iteration on the shipped COLMAP models (../shared/data/colmap),
# two dba binaries side by side, alternating, RUNS times each (medians, and
# the spread min–max): BASE, e.g. a build of the commit before a change, and
# NEW, each model in its own camera model (all SIMPLE_RADIAL). Then NEW on
# the same models rewritten as OPENCV (fx = fy = f, k1 = k, the rest 0) and
# FULL_OPENCV, for the cost of the larger intrinsic blocks: in the first
# round only, and at most 10 LM iterations (softmurata_177img's 177 groups
# take minutes to converge in FULL_OPENCV). Per iteration:
# (RCS formation + linear solve + back-substitution) / iterations, from the
# JSON report; 2 threads, default options. A few minutes; not part of CI.
#
#   bash bench/camera_models.sh BASE_DBA NEW_DBA [RUNS]
set -euo pipefail
base=$1
new=$2
runs=${3:-5}
root=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

per_iteration() {  # per_iteration REPORT -> seconds per LM iteration
  python3 -c '
import json, sys
d = json.load(open(sys.argv[1]))
s = d["seconds"]
print((s["rcs_formation"] + s["linear_solve"] + s["back_substitution"]) / max(1, d["iterations"]))' "$1"
}
field() { python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])' "$1" "$2"; }
stats() {  # stats VALUES... -> "median (min–max)" in ms
  python3 -c '
import statistics, sys
v = [1000 * float(x) for x in sys.argv[1:]]
print(f"{statistics.median(v):.1f} ({min(v):.1f}–{max(v):.1f})")' "$@"
}
rewrite() {  # rewrite DIR MODEL OUT: the SIMPLE_RADIAL cameras as MODEL (text)
  local dir=$1 model=$2 out=$3
  mkdir -p "$out"
  "$new" solve "$dir" -q --max-iterations 0 -o "$out" --colmap-format text >/dev/null
  python3 - "$out/cameras.txt" "$model" <<'PY'
import sys
path, model = sys.argv[1], sys.argv[2]
lines = []
for line in open(path):
    t = line.split()
    if line.startswith("#") or len(t) < 8 or t[1] != "SIMPLE_RADIAL":
        lines.append(line); continue
    f, cx, cy, k = t[4:8]
    extra = {"OPENCV": [f, f, cx, cy, k, "0", "0", "0"],
             "FULL_OPENCV": [f, f, cx, cy, k] + ["0"] * 7}[model]
    lines.append(" ".join(t[:1] + [model] + t[2:4] + extra) + "\n")
open(path, "w").writelines(lines)
PY
}

declare -A times iterations total
models=()
for dir in "$root"/../shared/data/colmap/*/sparse/0; do
  name=$(basename "$(dirname "$(dirname "$dir")")")
  models+=("$name")
  for m in OPENCV FULL_OPENCV; do rewrite "$dir" "$m" "$work/$name-$m"; done
done
for ((r = 0; r < runs; r++)); do
  for name in "${models[@]}"; do
    dir=$root/../shared/data/colmap/$name/sparse/0
    for which in base new; do
      bin=$base; [[ $which == new ]] && bin=$new
      "$bin" solve "$dir" -q -t 2 --report "$work/r.json" >/dev/null
      times[$name,$which]+=" $(per_iteration "$work/r.json")"
      iterations[$name,$which]=$(field "$work/r.json" iterations)
      total[$name]=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["seconds"]["total"])' "$work/r.json")
    done
    for m in OPENCV FULL_OPENCV; do
      ((r == 0)) || continue
      "$new" solve "$work/$name-$m" -q -t 2 --max-iterations 10 --report "$work/r.json" >/dev/null
      times[$name,$m]+=" $(per_iteration "$work/r.json")"
      iterations[$name,$m]=$(field "$work/r.json" iterations)
    done
  done
done

echo "| model | solve (s) | iterations (base / new) | base ms/iteration | new ms/iteration | new / base | OPENCV ms/iteration (iterations) | FULL_OPENCV ms/iteration (iterations) |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|"
for name in "${models[@]}"; do
  ratio=$(python3 -c '
import statistics, sys
a = [float(x) for x in sys.argv[1].split()]; b = [float(x) for x in sys.argv[2].split()]
print(f"{statistics.median(b) / statistics.median(a):.3f}")' "${times[$name,base]}" "${times[$name,new]}")
  # shellcheck disable=SC2086
  echo "| $name | ${total[$name]} | ${iterations[$name,base]} / ${iterations[$name,new]} | $(stats ${times[$name,base]}) | $(stats ${times[$name,new]}) | $ratio | $(stats ${times[$name,OPENCV]}) (${iterations[$name,OPENCV]}) | $(stats ${times[$name,FULL_OPENCV]}) (${iterations[$name,FULL_OPENCV]}) |"
done
