#!/usr/bin/env bash
# `dba generate`: help, argument errors, byte-identical output for a seed,
# and `dba solve --truth` on what it made.
# Usage: cli_generate.sh PATH_TO_DBA PROJECT_ROOT
set -uo pipefail
source "$(dirname "$0")/lib/check.sh"
dba=$1
root=${2:-$(dirname "$0")/..}

"$dba" generate --help >"$tmp/help"; check "generate --help exits 0" test $? -eq 0
for opt in --images --features --forward-overlap --side-overlap --cameras --model --camera-model \
           --field-of-view --noise --seed --truth --priors --gnss-sigma --gnss-outliers --unaligned \
           --gcps --control-points --check-points --gcp-sigma; do
  check "help lists $opt" grep -qF -- "$opt" "$tmp/help"
done
"$dba" generate >/dev/null 2>&1; check "missing output exits 2" test $? -eq 2
"$dba" generate "$tmp/x.dba" --images many >"$tmp/err" 2>&1; check "bad number exits 2" test $? -eq 2
check "bad number is named" grep -q -- "--images" "$tmp/err"
"$dba" generate "$tmp/x.dba" --side-overlap 1.5 >/dev/null 2>&1; check "bad overlap exits 2" test $? -eq 2
check "nothing written after refusal" test ! -e "$tmp/x.dba"
for bad in "--images 3000000000" "--images 1" "--features 0" "--forward-overlap 0.9999" "--side-overlap 0.9999" \
           "--noise -1" "--cameras 0" "--field-of-view 170"; do
  "$dba" generate "$tmp/x.dba" $bad >"$tmp/err" 2>&1
  check "generate $bad exits 2" test $? -eq 2
  check "generate $bad names the option" grep -qF -- "${bad%% *}:" "$tmp/err"
done
check "nothing written after the refusals" test ! -e "$tmp/x.dba"
# Memory and disk are checked before anything is generated.
DBA_MEMORY_AVAILABLE=1000000 "$dba" generate "$tmp/x.txt" --images 5000 >"$tmp/err" 2>&1
check "a BAL survey beyond the memory exits 1" test $? -eq 1
check "it names the need and the room" grep -q "needs about .* of memory but 1.0 MiB is available" "$tmp/err"
check "nothing written when the memory is short" test ! -e "$tmp/x.txt"
if [ "$(id -u)" = 0 ] && mkdir -p "$tmp/small" && mount -t tmpfs -o size=1m tmpfs "$tmp/small" 2>/dev/null; then
  "$dba" generate "$tmp/small/x.dba" --images 2000 >"$tmp/err" 2>&1
  check "a survey beyond the disk's free space exits 1" test $? -eq 1
  check "it names the file and the space" grep -q "small/x.dba: the survey's files need about .* but its file system has" "$tmp/err"
  check "nothing left on the full disk" test -z "$(ls -A "$tmp/small")"
  umount "$tmp/small"
else
  echo "SKIP: a full disk needs root and a tmpfs mount"
fi

"$dba" generate "$tmp/a.dba" --images 80 --seed 3 --truth "$tmp/a.truth.dba" >"$tmp/out"
check "generate exits 0" test $? -eq 0
"$dba" generate "$tmp/b.dba" --images 80 --seed 3 >/dev/null
check "same seed, same bytes" cmp -s "$tmp/a.dba" "$tmp/b.dba"
check "summary line" grep -q "80 images in" "$tmp/out"
"$dba" solve "$tmp/a.dba" -q --truth "$tmp/a.truth.dba" --report "$tmp/r.json" >"$tmp/solve"
check "solve with truth exits 0" test $? -eq 0
check "solve reports the ground truth" grep -q "RMS to noise-free observations" "$tmp/solve"
check "report has ground_truth: the fit nearer the noise-free observations than the noisy ones" \
  json "$tmp/r.json" '0 < d["ground_truth"]["rms_to_noise_free_px"] < d["final_rms_px"]
                      and near(d["ground_truth"]["similarity_scale"], 1, 0.01)'

