#!/usr/bin/env bash
# Rigs end to end (docs/design.md §1.7): dba generate --rig writes
# a .dba version 4 whose solve recovers the sensors' turns; --rig-geometry
# fixed holds them; the written problem re-reads at the final cost; the same survey renumbered at random solves to the same cost;
# --drop-rigs gives the same images as independent cameras; GNSS priors on
# the frames recover the antenna's lever arm; --fix-images holds an image's
# pose (its frame and its sensor); what rigs do not reach yet, and what
# generate cannot honour with a rig, is refused by name. Usage: cli_rigs.sh PATH_TO_DBA PROJECT_ROOT
set -uo pipefail
source "$(dirname "$0")/lib/check.sh"
dba=$1
# The starting sensor's turn from the truth, in full precision.
start_turn() {
  python3 -c 'import json,sys; print(repr(json.load(open(sys.argv[1]))["ground_truth"]["sensors"]["rotation_error_deg"][0]))' "$tmp/start.json"
}

"$dba" generate --model photo --rig stereo --images 160 --seed 4 "$tmp/rig.dba" \
  --truth "$tmp/truth.dba" > "$tmp/gen.txt" 2>&1
check "generate says the frames and the rig" contains "$tmp/gen.txt" "80 frames of a stereo rig"
check "the file is version 4" /usr/bin/python3 -c "
import struct, sys
sys.exit(0 if struct.unpack_from('<I', open('$tmp/rig.dba', 'rb').read(12), 8)[0] == 4 else 1)"

"$dba" solve "$tmp/rig.dba" -q --truth "$tmp/truth.dba" --report "$tmp/refine.json" > /dev/null 2>&1
# (its place, 60 cm from the origin, is known to a few cm from 80 frames:
# the 2,000-frame figures are in bench/README.md)
check "refined: the sensor turned within 0.01 deg of the truth" json "$tmp/refine.json" \
  "d['ground_truth']['sensors']['rotation_error_deg'][0] < 0.01 and d['ground_truth']['sensors']['position_error'][0] < 0.1"
check "refined: 6 unknowns per frame, 6 for the sensor" json "$tmp/refine.json" \
  "d['camera_unknowns'] == 80 * 6 + 2 * 3 + 6"
"$dba" solve "$tmp/rig.dba" -q --truth "$tmp/truth.dba" --max-iterations 0 \
  --report "$tmp/start.json" > /dev/null 2>&1
"$dba" solve "$tmp/rig.dba" -q --truth "$tmp/truth.dba" --rig-geometry fixed \
  --report "$tmp/fixed.json" > /dev/null 2>&1
check "fixed: the sensor turned exactly as it started" json "$tmp/fixed.json" \
  "d['ground_truth']['sensors']['rotation_error_deg'][0] == $(start_turn)"
check "fixed: 6 unknowns per frame only" json "$tmp/fixed.json" "d['camera_unknowns'] == 80 * 6 + 2 * 3"
check "the refined sensor started off by more than it ends" json "$tmp/start.json" \
  "d['ground_truth']['sensors']['rotation_error_deg'][0] > 0.05"
# By sensor: group 1 (the stereo's second camera) held is the whole rig held;
# group 0, the rig's origin, is held anyway.
"$dba" solve "$tmp/rig.dba" -q --rig-geometry fixed:1 --report "$tmp/fixed1.json" > /dev/null 2>&1
check "fixed:1 is fixed here: the same unknowns and cost" json "$tmp/fixed1.json" \
  "d['camera_unknowns'] == 80 * 6 + 2 * 3 and d['final_cost'] == $(json_value "$tmp/fixed.json" final_cost)"
"$dba" solve "$tmp/rig.dba" -q --rig-geometry fixed:0 --report "$tmp/fixed0.json" > /dev/null 2>&1
check "fixed:0 (the origin) is refine" json "$tmp/fixed0.json" \
  "d['camera_unknowns'] == 80 * 6 + 2 * 3 + 6 and d['final_cost'] == $(json_value "$tmp/refine.json" final_cost)"
"$dba" solve "$tmp/rig.dba" -q --rig-geometry fixed:2 > "$tmp/refused.txt" 2>&1
check "fixed: a group that is not there is refused" contains "$tmp/refused.txt" \
  "--rig-geometry fixed:2: intrinsic group 2 does not exist (the problem has 2, 0-based)"
