#!/usr/bin/env bash
# COLMAP >= 3.12 models with real rigs (docs/design.md §1.7): a
# generated stereo survey written as a COLMAP text model with a rig of two
# cameras (tests/lib/rig_to_colmap.py) solves as a rig problem (6 unknowns
# per frame and 6 for the sensor) to the .dba's final cost; text -> binary
# -> text round-trips byte for byte; a solve of no iteration keeps ids,
# names, structure and tracks exactly and the poses to 1e-15, the images'
# poses those composed from the frames; a sensor without a pose starts at
# image o frame^-1 and reaches the same optimum; --rig-geometry fixed keeps
# the sensor's pose, as COLMAP's refine_sensor_from_rig 0 does through dba
# colmap-bundle-adjuster; an IMU is kept (and said so), or as the rig's
# reference stands at camera 1's place; per-image intrinsics with rigs are
# refused; --fix-images holds an image's pose (its frame and its sensor);
# hostile rigs and frames files (zero or huge quaternions, text or binary,
# lines over 64 MiB, a number cut at the end, a frame with two images of
# one camera) are refused naming file and line (or byte).
# Usage: cli_colmap_rig_models.sh PATH_TO_DBA PROJECT_ROOT
set -uo pipefail
source "$(dirname "$0")/lib/check.sh"
dba=$1
root=$2
to_colmap() { PYTHONPATH="$(dirname "$dba")/python" /usr/bin/python3 "$root/tests/lib/rig_to_colmap.py" "$@"; }

"$dba" generate --model photo --rig stereo --images 160 --seed 4 "$tmp/rig.dba" > /dev/null 2>&1
to_colmap "$tmp/rig.dba" 2 "$tmp/m"
check "the model is written" test -s "$tmp/m/rigs.txt" -a -s "$tmp/m/frames.txt"
to_colmap "$tmp/rig.dba" 2 "$tmp/nopose" --no-pose

"$dba" solve "$tmp/rig.dba" -q --report "$tmp/dba.json" > /dev/null 2>&1
"$dba" solve "$tmp/m" -q -o "$tmp/out" --report "$tmp/colmap.json" > "$tmp/log" 2>&1
check "a COLMAP rig solves" test $? -eq 0
check "... as a rig: 6 unknowns per frame, 6 for the sensor" json "$tmp/colmap.json" \
  "d['camera_unknowns'] == 80 * 6 + 6 + 2 * 3"
check "... to the .dba's final cost (1e-5)" json "$tmp/colmap.json" \
  "near(d['final_cost'], $(json_value "$tmp/dba.json" final_cost), 1e-5)"

# The written model: images at the composed poses, frames and the sensor as solved.
check "the written images are their frames composed with the sensor" /usr/bin/python3 - "$tmp/out" <<'PY'
import sys
import numpy as np
d = sys.argv[1]
def R(q):
    w, x, y, z = np.array(q) / np.linalg.norm(q)
    return np.array([[1 - 2*(y*y + z*z), 2*(x*y - w*z), 2*(x*z + w*y)],
                     [2*(x*y + w*z), 1 - 2*(x*x + z*z), 2*(y*z - w*x)],
                     [2*(x*z - w*y), 2*(y*z + w*x), 1 - 2*(x*x + y*y)]])
lines = [l.split() for l in open(f"{d}/images.txt") if not l.startswith("#")]
images = {int(v[0]): (R([float(x) for x in v[1:5]]), np.array([float(x) for x in v[5:8]])) for v in lines[0::2]}
rig = open(f"{d}/rigs.txt").read().split("\n")
rig = [l.split() for l in rig if l and not l.startswith("#")][0]
Rs, ts = R([float(x) for x in rig[7:11]]), np.array([float(x) for x in rig[11:14]])
worst = 0.0
for l in open(f"{d}/frames.txt"):
    if l.startswith("#") or not l.strip(): continue
    v = l.split()
    Rf, tf = R([float(x) for x in v[2:6]]), np.array([float(x) for x in v[6:9]])
    for k in range(int(v[9])):
        cam, image = int(v[11 + 3 * k]), int(v[12 + 3 * k])
        Ri, ti = images[image]
        Rc, tc = (Rf, tf) if cam == 1 else (Rs @ Rf, Rs @ tf + ts)
        worst = max(worst, np.abs(Ri - Rc).max(), np.abs(ti - tc).max() / (1 + np.abs(tc).max()))
if worst > 1e-12: print(f"composed poses off by {worst:.3g}", file=sys.stderr)
sys.exit(0 if worst <= 1e-12 else 1)
PY