# The photogrammetric model: shared intrinsic groups, .dba only.
"$dba" generate "$tmp/p.dba" --model photo --images 80 --cameras 2 --seed 3 --truth "$tmp/p.truth.dba" >"$tmp/pout"
check "generate --model photo exits 0" test $? -eq 0
check "photo summary names the groups" grep -q "80 images (photo model, 2 intrinsic groups)" "$tmp/pout"
"$dba" generate "$tmp/p2.dba" --model photo --images 80 --cameras 2 --seed 3 >/dev/null
check "photo: same seed, same bytes" cmp -s "$tmp/p.dba" "$tmp/p2.dba"
"$dba" generate "$tmp/pb.dba" --images 80 --cameras 2 --seed 3 >/dev/null
cmp -s "$tmp/p.dba" "$tmp/pb.dba"; check "photo differs from bal" test $? -ne 0
"$dba" solve "$tmp/p.dba" -q --truth "$tmp/p.truth.dba" --report "$tmp/pr.json" >"$tmp/psolve"
check "photo solve with truth exits 0" test $? -eq 0
check "photo solve reports intrinsics errors" grep -q "intrinsics 1 .*error f" "$tmp/psolve"
check "photo report has both groups' focal lengths within 1%" json "$tmp/pr.json" \
  '[e["group"] for e in d["ground_truth"]["intrinsics_error"]] == [0, 1]
   and all(e["f_relative"] < 0.01 for e in d["ground_truth"]["intrinsics_error"])'
# Any lens model (.dba version 3): the truth reports its parameters by name;
# fixing by name in one group or all; the direct, sparse and iterative
# solvers agree on its larger intrinsic blocks (12 unknowns).
"$dba" generate "$tmp/l.dba" --model photo --camera-model FULL_OPENCV --field-of-view 100 \
  --images 60 --cameras 2 --seed 3 --truth "$tmp/l.truth.dba" >/dev/null
check "generate --camera-model exits 0" test $? -eq 0
"$dba" info "$tmp/l.dba" >"$tmp/linfo" 2>&1
check "info lists the groups' lens model" grep -q "FULL_OPENCV .* 2 (fx, fy, cx, cy, k1, k2, p1, p2, k3, k4, k5, k6)" "$tmp/linfo"
"$dba" solve "$tmp/l.dba" -q --truth "$tmp/l.truth.dba" --report "$tmp/l.json" >"$tmp/lsolve" 2>&1
check "lens truth names the parameters" grep -q "intrinsics 1 .*error fx .*, k6 " "$tmp/lsolve"
check "lens report: FULL_OPENCV groups within 0.1% in focal" json "$tmp/l.json" \
  'all(e["model"] == "FULL_OPENCV" and e["f_relative"] < 0.001 and "k6" in e
       for e in d["ground_truth"]["intrinsics_error"])'
for solver in dense sparse pcg; do
  "$dba" solve "$tmp/l.dba" -q --linear-solver "$solver" --report "$tmp/l_$solver.json" >/dev/null 2>&1
  check "--linear-solver $solver solves FULL_OPENCV" json "$tmp/l_$solver.json" \
    "near(d['final_cost'], $(json_value "$tmp/l.json" final_cost), 1e-5)"
done
# The largest blocks (16 unknowns) through the two-level preconditioner,
# with a tight linear solve (--eta 0): then PCG takes the dense solve's
# steps and ends at its cost. (With the truncated-Newton stop this wide-angle
# problem's LM tail ends wherever one small step falls below the function
# tolerance: 4e-6 above the dense cost at 7c04a42, 4e-5 after the kernel
# changes that followed, from rounding alone.)
"$dba" generate "$tmp/r.dba" --model photo --camera-model RAD_TAN_THIN_PRISM_FISHEYE --field-of-view 120 \
  --images 60 --cameras 2 --seed 3 >/dev/null
"$dba" solve "$tmp/r.dba" -q --refine-principal-point --linear-solver dense --report "$tmp/r_dense.json" >/dev/null 2>&1
"$dba" solve "$tmp/r.dba" -q --refine-principal-point --linear-solver pcg --eta 0 --report "$tmp/r_pcg.json" >/dev/null 2>&1
check "PCG solves 16-unknown intrinsic blocks as the dense solve does" json "$tmp/r_pcg.json" \
  "d['camera_unknowns'] == 6 * 60 + 32 and d['linear_solver']['type'] == 'pcg' and near(d['final_cost'], $(json_value "$tmp/r_dense.json" final_cost), 1e-9)"