"$dba" solve "$tmp/rig.dba" -q --rig-geometry held > "$tmp/refused.txt" 2>&1
check "a value that is not refine, fixed or fixed:IDS is refused" contains "$tmp/refused.txt" \
  "--rig-geometry: 'held' is not refine, fixed or fixed:ID,ID..."

# --fix-images holds an image's pose: image 1 (the stereo's second camera in
# frame 0) holds frame 0 and sensor 1, in every frame; written back, its
# pose is the input's (1e-12) where the other images moved.
"$dba" solve "$tmp/rig.dba" -q --fix-images 1 --max-iterations 5 -o "$tmp/held.dba" --report "$tmp/held.json" > /dev/null 2>&1
check "--fix-images 1: frame 0 and sensor 1 held" json "$tmp/held.json" \
  "d['camera_unknowns'] == 79 * 6 + 2 * 3"
check "... image 1 at its input pose (1e-12), image 3 moved" env PYTHONPATH="$(dirname "$dba")/python" \
  /usr/bin/python3 -c "
import sys
import numpy as np
import dba
a, b = dba.read_problem('$tmp/rig.dba').cameras, dba.read_problem('$tmp/held.dba').cameras
held, moved = np.abs(a[1] - b[1]).max(), np.abs(a[3] - b[3]).max()
print(f'image 1 off by {held:.3g}, image 3 moved by {moved:.3g}', file=sys.stderr)
sys.exit(0 if held <= 1e-12 and moved > 1e-6 else 1)"

"$dba" solve "$tmp/rig.dba" -q --max-iterations 0 -o "$tmp/same.dba" > /dev/null 2>&1
"$dba" solve "$tmp/same.dba" -q --max-iterations 0 --report "$tmp/same.json" > /dev/null 2>&1
check "no iteration: the rewritten rig problem starts at the same cost, with the same unknowns" \
  json "$tmp/same.json" "d['initial_cost'] == $(json_value "$tmp/start.json" initial_cost) and d['camera_unknowns'] == 80 * 6 + 2 * 3 + 6"
"$dba" solve "$tmp/rig.dba" -q -o "$tmp/out.dba" --report "$tmp/out.json" > /dev/null 2>&1
"$dba" solve "$tmp/out.dba" -q --max-iterations 0 --report "$tmp/re.json" > /dev/null 2>&1
check "the written rig problem re-reads at the final cost" json "$tmp/re.json" \
  "near(d['initial_cost'], $(json_value "$tmp/out.json" final_cost), 1e-9)"

"$dba" convert "$tmp/rig.dba" "$tmp/shuffled.dba" --shuffle 5 > /dev/null 2>&1
"$dba" solve "$tmp/shuffled.dba" -q --report "$tmp/shuffled.json" > /dev/null 2>&1
check "renumbered at random: the same cost (1e-5)" json "$tmp/shuffled.json" \
  "near(d['final_cost'], $(json_value "$tmp/refine.json" final_cost), 1e-5)"

"$dba" convert "$tmp/rig.dba" "$tmp/independent.dba" --drop-rigs > /dev/null 2>&1
"$dba" solve "$tmp/independent.dba" -q --max-iterations 0 --report "$tmp/ind0.json" > /dev/null 2>&1
check "--drop-rigs keeps the images' poses: the same initial cost" json "$tmp/ind0.json" \
  "near(d['initial_cost'], $(json_value "$tmp/start.json" initial_cost), 1e-12)"
check "--drop-rigs: 6 unknowns per image" json "$tmp/ind0.json" "d['camera_unknowns'] == 160 * 6 + 2 * 3"

# A ring of six cameras with 3% mismatches: a robust loss, then rejection,
# drops every mismatch and few inliers, and the sensors still come out.
"$dba" generate --model photo --rig ring6 --images 300 --seed 6 --outliers 0.03 "$tmp/ring.dba" \
  --truth "$tmp/ring_truth.dba" > /dev/null 2>&1
"$dba" solve "$tmp/ring.dba" -q --loss cauchy --reject-outliers 3 --truth "$tmp/ring_truth.dba" \
  --report "$tmp/ring.json" > /dev/null 2>&1
check "ring6, cauchy then rejection: every mismatch dropped, under 2% of the inliers" json "$tmp/ring.json" \
  "d['true_outliers']['outliers_dropped'] == d['true_outliers']['outliers'] > 700 and d['true_outliers']['inliers_dropped'] < 0.02 * d['true_outliers']['inliers']"
check "... the sensors within 0.05 deg" json "$tmp/ring.json" \
  "max(d['ground_truth']['sensors']['rotation_error_deg']) < 0.05"

