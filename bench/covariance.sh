#!/usr/bin/env bash
# --covariance at scale (bench/README.md, "Covariance"): a generated
# photogrammetric survey renumbered by `dba convert --shuffle`, solved with
# the defaults alone and with --covariance, alternating, REPEATS pairs; per
# run the wall time and peak (GNU time), the report's total and covariance
# figures. Nothing else should run.
# Usage: bench/covariance.sh DBA WORKDIR IMAGES [REPEATS]
set -euo pipefail
dba=$1
work=$2
images=$3
repeats=${4:-3}
mkdir -p "$work"
survey=$work/cov$images.dba
shuffled=$work/cov$images.shuffled.dba
[ -e "$shuffled" ] || { "$dba" generate --model photo --images "$images" --seed 3 "$survey" >/dev/null
                        "$dba" convert "$survey" "$shuffled" --shuffle 1 >/dev/null; }
for i in $(seq "$repeats"); do
  for mode in plain covariance; do
    extra=(); [ "$mode" = covariance ] && extra=(--covariance "$work/cov.csv")
    /usr/bin/time -f "%e %M" -o "$work/time" "$dba" solve "$shuffled" -q --report "$work/r.json" "${extra[@]}" >/dev/null
    read -r wall peak <"$work/time"
    /usr/bin/python3 - "$work/r.json" "$mode" "$wall" "$peak" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
c = d.get("covariance", {})
cov = c.get("seconds", 0.0)
print(f"{sys.argv[2]:10s} wall {float(sys.argv[3]):7.2f} s  peak {int(sys.argv[4]):>9,} kB  total {d['seconds']['total']:7.2f}  "
      f"solve {d['seconds']['total'] - cov:6.2f}  covariance {cov:6.2f} (factor {c.get('factor_seconds', 0):6.2f})  "
      f"factor values {c.get('factor_nonzeros', 0):,}  inversion flops {c.get('inversion_flops', 0):.3g}")
PY
  done
done