"$dba" solve "$tmp/l.dba" -q --fix-intrinsics 1:k4,k5,k6 --fix-intrinsics p1,p2 --report "$tmp/lf.json" >/dev/null 2>&1
check "fixing by name: 12 + 12 - 3 - 4 intrinsic unknowns, less the principal points" json "$tmp/lf.json" \
  'd["camera_unknowns"] == 6 * 60 + 17 - 4'
"$dba" solve "$tmp/l.dba" -q --fix-intrinsics k >"$tmp/lerr" 2>&1
check "a name no model has exits 2" test $? -eq 2
check "and lists the models' names" grep -q "no intrinsic parameter 'k' in any group's model; the models are FULL_OPENCV (fx, fy" "$tmp/lerr"
"$dba" solve "$tmp/l.dba" -q --fix-intrinsics 2:fx >"$tmp/lerr" 2>&1
check "a group that does not exist exits 2" test $? -eq 2
check "and is named" grep -q "intrinsic group 2 does not exist (the problem has 2 groups" "$tmp/lerr"
"$dba" generate "$tmp/x.dba" --camera-model OPENCV >"$tmp/err" 2>&1
check "--camera-model without --model photo exits 2" test $? -eq 2
"$dba" generate "$tmp/x.dba" --model photo --camera-model NOPE >"$tmp/err" 2>&1
check "an unknown camera model is refused with the known ones" grep -q "unknown camera model 'NOPE' (known: SIMPLE_PINHOLE" "$tmp/err"
"$dba" generate "$tmp/x.dba" --model photo --field-of-view 170 >"$tmp/err" 2>&1
check "a field of view of 170° is refused" grep -q -- "--field-of-view: expected a number in (0, 159.9]" "$tmp/err"

# GNSS camera priors: generated with 2% gross errors on a survey started in a
# random similarity frame; solve aligns onto them, then adjusts with them
# under their robust loss, and flags the gross errors by name (χ²₃ 99.9%).
"$dba" generate "$tmp/g.dba" --model photo --images 300 --cameras 2 --seed 4 --unaligned \
  --priors "$tmp/g.priors" --gnss-sigma 2,4 --gnss-outliers 0.03 --truth "$tmp/g.truth.dba" >/dev/null
check "generate --priors exits 0" test $? -eq 0
check "the priors file marks its gross errors" grep -q " # outlier$" "$tmp/g.priors"
"$dba" solve "$tmp/g.dba" -q --camera-priors "$tmp/g.priors" --truth "$tmp/g.truth.dba" \
  --report "$tmp/g.json" >"$tmp/gout" 2>&1
check "solve --camera-priors exits 0" test $? -eq 0
check "it aligns onto the priors first" grep -q "aligned onto them" "$tmp/gout"
outliers=$(grep " # outlier$" "$tmp/g.priors" | awk '{printf "%s\"%s\"", (n++ ? ", " : ""), $1}')
check "every gross error is flagged, and few others" json "$tmp/g.json" \
  "set([$outliers]) <= set(d['camera_priors']['flagged'])
   and len(d['camera_priors']['flagged']) <= len([$outliers]) + 3
   and d['camera_priors']['loss']['type'] == 'cauchy'"
check "the block lands in the priors' frame (the truth's, unaligned by the generator)" json "$tmp/g.json" \
  "all(abs(m) < 1.0 for m in d['camera_priors']['mean'])
   and near(d['ground_truth']['similarity_scale'], 1, 0.01)"
# --truth-absolute: no alignment before the comparison. With the priors the
# centres are within a metre of the truth; the same survey solved without
# them stays in the generator's random frame.
"$dba" solve "$tmp/g.dba" -q --camera-priors "$tmp/g.priors" --truth "$tmp/g.truth.dba" --truth-absolute \
  --report "$tmp/ga.json" --accuracy-report "$tmp/ga.txt" >/dev/null 2>&1
check "--accuracy-report: a row per prior, the flagged ones the report's" test \
  "$(grep -vc '^#' "$tmp/ga.txt") $(grep -c ' 1$' "$tmp/ga.txt")" = \
  "300 $(python3 -c "import json; print(len(json.load(open('$tmp/ga.json'))['camera_priors']['flagged']))")"