"$dba" convert "$tmp/out" "$tmp/bin" --colmap-format binary > /dev/null 2>&1
"$dba" convert "$tmp/bin" "$tmp/back" --colmap-format text > /dev/null 2>&1
for f in cameras images points3D rigs frames; do
  check "text -> binary -> text: $f.txt byte for byte" cmp -s "$tmp/out/$f.txt" "$tmp/back/$f.txt"
done

"$dba" solve "$tmp/out" -q --max-iterations 0 -o "$tmp/zero" > /dev/null 2>&1
check "no iteration: ids, names, structure and tracks exact, poses to 1e-15" /usr/bin/python3 - "$tmp/out" "$tmp/zero" <<'PY'
import sys
def rows(d, name):
    return [l.split() for l in open(f"{d}/{name}") if l.strip() and not l.startswith("#")]
a, b = sys.argv[1], sys.argv[2]
def close(x, y):
    return all(abs(float(p) - float(q)) <= 1e-15 * max(1.0, abs(float(p))) for p, q in zip(x, y))
ok = True
for name, numeric in (("images.txt", range(1, 8)), ("frames.txt", range(2, 9)), ("rigs.txt", range(7, 14))):
    ra, rb = rows(a, name), rows(b, name)
    if name == "images.txt":  # the pose lines only; the 2D points exact
        ok &= ra[1::2] == rb[1::2]
        ra, rb = ra[0::2], rb[0::2]
    for x, y in zip(ra, rb):
        keep = [i for i in range(len(x)) if i not in numeric]
        ok &= len(x) == len(y) and [x[i] for i in keep] == [y[i] for i in keep]
        ok &= close([x[i] for i in numeric], [y[i] for i in numeric])
    ok &= len(ra) == len(rb)
pa, pb = rows(a, "points3D.txt"), rows(b, "points3D.txt")
ok &= [p[:1] + p[8:] for p in pa] == [p[:1] + p[8:] for p in pb]
sys.exit(0 if ok else 1)
PY

"$dba" solve "$tmp/nopose" -q -o "$tmp/nopose_out" --report "$tmp/nopose.json" > /dev/null 2>&1
check "a sensor without a pose starts at image o frame^-1: the same start" json "$tmp/nopose.json" \
  "near(d['initial_cost'], $(json_value "$tmp/colmap.json" initial_cost), 1e-9)"
check "... and the same optimum (1e-5)" json "$tmp/nopose.json" \
  "near(d['final_cost'], $(json_value "$tmp/colmap.json" final_cost), 1e-5)"
check "... written with its pose" /usr/bin/python3 -c "
import sys
v = [l.split() for l in open('$tmp/nopose_out/rigs.txt') if l.strip() and not l.startswith('#')][0]
sys.exit(0 if v[6] == '1' and len(v) == 14 else 1)"

"$dba" solve "$tmp/m" -q -o "$tmp/fixed" --rig-geometry fixed --report "$tmp/fixed.json" > /dev/null 2>&1
check "--rig-geometry fixed: 6 unknowns per frame only" json "$tmp/fixed.json" "d['camera_unknowns'] == 80 * 6 + 2 * 3"
check "... the sensor's pose as it was (its turn and its place: the scale is the rig's)" /usr/bin/python3 -c "
import sys
a, b = ([float(x) for x in [l.split() for l in open(p) if l.strip() and not l.startswith('#')][0][7:]]
        for p in ('$tmp/m/rigs.txt', '$tmp/fixed/rigs.txt'))
sys.exit(0 if a == b else 1)"

"$dba" colmap-bundle-adjuster --input_path "$tmp/m" --output_path "$tmp/ba" \
  --BundleAdjustment.refine_sensor_from_rig 0 --BundleAdjustment.max_num_iterations 5 > "$tmp/ba.log" 2>&1
"$dba" convert "$tmp/ba" "$tmp/ba_text" --colmap-format text > /dev/null 2>&1  # written binary, as COLMAP does
check "colmap-bundle-adjuster: refine_sensor_from_rig 0 holds the sensor" /usr/bin/python3 -c "
import sys
a, b = ([float(x) for x in [l.split() for l in open(p) if l.strip() and not l.startswith('#')][0][7:]]
        for p in ('$tmp/m/rigs.txt', '$tmp/ba_text/rigs.txt'))
sys.exit(0 if a == b else 1)"

# An IMU on the rig and in the first frame: kept in the model, not modelled.
cp -r "$tmp/m" "$tmp/imu"
sed -i '/^[^#]/ s/^1 2 \(.*\)$/1 3 \1 IMU 7 0/' "$tmp/imu/rigs.txt"
awk '!/^#/ && !done {$10 = $10 + 1; $0 = $0 " IMU 7 99"; done = 1} {print}' "$tmp/m/frames.txt" > "$tmp/imu/frames.txt"
"$dba" solve "$tmp/imu" -q -o "$tmp/imu_out" --report "$tmp/imu.json" > "$tmp/log" 2>&1
check "an IMU sensor and its data are read" test $? -eq 0
check "... and not modelled: the same optimum" json "$tmp/imu.json" \
  "near(d['final_cost'], $(json_value "$tmp/colmap.json" final_cost), 1e-9)"
