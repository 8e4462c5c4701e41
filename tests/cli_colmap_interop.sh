#!/usr/bin/env bash
# Against the real COLMAP (Debian's colmap 3.8, installed by the README's
# test command): `colmap bundle_adjuster` and `dba colmap-bundle-adjuster`
# with the same flags reach the same final cost (1e-6 relative, both
# outputs evaluated by one reader), and dba's outputs load in `colmap
# model_analyzer` with the input's counts, written binary from a text model
# as COLMAP 3.8 writes them; a rerun into the directory COLMAP wrote
# replaces COLMAP's model. Without colmap the test fails and says why.
# Usage: cli_colmap_interop.sh PATH_TO_DBA PROJECT_ROOT
set -uo pipefail
source "$(dirname "$0")/lib/check.sh"
dba=$1
root=$2
colmap_data=$root/../shared/data/colmap
need_shared "$colmap_data"
need_colmap

# cost MODEL: the cost of a model as it is (dba solve, no iteration).
cost() {
  "$dba" solve "$1" -q --max-iterations 0 --report "$tmp/cost.json" >/dev/null 2>&1 &&
    json_value "$tmp/cost.json" initial_cost
}
# counts MODEL: model_analyzer's cameras, images, registered images, points, observations.
counts() {
  colmap model_analyzer --path "$1" 2>&1 | grep -E "^(Cameras|Images|Registered images|Points|Observations):" |
    sed 's/ *$//'
}

run=0
for m in mithunnallana_6img statue_of_liberty_small_txt; do
  model=$colmap_data/$m/sparse/0
  flagsets=("" "--BundleAdjustment.refine_principal_point 1 --BundleAdjustment.refine_extra_params 0")
  [ "$m" = mithunnallana_6img ] || flagsets=("")
  for flags in "${flagsets[@]}"; do
    run=$((run + 1))
    mkdir -p "$tmp/c$run" "$tmp/d$run"
    # shellcheck disable=SC2086
    colmap bundle_adjuster --input_path "$model" --output_path "$tmp/c$run" $flags >"$tmp/c$run.log" 2>&1
    check "$m ${flags:-defaults}: colmap bundle_adjuster exits 0" test $? -eq 0
    # shellcheck disable=SC2086
    "$dba" colmap-bundle-adjuster --input_path "$model" --output_path "$tmp/d$run" $flags >"$tmp/d$run.log" 2>&1
    check "$m ${flags:-defaults}: dba colmap-bundle-adjuster exits 0" test $? -eq 0
    c=$(cost "$tmp/c$run"); d=$(cost "$tmp/d$run")
    check "$m ${flags:-defaults}: the same final cost as COLMAP ($d vs $c)" \
      python3 -c "import sys; c, d = float(sys.argv[1]), float(sys.argv[2]); sys.exit(abs(d - c) > 1e-6 * c)" "${c:-nan}" "${d:-nan}"
    check "$m ${flags:-defaults}: dba's output loads in colmap model_analyzer with the input's counts" \
      test "$(counts "$tmp/d$run")" = "$(counts "$model")" -a -n "$(counts "$model")"
    check "$m ${flags:-defaults}: written binary, as COLMAP 3.8 writes it from a text model too" \
      test "$(cd "$tmp/d$run" && echo *)" = "$(cd "$tmp/c$run" && echo *)" -a "$(cd "$tmp/d$run" && echo *)" = \
      "cameras.bin images.bin points3D.bin"
  done
  # Rerun into the directory COLMAP wrote: its model is replaced, and
  # COLMAP reads dba's.
  cp -r "$tmp/c$run" "$tmp/c$run.colmap"
  "$dba" colmap-bundle-adjuster --input_path "$model" --output_path "$tmp/c$run" >"$tmp/rerun.log" 2>&1
  check "$m: a rerun into the directory colmap bundle_adjuster wrote exits 0" test $? -eq 0
  check "$m: ... and replaces COLMAP's model" \
    test "$(cmp -s "$tmp/c$run/images.bin" "$tmp/c$run.colmap/images.bin"; echo $?)" = 1
  mkdir -p "$tmp/c$run.txt"
  colmap model_converter --input_path "$tmp/c$run" --output_path "$tmp/c$run.txt" --output_type TXT >"$tmp/conv.log" 2>&1
  check "$m: ... which colmap model_converter reads" test $? -eq 0 -a -s "$tmp/c$run.txt/images.txt"
done