"$dba" solve "$tmp/g.dba" -q --accuracy-report "$tmp/never.txt" >"$tmp/gerr" 2>&1
check "--accuracy-report without priors exits 2" test $? -eq 2
check "and writes nothing" test ! -e "$tmp/never.txt"
"$dba" solve "$tmp/g.dba" -q --truth "$tmp/g.truth.dba" --truth-absolute --report "$tmp/gn.json" >/dev/null 2>&1
check "absolute truth: within a metre with priors, far without" json "$tmp/ga.json" \
  "d['ground_truth']['absolute'] and d['ground_truth']['camera_centre_rms'] < 1.0
   and $(python3 -c "import json; print(json.load(open('$tmp/gn.json'))['ground_truth']['camera_centre_rms'])") > 50"
# The same priors in WGS84 (EPSG:4979: latitude, longitude, ellipsoidal
# height), the generator's frame taken as east, north, up at 47°N 8°E 500 m:
# solved in a local ENU frame through geocentric coordinates (PROJ), the
# same priors are flagged and σ0² is the metric solve's.
python3 - "$tmp/g.priors" "$tmp/g84.priors" <<'PY'
import math, sys
a, f = 6378137.0, 1 / 298.257223563
e2 = f * (2 - f)
def ecef(lat, lon, h):
    p, l = math.radians(lat), math.radians(lon)
    n = a / math.sqrt(1 - e2 * math.sin(p) ** 2)
    return ((n + h) * math.cos(p) * math.cos(l), (n + h) * math.cos(p) * math.sin(l),
            (n * (1 - e2) + h) * math.sin(p))
def geodetic(x, y, z):
    lon, r = math.atan2(y, x), math.hypot(x, y)
    lat = math.atan2(z, r * (1 - e2))
    for _ in range(10):
        n = a / math.sqrt(1 - e2 * math.sin(lat) ** 2)
        h = r / math.cos(lat) - n
        lat = math.atan2(z, r * (1 - e2 * n / (n + h)))
    return math.degrees(lat), math.degrees(lon), h
lat0, lon0 = math.radians(47.0), math.radians(8.0)
o = ecef(47.0, 8.0, 500.0)
e = (-math.sin(lon0), math.cos(lon0), 0.0)
n = (-math.sin(lat0) * math.cos(lon0), -math.sin(lat0) * math.sin(lon0), math.cos(lat0))
u = (math.cos(lat0) * math.cos(lon0), math.cos(lat0) * math.sin(lon0), math.sin(lat0))
with open(sys.argv[1]) as src, open(sys.argv[2], "w") as out:
    for line in src:
        if line.startswith("#"):
            continue
        t = line.split()
        x, y, z = map(float, t[1:4])
        p = [o[k] + x * e[k] + y * n[k] + z * u[k] for k in range(3)]
        lat, lon, h = geodetic(*p)
        out.write(f"{t[0]} {lat:.10f} {lon:.10f} {h:.4f} {t[4]} {t[5]}\n")
PY
"$dba" solve "$tmp/g.dba" -q --camera-priors "$tmp/g84.priors" --prior-crs EPSG:4979 \
  --report "$tmp/g84.json" >"$tmp/g84out" 2>&1
check "--prior-crs EPSG:4979 solves in a local frame" grep -q "local frame: east, north, up at latitude 47.0" "$tmp/g84out"
check "and flags the same priors with the same σ0²" json "$tmp/g84.json" \
  "d['camera_priors']['flagged'] == $(python3 -c "import json; print(json.load(open('$tmp/g.json'))['camera_priors']['flagged'])")
   and near(d['camera_priors']['sigma0_squared'], $(python3 -c "import json; print(json.load(open('$tmp/g.json'))['camera_priors']['sigma0_squared'])"), 1e-3)
   and d['camera_priors']['crs'] == 'EPSG:4979' and 'cart' in d['camera_priors']['local_frame']['proj_pipeline']"
# --output-crs: the camera centres back in WGS84, each near its prior
# (within 15 m but for the gross errors), and nowhere without a CRS.
"$dba" solve "$tmp/g.dba" -q --camera-priors "$tmp/g84.priors" --prior-crs EPSG:4979 \
  --output-crs EPSG:4979 --camera-centres "$tmp/g84.centres" --ply "$tmp/g84.ply" >/dev/null 2>&1
