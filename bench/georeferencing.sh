#!/usr/bin/env bash
# GNSS-georeferenced surveys: a generated survey started in a random
# similarity frame (--unaligned), GNSS priors with σ 2 m horizontal / 4 m
# vertical and 2% gross errors (20-50 m), solved with defaults. Prints, per
# seed: the mean camera-centre offset from the truth per axis against
# 3σ/√N, the gross errors flagged (of how many) and the inliers flagged, and
# the time per LM iteration with and without the priors (the same survey,
# already aligned, solved without them). About 13 s per seed at 10,000
# images; not part
# of CI (tests/cli_generate.sh runs a 300-image version).
#
#   bash bench/georeferencing.sh [IMAGES] [SEEDS...]
#   PRIOR_ARGS="--prior-loss huber --prior-loss-scale 2" bash bench/georeferencing.sh ...
# (the solve's prior options; default: none, dba's defaults)
set -euo pipefail
cd "$(dirname "$0")/.."
images=${1:-10000}
shift || true
seeds=("${@:-1}")
dba=./build/dba
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

echo "| seed | images | mean offset X, Y, Z (m) | 3σ/√N (m) | RMS centre error (m) | gross errors flagged | inliers flagged | iterations | ms/iteration with priors | without |"
echo "|---:|---:|---|---|---:|---:|---:|---:|---:|---:|"
for seed in "${seeds[@]}"; do
  "$dba" generate "$work/s.dba" --model photo --images "$images" --cameras 2 --seed "$seed" \
    --unaligned --priors "$work/p.txt" --gnss-sigma 2,4 --gnss-outliers 0.02 \
    --truth "$work/t.dba" >/dev/null
  # shellcheck disable=SC2086
  "$dba" solve "$work/s.dba" -q --camera-priors "$work/p.txt" ${PRIOR_ARGS:-} -o "$work/out.dba" \
    --report "$work/with.json" >/dev/null
  "$dba" solve "$work/out.dba" -q --report "$work/without.json" >/dev/null
  python3 - "$work" "$images" "$seed" <<'PY'
import json, math, struct, sys
work, n = sys.argv[1], int(sys.argv[2])
with_ = json.load(open(f"{work}/with.json"))
without = json.load(open(f"{work}/without.json"))
# Centres of the solved and the true cameras, from the .dba files (poses:
# 6 doubles per image after the 128-byte header; C = -R(w)^T t).
def centres(path):
    with open(path, "rb") as f:
        f.seek(128)
        data = f.read(48 * n)
    out = []
    for i in range(n):
        w = struct.unpack_from("6d", data, 48 * i)
        th = math.sqrt(w[0] ** 2 + w[1] ** 2 + w[2] ** 2)
        k = [c / th for c in w[:3]] if th > 0 else [0.0, 0.0, 0.0]
        c, s = math.cos(th), math.sin(th)
        t = w[3:]
        # R^T t by Rodrigues with -w: t cos + (k x t)(-s) ... R(-w) t
        kxt = [k[1] * t[2] - k[2] * t[1], k[2] * t[0] - k[0] * t[2], k[0] * t[1] - k[1] * t[0]]
        kt = sum(k[j] * t[j] for j in range(3))
        rt = [t[j] * c - kxt[j] * s + k[j] * kt * (1 - c) for j in range(3)]
        out.append([-x for x in rt])
    return out
solved, truth = centres(f"{work}/out.dba"), centres(f"{work}/t.dba")
mean = [sum(a[j] - b[j] for a, b in zip(solved, truth)) / n for j in range(3)]
rms = math.sqrt(sum(sum((a[j] - b[j]) ** 2 for j in range(3)) for a, b in zip(solved, truth)) / n)
bound = [3 * 2 / math.sqrt(n), 3 * 2 / math.sqrt(n), 3 * 4 / math.sqrt(n)]
outliers = set(l.split()[0] for l in open(f"{work}/p.txt") if l.rstrip().endswith("# outlier"))
flagged = set(with_["camera_priors"]["flagged"])
per_it = lambda d: 1000 * (d["seconds"]["rcs_formation"] + d["seconds"]["linear_solve"] +
                           d["seconds"]["back_substitution"]) / max(1, d["iterations"])
print(f"| {sys.argv[3]} | {n} | "
      f"{mean[0]:.3f}, {mean[1]:.3f}, {mean[2]:.3f} | {bound[0]:.3f}, {bound[1]:.3f}, {bound[2]:.3f} | "
      f"{rms:.3f} | "
      f"{len(outliers & flagged)} of {len(outliers)} | {len(flagged - outliers)} of {n - len(outliers)} | "
      f"{with_['iterations']} | {per_it(with_):.0f} | {per_it(without):.0f} |")
PY
done