# FOV from small ω (COLMAP switches formula at ω = 0.01, dba copies its
# values, and inside the series ω = 0 is a false minimum: a free ω starts at
# ±0.01, docs/camera_models.md). statue_of_liberty_small_txt's strong
# barrel (optimum ω = ±1.29) stalled dba at 2.82e5 from ω = 0.001 before;
# COLMAP reaches 8107.3 from all three starts.
fov_camera() {  # fov_camera MODEL OMEGA: the model's camera as a FOV one
  case $1 in
    mithunnallana_6img) echo "1 FOV 1280 720 700.241 700.241 640 360 $2" ;;
    statue_of_liberty_small_txt) echo "1 FOV 800 1200 2395.65 2395.65 400 600 $2" ;;
  esac
}
for m in mithunnallana_6img statue_of_liberty_small_txt; do
  for omega in 0.001 0.01 0.1; do
    f=$tmp/fov_${m}_$omega
    mkdir -p "$f.in" "$f.c" "$f.d"
    cp "$colmap_data/$m/sparse/0/"{images,points3D}.txt "$f.in/"
    fov_camera "$m" "$omega" >"$f.in/cameras.txt"
    colmap bundle_adjuster --input_path "$f.in" --output_path "$f.c" >"$f.c.log" 2>&1
    "$dba" colmap-bundle-adjuster --input_path "$f.in" --output_path "$f.d" >"$f.d.log" 2>&1
    c=$(cost "$f.c"); d=$(cost "$f.d")
    check "$m, FOV from omega $omega: COLMAP's final cost ($d vs $c)" \
      python3 -c "import sys; c, d = float(sys.argv[1]), float(sys.argv[2]); sys.exit(abs(d - c) > 1e-6 * c)" "${c:-nan}" "${d:-nan}"
  done
done
check "the log says where omega started" contains "$tmp/fov_statue_of_liberty_small_txt_0.001.d.log" \
  "FOV group 0: omega 0.001 starts at 0.01"

# A lens model COLMAP 3.8 cannot read: written with a warning (and COLMAP
# 3.8 indeed refuses the model), refused before the solve with
# --colmap-version 3.8.
mkdir -p "$tmp/radtan"
cp "$colmap_data/mithunnallana_6img/sparse/0/"{images,points3D}.txt "$tmp/radtan/"
echo "1 RAD_TAN_THIN_PRISM_FISHEYE 1280 720 700.241 700.241 640 360 0 0 0 0 0 0 0 0 0 0 0 0" >"$tmp/radtan/cameras.txt"
"$dba" solve "$tmp/radtan" -q --max-iterations 2 -o "$tmp/radtan_out" >"$tmp/out" 2>&1
check "a model COLMAP 3.8 cannot read is written" test $? -eq 0 -a -s "$tmp/radtan_out/cameras.txt"
check "... with a warning naming the lens model" contains "$tmp/out" "is RAD_TAN_THIN_PRISM_FISHEYE, which COLMAP 3.8 (Debian 12's) cannot read"
check "... which COLMAP 3.8 indeed cannot read" test -z "$(counts "$tmp/radtan_out")"
"$dba" solve "$tmp/radtan" -q -o "$tmp/radtan_38" --colmap-version 3.8 >"$tmp/out" 2>&1
check "--colmap-version 3.8 refuses it (exit 2)" test $? -eq 2
check "... naming why" contains "$tmp/out" "(--colmap-version 3.8)"
check "... and writes nothing" test ! -e "$tmp/radtan_38"

# Options COLMAP has and dba cannot honour are refused by name; a missing
# path is named.
"$dba" colmap-bundle-adjuster --input_path "$colmap_data/mithunnallana_6img/sparse/0" --output_path "$tmp/x" \
  --BundleAdjustment.refine_points 0 >"$tmp/out" 2>&1
check "an unknown option exits 2" test $? -eq 2
check "an unknown option is named" contains "$tmp/out" "--BundleAdjustment.refine_points"
"$dba" colmap-bundle-adjuster --output_path "$tmp/x" >"$tmp/out" 2>&1
check "a missing --input_path exits 2 and is named" contains "$tmp/out" "--input_path is required"
"$dba" colmap-bundle-adjuster --input_path "$colmap_data/mithunnallana_6img/sparse/0" --output_path "$tmp/x" \
  --BundleAdjustment.refine_extrinsics maybe >"$tmp/out" 2>&1
check "a bad boolean exits 2 and is named" contains "$tmp/out" "'maybe' is not a boolean"
finish