check "--output-crs EPSG:4979 exits 0" test $? -eq 0
check "the camera centres are in latitude, longitude, height, near their priors" \
  python3 - "$tmp/g84.centres" "$tmp/g84.priors" <<'PY'
import math, sys
c = {l.split()[0]: [float(x) for x in l.split()[1:4]] for l in open(sys.argv[1]) if not l.startswith("#")}
p = {l.split()[0]: [float(x) for x in l.split()[1:4]] for l in open(sys.argv[2])}
near = sum(1 for k in p if abs(c[k][0] - p[k][0]) * 111e3 < 15 and abs(c[k][1] - p[k][1]) * 76e3 < 15
           and abs(c[k][2] - p[k][2]) < 15)
sys.exit(0 if len(c) == 300 and near >= 0.95 * 300 else 1)
PY
"$dba" solve "$tmp/g.dba" -q --camera-priors "$tmp/g.priors" --output-crs EPSG:4979 >"$tmp/gerr" 2>&1
check "--output-crs with priors in a Cartesian frame exits 2" test $? -eq 2
check "and says why" grep -q -- "--output-crs needs --prior-crs or --gcp-crs" "$tmp/gerr"
"$dba" solve "$tmp/g.dba" -q --camera-priors "$tmp/g84.priors" --prior-crs EPSG:4326 >"$tmp/gerr" 2>&1
check "a 2D CRS exits 2" test $? -eq 2
check "and says why" grep -q -- "--prior-crs: the CRS 'EPSG:4326' has 2 axes: a 3D CRS is needed" "$tmp/gerr"
"$dba" solve "$tmp/g.dba" -q --camera-priors "$tmp/g84.priors" --prior-crs NOPE:1 >"$tmp/gerr" 2>&1
check "a CRS PROJ cannot parse is refused" grep -q -- "--prior-crs: PROJ cannot parse the CRS 'NOPE:1'" "$tmp/gerr"
# Bad priors files: file and line, nothing solved.
printf '0 1 2 3 2 4\n0 1 2 3 2 4\n' >"$tmp/dup.priors"
printf '0 1 2 3\n' >"$tmp/nosigma.priors"
printf '0 1 2 3 2 4\n# a comment\n\n400 1 2 3 2 4\n' >"$tmp/range.priors"
printf '0 1 2 3 0 4\n' >"$tmp/zero.priors"
printf '0 1 2 3 1e-300 4\n' >"$tmp/tiny.priors"
printf '0 1 x 3\n' >"$tmp/nan.priors"
for bad in "dup:2: image '0' already has a prior (line 1)" \
           "nosigma:1: no SIGMA_XY SIGMA_Z on the line and no --prior-sigma XY,Z" \
           "range:4: image '400': expected a 0-based camera index below 300" \
           "zero:1: sigma must be within [1e-06, 1e+06]" "tiny:1: sigma must be within" "nan:1: Y: 'x' is not a finite number"; do
  name=${bad%%:*}
  "$dba" solve "$tmp/g.dba" -q --camera-priors "$tmp/$name.priors" >"$tmp/gerr" 2>&1
  check "bad priors ($name) exit 1" test $? -eq 1
  check "bad priors ($name) name the file and line" grep -qF "$tmp/$name.priors:${bad#*:}" "$tmp/gerr"
done
"$dba" solve "$tmp/g.dba" -q --camera-priors "$tmp/nosigma.priors" --prior-sigma 2,4 >"$tmp/gerr" 2>&1
check "--prior-sigma gives rows their σ; one prior cannot align the block" \
  grep -q "nosigma.priors: the alignment onto the priors needs at least 3 priors, got 1" "$tmp/gerr"
head -4 "$tmp/g.priors" | awk '/^#/ { next } { print $1, $2, $3, $4 }' >"$tmp/three.priors"
"$dba" solve "$tmp/g.dba" -q --camera-priors "$tmp/three.priors" --prior-sigma 2,4 --max-iterations 2 \
  >/dev/null 2>&1
check "three priors without σ and --prior-sigma solve" test $? -eq 0