# GNSS on the rig: the antenna 0.25, -0.15, -0.40 m from the
# rig's origin, one prior per frame (sigma 2 cm), 5 control and 3 check
# points; 500 frames of the oblique head (the frames' ~3 deg attitude
# differences place the lever arm's horizontal part, the control points its
# vertical part).
"$dba" generate --model photo --rig oblique5 --images 2500 --seed 5 "$tmp/gnss.dba" \
  --truth "$tmp/gnss_truth.dba" --priors "$tmp/gnss.txt" --gnss-sigma 0.02,0.02 \
  --lever-arm 0.25,-0.15,-0.4 --gcps "$tmp/gcps.txt" --control-points 5 --check-points 3 \
  > /dev/null 2>&1
check "one prior per frame" test "$(grep -vc '^#' "$tmp/gnss.txt")" -eq 500
"$dba" solve "$tmp/gnss.dba" -q --camera-priors "$tmp/gnss.txt" --gcps "$tmp/gcps.txt" \
  --refine-lever-arm --report "$tmp/lever.json" > "$tmp/lever.txt" 2>&1
check "refined from 0: the lever arm within 1 cm of the truth" json "$tmp/lever.json" \
  "all(abs(a - b) < 0.01 for a, b in zip(d['camera_priors']['lever_arm'], [0.25, -0.15, -0.4])) and d['camera_priors']['lever_arm_refined']"
check "the antennas end on the priors (RMS within 1.5 sigma)" json "$tmp/lever.json" \
  "max(d['camera_priors']['rms']) < 0.03 and d['check_points']['rms_3d'] < 0.1"
check "3 unknowns more than the frames' and sensors'" json "$tmp/lever.json" \
  "d['camera_unknowns'] == 500 * 6 + 5 * 3 + 4 * 6 + 3"
"$dba" solve "$tmp/gnss.dba" -q --camera-priors "$tmp/gnss.txt" --gcps "$tmp/gcps.txt" \
  --lever-arm 0.25,-0.15,-0.4 --report "$tmp/given.json" > /dev/null 2>&1
"$dba" solve "$tmp/gnss.dba" -q --camera-priors "$tmp/gnss.txt" --gcps "$tmp/gcps.txt" \
  --report "$tmp/none.json" > /dev/null 2>&1
check "given: held as given, the antennas on the priors" json "$tmp/given.json" \
  "d['camera_priors']['lever_arm'] == [0.25, -0.15, -0.4] and not d['camera_priors']['lever_arm_refined'] and max(d['camera_priors']['rms']) < 0.03"
check "no lever arm: the block shifts by it, the control points 10 cm off" json "$tmp/none.json" \
  "d['control_points']['rms_3d'] > 0.1 and $(json_value "$tmp/lever.json" control_points)['rms_3d'] < 0.03"
check "refined ends as low as given (3 more unknowns)" json "$tmp/lever.json" \
  "d['final_cost'] <= $(json_value "$tmp/given.json" final_cost) * (1 + 1e-6)"
# The same survey renumbered at random (its points walked again): the priors
# and measurements follow their images (matched by pose), and the solve ends
# on the same cost and lever arm (1e-5, the agreement rule).
"$dba" convert "$tmp/gnss.dba" "$tmp/gnss_s.dba" --shuffle 3 > /dev/null 2>&1
PYTHONPATH="$(dirname "$dba")/python" /usr/bin/python3 - "$tmp" <<'PY'
import sys
import numpy as np
import dba
d = sys.argv[1]
a, b = dba.read_problem(f"{d}/gnss.dba"), dba.read_problem(f"{d}/gnss_s.dba")
new = {a_i: b_i for b_i, a_i in enumerate(
    {tuple(c): i for i, c in enumerate(a.cameras)}[tuple(c)] for c in b.cameras)}
with open(f"{d}/gnss_s.txt", "w") as f:
    for l in open(f"{d}/gnss.txt"):
        t = l.split()
        f.write(l if l.startswith("#") else " ".join([str(new[int(t[0])])] + t[1:]) + "\n")
with open(f"{d}/gcps_s.txt", "w") as f:
    for l in open(f"{d}/gcps.txt"):
        t = l.split()
        f.write(f"{t[0]} {new[int(t[1])]} {t[2]} {t[3]}\n" if len(t) == 4 and not l.startswith("#") else l)
PY
"$dba" solve "$tmp/gnss_s.dba" -q --camera-priors "$tmp/gnss_s.txt" --gcps "$tmp/gcps_s.txt" \
  --refine-lever-arm --report "$tmp/lever_s.json" > /dev/null 2>&1
