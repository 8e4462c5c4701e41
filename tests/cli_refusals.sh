#!/usr/bin/env bash
# Every refusal of `dba solve` as a table: the arguments, the exit status
# (2: arguments, also those that do not fit the input; 1: input or
# environment), a part of the message (naming the flag or the file), and
# that nothing is left behind or changed (no -o output, no report, no
# temporary; the input files' bytes as they were).
# Usage: cli_refusals.sh PATH_TO_DBA PROJECT_ROOT
set -uo pipefail
source "$(dirname "$0")/lib/check.sh"
dba=$1
root=$2
bal=$root/data/problem-49-7776-pre.txt.bz2
colmap=$root/../shared/data/colmap/mithunnallana_6img/sparse/0
need_shared "$colmap" "$root/../shared/data/bal"
printf '2 1 2\n0 0 1.0 2.0\n1 0 1.0 abc\n' >"$tmp/malformed.txt"
printf '2 2 4\n0 0 1.0 2.0\n1 0 1.5 2.0\n0 1 1.0 2.0\n1 1 3.0 2.0\n0 0 0 0 0 -5 500 0 0\n0.01 0 0 0 0 -5 500 0 0\n0 0 1\n1e200 0.1 0.5\n' >"$tmp/nonfinite.txt"
printf '2 2 4\n0 0 1.0 2.0\n1 0 1.5 2.0\n0 1 1.0 1e80\n1 1 3.0 2.0\n0 0 0 0 0 -5 500 0 0\n0.01 0 0 0 0 -5 500 0 0\n0 0 1\n0.1 0.1 0.5\n' >"$tmp/bigpixel.txt"
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
  local inputs=() a
  for a in "$@"; do [ -f "$a" ] && inputs+=("$a"); [ -d "$a" ] && inputs+=("$a"/*); done
  local before=""
  [ ${#inputs[@]} -gt 0 ] && before=$(cksum "${inputs[@]}" 2>/dev/null)
  "$dba" solve "$@" "${extra[@]}" --report "$report" >"$tmp/log" 2>&1
  local got=$?
  if [ ${#inputs[@]} -gt 0 ]; then
    check "[$n]: the inputs' bytes unchanged" test "$before" = "$(cksum "${inputs[@]}" 2>/dev/null)"
  fi
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
refuse 2 "--colmap-format needs -o" no-o "$bal" --colmap-format text
# Options that mean nothing without another, refused by name (the option
# table's needs).
refuse 2 "--prior-crs needs --camera-priors or --gcps" "$bal" --prior-crs EPSG:4979
refuse 2 "--lever-arm needs --camera-priors" "$tmp/photo.dba" --lever-arm 0,0,0.1
refuse 2 "--min-triangulation-angle needs --reject-outliers" "$bal" --min-triangulation-angle 3
refuse 2 "--eta needs --linear-solver pcg or auto" "$bal" --linear-solver sparse --eta 0.5
refuse 2 "--rig-geometry: the problem has no rigs" "$tmp/photo.dba" --rig-geometry fixed
refuse 2 "--rig-geometry: the problem has no rigs" "$colmap" --rig-geometry refine
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
# A byte of a middle block of a multi-block .bz2 changed (bzip2 -1).
bzcat "$bal" | bzip2 -1 >"$tmp/flipped.bz2"
printf 'X' | dd of="$tmp/flipped.bz2" bs=1 seek=$(($(stat -c %s "$tmp/flipped.bz2") / 2)) conv=notrunc 2>/dev/null
refuse 1 "corrupt bzip2 data in the block at bytes" "$tmp/flipped.bz2"
refuse 1 "observation 2 (camera 0, point 1)" "$tmp/nonfinite.txt"
refuse 1 "$tmp/bigpixel.txt:4: observation 2: pixel (1, 1e+80) is beyond 1e7 px from the origin" "$tmp/bigpixel.txt"
refuse 1 "$tmp/no_truth.txt" "$bal" --truth "$tmp/no_truth.txt"
refuse 1 "does not exist" "$bal" -o "$tmp/no_dir/out.txt"
refuse 1 "does not exist" "$bal" --ply "$tmp/no_dir/p.ply"

# Absurd values and inputs cut short (exit 1 for a file's, 2 for a flag's).
bzcat "$bal" | head -c -25 >"$tmp/cut.txt"  # inside the last number, no final newline
refuse 1 "$tmp/cut.txt:$(($(wc -l <"$tmp/cut.txt") + 1)): the file ends inside this line" "$tmp/cut.txt"
refuse 2 "-o: an empty value" no-o "$bal" -o ''
refuse 2 "--prior-crs: an empty value" "$bal" --prior-crs ''
refuse 2 "--loss-scale" "$bal" --loss cauchy --loss-scale 1e20
# Values that ended a solve with exit 0 where it started: their range named.
refuse 2 "--initial-lambda: expected a number in [1e-16, 10000], got '1e-320'" "$bal" --initial-lambda 1e-320
refuse 2 "--initial-lambda: expected a number in [1e-16, 10000], got '2147483648'" "$bal" --initial-lambda 2147483648
refuse 2 "--loss-scale: expected a number in [0.01, 10000], got '1e-6'" "$bal" --loss tukey --loss-scale 1e-6
refuse 2 "--prior-sigma" "$bal" --camera-priors "$tmp/none.txt" --prior-sigma 1e-300
# A rejection round past --reject-max-share stops the run, saying the share;
# one that leaves nothing (the guard off, a squared first solve: the robust
# one at 2e-6 px fits 374 observations) is refused, with how much it dropped.
refuse 1 "outlier rejection round 1 (|r| > 1e-06 px) would drop 31469 of 31843 observations (98.8%; with 10 points under --min-triangulation-angle), more than --reject-max-share 0.25" \
  "$bal" --reject-outliers 1e-6
refuse 1 "outlier rejection dropped every observation (31843 observations and 7776 points" \
  "$bal" --reject-outliers 1e-6 --loss trivial --reject-max-share 1
refuse 1 "outlier rejection dropped every observation" "$bal" --reject-outliers 1e6 \
  --min-triangulation-angle 179 --reject-max-share 1
refuse 2 "--reject-max-share" "$bal" --reject-outliers 3 --reject-max-share 0
# Priors in a CRS: a wrapped longitude, a blunder of a height; a PROJ string
# that is no CRS is the flag's error, PROJ's own log kept off stderr.
"$dba" generate "$tmp/geo.dba" --images 20 --priors "$tmp/geo.txt" >/dev/null
awk '!/^#/ {printf "%s %.9f %.9f %.3f 2 4\n", $1, 47 + $3 / 111000, 8 + $2 / 76000, 500 + $4}' \
  "$tmp/geo.txt" >"$tmp/wgs84.txt"
"$dba" solve "$tmp/geo.dba" --camera-priors "$tmp/wgs84.txt" --prior-crs EPSG:4979 --max-iterations 2 >"$tmp/log" 2>&1
check "the WGS84 priors themselves are taken" contains "$tmp/log" "camera priors: 20"
# A refined lever arm where every image with a prior is held: nothing in
# the solve places it (it stayed at its start, exit 0).
refuse 2 "--refine-lever-arm: every image with a camera prior is held (--fix-images)" \
  "$tmp/geo.dba" --camera-priors "$tmp/geo.txt" --refine-lever-arm --fix-images all
awk 'NR == 3 {$3 = 400} {print}' "$tmp/wgs84.txt" >"$tmp/lon400.txt"
refuse 1 "lon400.txt: image 2: (46.99998446, 400, 609.183)" "$tmp/geo.dba" --camera-priors "$tmp/lon400.txt" --prior-crs EPSG:4979
check "the wrapped longitude is named" contains "$tmp/log" "is outside the CRS's range"
awk 'NR == 3 {$4 = 1e20} {print}' "$tmp/wgs84.txt" >"$tmp/high.txt"
refuse 1 "m from the WGS84 ellipsoid, beyond the 1e7 m dba accepts" "$tmp/geo.dba" --camera-priors "$tmp/high.txt" --prior-crs EPSG:4979
refuse 2 "--prior-crs: PROJ cannot parse the CRS '+proj=foo'" "$tmp/geo.dba" --camera-priors "$tmp/wgs84.txt" --prior-crs +proj=foo
check "PROJ's own log stays off stderr" lacks "$tmp/log" "proj_create"
refuse 2 "--prior-crs: PROJ takes '+proj=geocent +ellps=WGS84' as a coordinate operation, not a CRS" \
  "$tmp/geo.dba" --camera-priors "$tmp/wgs84.txt" --prior-crs '+proj=geocent +ellps=WGS84'
refuse 2 "--output-crs: PROJ takes '+proj=geocent' as a coordinate operation" \
  "$tmp/geo.dba" --camera-priors "$tmp/wgs84.txt" --prior-crs EPSG:4979 --output-crs +proj=geocent
# COLMAP models with values no camera has, or one name for two images.
bad_model() {  # bad_model NAME AWK_PROGRAM_ON_FILE FILE: a copy of $colmap with FILE edited
  mkdir -p "$tmp/$1" && cp "$colmap"/*.txt "$tmp/$1/"
  awk "$2" "$colmap/$3" >"$tmp/$1/$3"
}
bad_model zero_width '/^1 SIMPLE_RADIAL/ {$3 = 0} {print}' cameras.txt
refuse 1 "cameras.txt:4: camera 1: image size 0 x 720 is outside 1 to 1000000 pixels a side" "$tmp/zero_width"
bad_model negative_f '/^1 SIMPLE_RADIAL/ {$5 = -700} {print}' cameras.txt
refuse 1 "camera 1: SIMPLE_RADIAL's f is -700: it must be > 0 (a focal length)" "$tmp/negative_f"
bad_model same_name '{sub(/ l-212[.]jpg/, " l-115.jpg"); print}' images.txt
refuse 1 "the name 'l-115.jpg' is also image on line 5's: image names must be unique" "$tmp/same_name"
printf '# one camera\n1 EQUIRECTANGULAR 1280 720 1280 640\n' >"$tmp/equi_cameras.txt"
bad_model equi_size 'FNR == 0 {} {print}' images.txt
cp "$tmp/equi_cameras.txt" "$tmp/equi_size/cameras.txt"
refuse 1 "EQUIRECTANGULAR's w, h are 1280, 640 but the image is 1280 x 720" "$tmp/equi_size"
# Every lens model's physical range, in any input: one case per rule.
lens_model() {  # lens_model NAME CAMERA_LINE: a copy of $colmap with camera 1 replaced
  mkdir -p "$tmp/$1" && cp "$colmap"/*.txt "$tmp/$1/"
  printf '# one camera\n%s\n' "$2" >"$tmp/$1/cameras.txt"
}
lens_model zero_fy "1 PINHOLE 1280 720 700 0 640 360"
refuse 1 "cameras.txt:2: camera 1: PINHOLE's fy is 0: it must be > 0 (a focal length)" "$tmp/zero_fy"
lens_model fov_pi "1 FOV 1280 720 700 700 640 360 3.2"
refuse 1 "camera 1: FOV's omega is 3.2000000000000002: it must be within (-pi, pi)" "$tmp/fov_pi"
lens_model eucm_alpha "1 EUCM 1280 720 700 700 640 360 1.5 1"
refuse 1 "camera 1: EUCM's alpha is 1.5: it must be within [0, 1]" "$tmp/eucm_alpha"
lens_model eucm_beta "1 EUCM 1280 720 700 700 640 360 0.5 -1"
refuse 1 "camera 1: EUCM's beta is -1: it must be > 0" "$tmp/eucm_beta"
lens_model equi_negative "1 EQUIRECTANGULAR 1280 720 -1280 720"
refuse 1 "camera 1: EQUIRECTANGULAR's w is -1280: it must be >= 1" "$tmp/equi_negative"
# dba convert reads through the same check (a .dba's groups are checked by
# its reader: io/binary_problem_test.cc; Python's arrays: test_arrays.py).
"$dba" convert "$tmp/eucm_beta" "$tmp/eucm_beta.dba" >"$tmp/log" 2>&1
check "dba convert refuses it too" test $? -eq 1
check "and writes nothing" test ! -e "$tmp/eucm_beta.dba"
# --fix-intrinsics and --fix-images name COLMAP ids: an unknown one is the
# flag's error (2), a name not in that camera's model too, naming the camera.
refuse 2 "--fix-intrinsics: camera 7: $colmap has no camera with that id" "$colmap" --fix-intrinsics 7:f
refuse 2 "no intrinsic parameter 'f:cx' in COLMAP camera 1's model SIMPLE_RADIAL" "$colmap" --fix-intrinsics 1:f:cx
refuse 2 "--fix-images: image 99: $colmap has no image with that id" "$colmap" --fix-images 99
finish