# Ground control (a small version of bench/ground_control.sh): 10 control and
# 20 check points (σ 2 cm) on the same kind of survey, with the GNSS priors.
# Control points are points of the solve with a prior; check points are
# triangulated after it and land within the reconstruction's own error of
# their truth (at most 1.6x its RMS after the best similarity; the written
# output keeps only the problem's own points).
mkdir -p "$tmp/gc"
"$dba" generate "$tmp/gc.dba" --model photo --images 300 --cameras 2 --seed 4 --unaligned \
  --priors "$tmp/gc/p.txt" --gnss-sigma 2,4 --gnss-outliers 0.02 \
  --gcps "$tmp/gc/g.txt" --control-points 10 --check-points 20 --truth "$tmp/gc.truth.dba" >/dev/null
check "generate --gcps exits 0" test $? -eq 0
check "it writes 10 control and 20 check points with their truth" test \
  "$(grep -c ' control # true' "$tmp/gc/g.txt") $(grep -c ' check # true' "$tmp/gc/g.txt")" = "10 20"
"$dba" solve "$tmp/gc.dba" -q --camera-priors "$tmp/gc/p.txt" --gcps "$tmp/gc/g.txt" \
  -o "$tmp/gc.out.dba" --report "$tmp/gc/with.json" --accuracy-report "$tmp/gc/acc.txt" >"$tmp/gcout" 2>&1
check "solve --camera-priors --gcps exits 0" test $? -eq 0
check "the report has the control and check points, none flagged" json "$tmp/gc/with.json" \
  "d['control_points']['count'] == 10 and d['check_points']['count'] == 20
   and d['control_points']['flagged'] == [] and d['control_points']['rms_3d'] < 0.05
   and d['check_points']['rms_3d'] < 0.5 and near(d['georeferencing']['sigma0_squared'], 1, 0.05)"
check "--accuracy-report: a row per prior, control and check point" test \
  "$(grep -c '^gnss ' "$tmp/gc/acc.txt") $(grep -c '^control ' "$tmp/gc/acc.txt") $(grep -c '^check ' "$tmp/gc/acc.txt")" = "300 10 20"
"$dba" solve "$tmp/gc.out.dba" -q --max-iterations 1 --report "$tmp/gc/without.json" >/dev/null 2>&1
check "the output holds the problem's points only" test \
  "$(json_value "$tmp/gc/without.json" num_points)" = "$(json_value "$tmp/gc/with.json" num_points)"
check "check points within 1.6x the reconstruction's own error of their truth" \
  python3 -c "import sys; r = float(sys.argv[1].split('|')[5]); sys.exit(0 if 0 < r <= 1.6 else 1)" \
  "$(python3 "$root/bench/check_point_ratio.py" "$tmp/gc" 300 4)"
# Control points alone place the block: aligned onto them, then held by them.
"$dba" solve "$tmp/gc.dba" -q --gcps "$tmp/gc/g.txt" --truth "$tmp/gc.truth.dba" --truth-absolute \
  --report "$tmp/gc/only.json" >"$tmp/gcout" 2>&1
check "--gcps alone aligns onto the control points" grep -q "aligned onto the control points (scale [0-9.]*, 10 inliers)" "$tmp/gcout"
check "and lands the cameras within 0.5 m of the truth, with no similarity" json "$tmp/gc/only.json" \
  "d['ground_truth']['absolute'] and d['ground_truth']['camera_centre_rms'] < 0.5"
# Bad ground control: file and line, exit 1, nothing written.
grep -v ' check ' "$tmp/gc/g.txt" | grep -v '^CHK' | sed 's/ control / check /' >"$tmp/gc/checkonly.txt"
printf 'A 1 2 3 0.02 0.02 control\nA 400 10 10\n' >"$tmp/gc/range.txt"
printf 'A 1 2 3 0.02 0.02 control\nB 4 10 10\n' >"$tmp/gc/undefined.txt"
for bad in "range:2: image '400': expected a 0-based camera index below 300" \
           "undefined:2: measurement of 'B', which no line" \
           "checkonly: no control points and no --camera-priors"; do
  name=${bad%%:*}
  "$dba" solve "$tmp/gc.dba" -q --gcps "$tmp/gc/$name.txt" -o "$tmp/gc/never.dba" >"$tmp/gerr" 2>&1
  check "bad ground control ($name) exits 1" test $? -eq 1
  check "bad ground control ($name) names the file and line" grep -qF "$tmp/gc/$name.txt${bad#"$name"}" "$tmp/gerr"
  check "bad ground control ($name) writes nothing" test ! -e "$tmp/gc/never.dba"