check "renumbered at random: the same cost and lever arm (1e-5)" json "$tmp/lever_s.json" \
  "near(d['final_cost'], $(json_value "$tmp/lever.json" final_cost), 1e-5) and all(abs(x - y) < 1e-5 for x, y in zip(d['camera_priors']['lever_arm'], $(json_value "$tmp/lever.json" camera_priors)['lever_arm']))"

# Hostile: two priors on one frame, a lever arm without priors, a malformed
# one.
{ grep -v '^#' "$tmp/gnss.txt" | head -2; echo "1 1 2 3 0.02 0.02"; } > "$tmp/twice.txt"
"$dba" solve "$tmp/gnss.dba" -q --camera-priors "$tmp/twice.txt" > "$tmp/refused.txt" 2>&1
check "two priors on one frame are refused by name" contains "$tmp/refused.txt" \
  "$tmp/twice.txt: images 0 and 1 are one frame (one exposure of a rig)"
"$dba" solve "$tmp/gnss.dba" -q --refine-lever-arm > "$tmp/refused.txt" 2>&1
check "a lever arm without priors is refused" contains "$tmp/refused.txt" \
  "--refine-lever-arm needs --camera-priors"
# Every exposure with a prior held: nothing places a refined lever arm (it
# stayed at its start with exit 0).
"$dba" solve "$tmp/gnss.dba" -q --camera-priors "$tmp/gnss.txt" --refine-lever-arm --fix-images all \
  > "$tmp/refused.txt" 2>&1
check "a refined lever arm with every exposure held exits 2" test $? -eq 2
check "a refined lever arm with every exposure held is refused by name" contains "$tmp/refused.txt" \
  "--refine-lever-arm: every image with a camera prior is held (--fix-images)"
"$dba" solve "$tmp/gnss.dba" -q --camera-priors "$tmp/gnss.txt" --lever-arm 1,2 > "$tmp/refused.txt" 2>&1
check "a lever arm of two numbers is refused" contains "$tmp/refused.txt" "--lever-arm: '1,2' is not X,Y,Z"
"$dba" generate --rig oblique5 --images 50 "$tmp/bal.txt" > "$tmp/refused2.txt" 2>&1
check "a rig needs the photo model" contains "$tmp/refused2.txt" "--rig needs --model photo"
# What generate cannot honour with a rig is refused (exit 2), not rounded or
# dropped: images that are not whole frames (ring6: 7 would be 12), fewer
# than two frames, --cameras (a rig's sensors are its cameras). The default
# count (no --images) is whole frames: the largest multiple up to 1000.
generate_refused() {  # generate_refused SAYS ARGS...
  local says=$1; shift
  "$dba" generate --model photo "$@" "$tmp/refused.dba" > "$tmp/refused4.txt" 2>&1
  local status=$?
  check "generate $*: exit 2 (got $status)" test "$status" -eq 2
  check "generate $*: says '$says'" contains "$tmp/refused4.txt" "$says"
  check "generate $*: nothing written" test ! -e "$tmp/refused.dba"
}
generate_refused "--images 7: every frame of a ring6 rig holds its 6 sensors' images, and a survey two frames or more: give a multiple of 6 from 12 (e.g. 12)" \
  --rig ring6 --images 7
generate_refused "--images 1000: every frame of a ring6 rig holds its 6 sensors' images, and a survey two frames or more: give a multiple of 6 from 12 (e.g. 996 or 1002)" \
  --rig ring6 --images 1000
"$dba" generate --model photo --rig ring6 --features 20 "$tmp/ring_default.dba" >/dev/null 2>&1
check "ring6 without --images: 996 images, 166 frames" \
  sh -c "'$dba' info '$tmp/ring_default.dba' | grep -qE 'images +996'"
generate_refused "give a multiple of 2 from 4 (e.g. 4)" --rig stereo --images 2
generate_refused "--cameras: not with --rig (the stereo rig's 2 sensors are its cameras)" \
  --rig stereo --images 40 --cameras 3
generate_refused "--cameras: not with --rig (the oblique5 rig's 5 sensors are its cameras)" \
  --rig oblique5 --images 40 --cameras 1
"$dba" convert "$tmp/rig.dba" "$tmp/rig.txt" > "$tmp/refused3.txt" 2>&1
check "BAL cannot hold a rig" contains "$tmp/refused3.txt" "converts to .dba only"
finish