check "... and written back" contains "$tmp/imu_out/frames.txt" " IMU 7 99"
check "... on its rig" contains "$tmp/imu_out/rigs.txt" " IMU 7 0"
check "... and the count in the report" json "$tmp/imu.json" "d['num_colmap_sensors_not_modelled'] == 1"
"$dba" solve "$tmp/imu" -o "$tmp/imu_out2" > "$tmp/log" 2>&1
check "... and a line says so" contains "$tmp/log" \
  "COLMAP rigs: 1 sensor that is not a camera (IMU) is kept in the model as read, not adjusted"

# An IMU as the rig's reference sensor, at camera 1's place: camera 1 (posed
# at the identity) is held where the model puts it and places the rig's
# frame, so the solve is the camera-origin model's, to the digit (tight);
# the IMU stays the written rig's reference.
to_colmap "$tmp/rig.dba" 2 "$tmp/imuref" --imu-origin
"$dba" solve "$tmp/m" -q --linear-solver dense --report "$tmp/camref.json" > /dev/null 2>&1
"$dba" solve "$tmp/imuref" -q --linear-solver dense -o "$tmp/imuref_out" --report "$tmp/imuref.json" > "$tmp/log" 2>&1
check "a rig whose reference is an IMU solves" test $? -eq 0
check "... as the camera-origin rig (1e-9), with its unknowns" json "$tmp/imuref.json" \
  "near(d['final_cost'], $(json_value "$tmp/camref.json" final_cost), 1e-9) and d['camera_unknowns'] == 80 * 6 + 6 + 2 * 3"
check "... written with the IMU its reference, camera 1 held" contains "$tmp/imuref_out/rigs.txt" \
  "1 3 IMU 1 CAMERA 1 1 1 0 0 0 0 0 0 CAMERA 2 1"
sed -i '/^[^#]/ s/CAMERA 1 1 1 0 0 0 0 0 0/CAMERA 1 0/' "$tmp/imuref/rigs.txt"
"$dba" solve "$tmp/imuref" -q > "$tmp/refused.txt" 2>&1
check "... refused by name when its first camera has no pose" contains "$tmp/refused.txt" \
  "rig 1: its reference sensor is not a camera, and its first camera (1) has no pose in it"

"$dba" solve "$tmp/m" -q --rig-geometry fixed:2 --report "$tmp/fixed2.json" > /dev/null 2>&1
check "--rig-geometry fixed:2 holds COLMAP camera 2, the rig's sensor" json "$tmp/fixed2.json" \
  "d['camera_unknowns'] == 80 * 6 + 2 * 3"
"$dba" solve "$tmp/m" -q --rig-geometry fixed:9 > "$tmp/refused.txt" 2>&1
check "... and a camera that is not a sensor is refused" contains "$tmp/refused.txt" \
  "--rig-geometry fixed:9: COLMAP camera 9 is not a sensor of the model's rigs"
"$dba" solve "$tmp/m" -q --intrinsics per-image > "$tmp/refused.txt" 2>&1
check "per-image intrinsics with rigs are refused by name" contains "$tmp/refused.txt" \
  "--intrinsics per-image: $tmp/m has rigs of several cameras"
# --fix-images on a rig holds the image's pose: its frame and its sensor
# (camera 2, in every frame), so 79 frames and no sensor are unknowns and
# image 2 (camera 2 in frame 1) is written at its pose as read (1e-12)
# after 5 iterations (holding the rig at its start fits it slowly).
"$dba" solve "$tmp/m" -q --fix-images 2 --max-iterations 5 -o "$tmp/held" --report "$tmp/held.json" > /dev/null 2>&1
check "--fix-images 2 on a rig: its frame and its sensor held" json "$tmp/held.json" \
  "d['camera_unknowns'] == 79 * 6 + 2 * 3"
check "... image 2 written at its pose as read (1e-12), image 4 moved" /usr/bin/python3 - "$tmp/m" "$tmp/held" <<'PY'
import sys
import numpy as np
def poses(d):
    lines = [l.split() for l in open(f"{d}/images.txt") if not l.startswith("#")][0::2]
    out = {}
    for v in lines:
        w, x, y, z = np.array([float(a) for a in v[1:5]]) / np.linalg.norm([float(a) for a in v[1:5]])
        R = np.array([[1 - 2*(y*y + z*z), 2*(x*y - w*z), 2*(x*z + w*y)],
                      [2*(x*y + w*z), 1 - 2*(x*x + z*z), 2*(y*z - w*x)],
                      [2*(x*z - w*y), 2*(y*z + w*x), 1 - 2*(x*x + y*y)]])
        out[int(v[0])] = np.concatenate([R.ravel(), [float(a) for a in v[5:8]]])
    return out