done
"$dba" solve "$tmp/gc.dba" -q --gcp-crs EPSG:4979 >"$tmp/gerr" 2>&1
check "--gcp-crs without --gcps exits 2" test $? -eq 2

# Mismatches: a robust loss finds them, --reject-outliers drops them, and the
# solves after that use the squared loss (final_cost is then the plain
# ½ Σ |r|² of the observations left, as the written output re-reads), or
# keep the robust loss with --reject-keep-loss.
"$dba" generate "$tmp/o.dba" --images 120 --seed 5 --outliers 0.05 --truth "$tmp/o.truth.dba" >/dev/null
reject=(--loss cauchy --loss-scale 2 --reject-outliers 4 --truth "$tmp/o.truth.dba")
"$dba" solve "$tmp/o.dba" -q "${reject[@]}" -o "$tmp/o.out.dba" --report "$tmp/o.json" >/dev/null 2>&1
check "rejection drops the mismatches and few true observations" json "$tmp/o.json" \
  'd["true_outliers"]["outliers_dropped"] >= 0.99 * d["true_outliers"]["outliers"] > 0
   and d["true_outliers"]["inliers_dropped"] < 0.005 * d["true_outliers"]["inliers"]'
check "after rejection the final cost is the squared loss's" json "$tmp/o.json" \
  'd["loss"]["type"] == "cauchy" and d["final_loss"]["type"] == "trivial"'
"$dba" solve "$tmp/o.out.dba" -q --max-iterations 0 --report "$tmp/o.reread.json" >/dev/null 2>&1
check "the output re-reads at that final cost" json "$tmp/o.reread.json" \
  "near(d['initial_cost'], $(json_value "$tmp/o.json" final_cost), 1e-9)"
"$dba" solve "$tmp/o.dba" -q "${reject[@]}" --reject-keep-loss --report "$tmp/ok.json" >/dev/null 2>&1
check "--reject-keep-loss keeps the robust loss" json "$tmp/ok.json" \
  'd["final_loss"]["type"] == "cauchy" and d["final_cost"] != '"$(json_value "$tmp/o.json" final_cost)"

"$dba" generate "$tmp/p.txt" --model photo >"$tmp/err" 2>&1; check "photo to BAL text exits 2" test $? -eq 2
check "photo to BAL text says why" grep -q "cannot hold shared intrinsics" "$tmp/err"
check "nothing written for photo text" test ! -e "$tmp/p.txt"
"$dba" generate "$tmp/q.dba" --model pinhole >"$tmp/err" 2>&1; check "unknown model exits 2" test $? -eq 2
"$dba" solve "$tmp/p.dba" -q -o "$tmp/p.out.txt" >"$tmp/err" 2>&1; check "photo solve to text exits 2 (an argument that does not fit the input)" test $? -eq 2
check "photo solve to text says why" grep -q "cannot hold shared intrinsics" "$tmp/err"
check "no text output for photo" test ! -e "$tmp/p.out.txt"

# SIGTERM or SIGHUP during a write removes the temporary (and leaves no
# output): a generation that is still writing is interrupted.
for sig in TERM HUP; do  # (a background job ignores SIGINT)
  # At the lowest priority, so that on a busy machine (ctest -j8) the
  # generator writes slowly and this loop still sees the temporary.
  nice -n 19 "$dba" generate "$tmp/interrupted.dba" --images 60000 >/dev/null 2>&1 &
  pid=$!
  # Waits while the generator lives (not a fixed time: starved at nice 19
  # beside ctest -j8 it may take a minute to start writing), at most 10 min.
  for _ in $(seq 12000); do
    compgen -G "$tmp/interrupted.dba.tmp.$pid.*" >/dev/null && break
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.05
  done
  check "a temporary exists while writing ($sig)" compgen -G "$tmp/interrupted.dba.tmp.$pid.*"
  kill -"$sig" "$pid"; wait "$pid" 2>/dev/null
  check "SIG$sig leaves no temporary" test -z "$(ls "$tmp" | grep interrupted)"
done

finish