a, b = poses(sys.argv[1]), poses(sys.argv[2])
held, moved = np.abs(a[2] - b[2]).max(), np.abs(a[4] - b[4]).max()
print(f"image 2 off by {held:.3g}, image 4 moved by {moved:.3g}", file=sys.stderr)
sys.exit(0 if held <= 1e-12 and moved > 1e-6 else 1)
PY

# Hostile rigs and frames files, read as images.txt is (one line reader, one
# quaternion check): a zero or 1e300 quaternion, a line over 64 MiB, a
# number cut at the end of the file, refused naming the file and line (exit
# 1, nothing written); the binary files' quaternions by byte; a frame
# holding two images of one camera, by frame and camera.
edited() { rm -rf "$tmp/$1"; cp -r "${2:-$tmp/m}" "$tmp/$1"; }
refused() {  # refused NAME SAYS: the solve of $tmp/NAME exits 1 saying SAYS
  "$dba" solve "$tmp/$1" -q -o "$tmp/$1.out" > "$tmp/log" 2>&1
  local status=$?
  check "$1: exit 1 (got $status)" test "$status" -eq 1
  check "$1: says '$2'" contains "$tmp/log" "$2"
  check "$1: nothing written" test ! -e "$tmp/$1.out"
}
edited zero_frame
awk 'NR == 2 {$3 = 0; $4 = 0; $5 = 0; $6 = 0} {print}' "$tmp/m/frames.txt" > "$tmp/zero_frame/frames.txt"
refused zero_frame "$tmp/zero_frame/frames.txt:2: the frame's quaternion is zero or its norm is not finite"
edited huge_sensor
awk '{$8 = "1e300"; $9 = "1e300"; $10 = "1e300"; $11 = "1e300"} {print}' "$tmp/m/rigs.txt" > "$tmp/huge_sensor/rigs.txt"
refused huge_sensor "$tmp/huge_sensor/rigs.txt:1: the sensor's quaternion is zero or its norm is not finite"
edited long_line
{ head -c 70000000 /dev/zero | tr '\0' ' '; echo; } >> "$tmp/long_line/frames.txt"
refused long_line "$tmp/long_line/frames.txt:81: line longer than 64 MiB"
edited cut_frames
frames_txt=$(cat "$tmp/m/frames.txt")
printf '%s' "${frames_txt%?}" > "$tmp/cut_frames/frames.txt"  # no newline, last digit gone
refused cut_frames "$tmp/cut_frames/frames.txt:80: the file ends inside this line"
edited cut_rigs
rigs_txt=$(cat "$tmp/m/rigs.txt")
printf '%s' "${rigs_txt%?}" > "$tmp/cut_rigs/rigs.txt"
refused cut_rigs "$tmp/cut_rigs/rigs.txt:1: the file ends inside this line"
"$dba" convert "$tmp/m" "$tmp/mb" --colmap-format binary > /dev/null 2>&1
patch_f64() {  # patch_f64 FILE OFFSET VALUE...: doubles written from byte OFFSET
  python3 -c "import struct, sys; f = open(sys.argv[1], 'r+b'); f.seek(int(sys.argv[2])); f.write(struct.pack('<%dd' % (len(sys.argv) - 3), *map(float, sys.argv[3:])))" "$@"
}
edited zero_frame_bin "$tmp/mb"
patch_f64 "$tmp/zero_frame_bin/frames.bin" 16 0 0 0 0  # the first frame's QW..QZ (after count, ids)
refused zero_frame_bin "frame #0 (id 1) rig_from_world's quaternion is zero or its norm is not finite"
check "zero_frame_bin: ... naming the file and byte" contains "$tmp/log" "$tmp/zero_frame_bin/frames.bin: at byte 48"
edited huge_sensor_bin "$tmp/mb"
patch_f64 "$tmp/huge_sensor_bin/rigs.bin" 33 1e300 1e300 1e300 1e300  # the sensor's QW..QZ
refused huge_sensor_bin "rig #0 (id 1) sensor_from_rig's quaternion is zero or its norm is not finite"
edited one_camera_twice
awk 'NR == 3 {$9 = 1} {print}' "$tmp/m/images.txt" > "$tmp/one_camera_twice/images.txt"
awk 'NR == 1 {$15 = 1} {print}' "$tmp/m/frames.txt" > "$tmp/one_camera_twice/frames.txt"
refused one_camera_twice \
  "$tmp/one_camera_twice/frames.txt: frame 1: images 1 and 2 are both of camera 1 (a frame is one exposure: one image per sensor)"
finish
