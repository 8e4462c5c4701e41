#!/usr/bin/env bash
# The gauge held by default (camera/gauge_hold.h): on every shipped COLMAP
# model and on a BAL problem, the first image (the lowest image id; the
# first camera) keeps its pose and its distance to the next image, to 1e-9
# of the spread of the centres; the cost is the free gauge's; the written
# model re-reads at the final cost. A fixed image holds the pose, two hold
# everything. Usage: cli_gauge.sh PATH_TO_DBA PROJECT_ROOT
set -uo pipefail
source "$(dirname "$0")/lib/check.sh"
dba=$1
root=$2
colmap=$root/../shared/data/colmap
need_shared "$colmap" "$root/../shared/data/bal"

# held IN OUT [ANCHOR_ID]: the pose of image ANCHOR_ID (default: the lowest
# id) and its distance to the next id's centre, IN (as loaded) against OUT,
# both COLMAP text models.
held() {
  /usr/bin/python3 - "$@" <<'PY'
import sys
import numpy as np
def poses(d):
    lines = [l for l in open(f"{d}/images.txt") if not l.startswith("#")]
    out = {}
    for l in lines[0::2]:
        v = l.split()
        if len(v) < 10: continue
        q = np.array([float(x) for x in v[1:5]]); q /= np.linalg.norm(q)
        w, x, y, z = q
        R = np.array([[1 - 2*(y*y + z*z), 2*(x*y - w*z), 2*(x*z + w*y)],
                      [2*(x*y + w*z), 1 - 2*(x*x + z*z), 2*(y*z - w*x)],
                      [2*(x*z - w*y), 2*(y*z + w*x), 1 - 2*(x*x + y*y)]])
        t = np.array([float(x) for x in v[5:8]])
        out[int(v[0])] = (R, -R.T @ t)
    return out
a, b = poses(sys.argv[1]), poses(sys.argv[2])
ids = sorted(a)
anchor = int(sys.argv[3]) if len(sys.argv) > 3 else ids[0]
other = next(i for i in ids if i != anchor)
centres = np.array([a[i][1] for i in ids])
spread = np.linalg.norm(centres.max(0) - centres.min(0))
moved = np.linalg.norm(a[anchor][1] - b[anchor][1]) / spread
# |R - I|_F = 2√2 sin(θ/2): exact near θ = 0, where arccos of the trace is not
turn = 2 * np.arcsin(min(1.0, np.linalg.norm(a[anchor][0].T @ b[anchor][0] - np.eye(3)) / (2 * np.sqrt(2))))
d0 = np.linalg.norm(a[other][1] - a[anchor][1]); d1 = np.linalg.norm(b[other][1] - b[anchor][1])
ok = moved < 1e-9 and turn < 1e-9 and abs(d1 / d0 - 1) < 1e-9
if not ok: print(f"centre moved {moved:.3g} of the spread, turned {turn:.3g} rad, distance {d1/d0 - 1:.3g}", file=sys.stderr)
sys.exit(0 if ok else 1)
PY
}

not_held() { ! held "$@" 2>/dev/null; }

for m in mithunnallana_6img statue_of_liberty_small_txt statue_of_liberty fountain_p11 softmurata_177img; do
  model=$colmap/$m/sparse/0
  # softmurata takes half a minute to converge: five iterations move it enough.
  limit=(); [ "$m" = softmurata_177img ] && limit=(--max-iterations 5)
  "$dba" solve "$model" -q --max-iterations 0 --gauge free -o "$tmp/$m.in" --colmap-format text >/dev/null 2>&1
  "$dba" solve "$model" -q ${limit[@]+"${limit[@]}"} -o "$tmp/$m.hold" --colmap-format text \
    --report "$tmp/$m.hold.json" >"$tmp/out" 2>&1
  check "$m: solve exits 0" test $? -eq 0
  "$dba" solve "$model" -q ${limit[@]+"${limit[@]}"} --gauge free -o "$tmp/$m.free" --colmap-format text \
    --report "$tmp/$m.free.json" >/dev/null 2>&1
  check "$m: the first image keeps its pose and its distance to the second" held "$tmp/$m.in" "$tmp/$m.hold"
  check "$m: with --gauge free it does not (the test can fail)" not_held "$tmp/$m.in" "$tmp/$m.free"
  check "$m: the cost is the free gauge's" json "$tmp/$m.hold.json" \
    "near(d['final_cost'], $(json_value "$tmp/$m.free.json" final_cost), 1e-12)"
  check "$m: the summary says what held it" json "$tmp/$m.hold.json" \
    "d['gauge'].startswith(\"image 0's pose and its distance to image 1\")"
  "$dba" solve "$tmp/$m.hold" -q --max-iterations 0 --report "$tmp/$m.reread.json" >/dev/null 2>&1
  check "$m: the held model re-reads at the final cost" json "$tmp/$m.reread.json" \
    "near(d['initial_cost'], $(json_value "$tmp/$m.hold.json" final_cost), 1e-9)"
done

# A solve that does not move the model leaves it bit for bit: the held gauge
# maps it by nothing (not an identity to rounding), and an unchanged
# rotation keeps its quaternion. (Each point's ERROR is recomputed, from
# poses that went through angle-axis: equal to rounding, so left out.)
no_error() { awk '!/^#/ {$8 = ""} {print}' "$1"; }
for m in mithunnallana_6img fountain_p11; do
  for gauge in hold free; do
    "$dba" solve "$tmp/$m.in" -q --max-iterations 0 --gauge $gauge -o "$tmp/$m.same$gauge" \
      --colmap-format text >/dev/null 2>&1
    check "$m: no iteration, --gauge $gauge: images.txt byte for byte" \
      cmp -s "$tmp/$m.in/images.txt" "$tmp/$m.same$gauge/images.txt"
    check "$m: no iteration, --gauge $gauge: points3D.txt byte for byte but ERROR" \
      cmp -s <(no_error "$tmp/$m.in/points3D.txt") <(no_error "$tmp/$m.same$gauge/points3D.txt")
  done
done

# One model, one result: converted to .dba (for MPI) it solves as the COLMAP
# directory does (COLMAP's defaults are the model's, not the reader's).
"$dba" convert "$colmap/mithunnallana_6img/sparse/0" "$tmp/m.dba" >/dev/null 2>&1
"$dba" solve "$tmp/m.dba" -q --report "$tmp/mdba.json" >/dev/null 2>&1
check "converted to .dba, the same final cost" json "$tmp/mdba.json" \
  "near(d['final_cost'], $(json_value "$tmp/mithunnallana_6img.hold.json" final_cost), 1e-9)"

# The counts named as COLMAP names them: softmurata's 177 images use 177 of
# its 690 cameras (num_cameras, deprecated, still counts images).
check "num_images, num_colmap_cameras and the cameras in use" json "$tmp/softmurata_177img.hold.json" \
  "[d['num_images'], d['num_colmap_cameras'], d['num_colmap_cameras_used'], d['num_cameras']] == [177, 690, 177, 177]"

# A point moved behind a camera (reflected through the camera's centre) is
# counted in the report and said in the summary; none in the shipped model.
check "no observation behind a camera in the shipped model" json "$tmp/mithunnallana_6img.hold.json" \
  "d['observations_behind_cameras'] == 0"
mkdir -p "$tmp/behind"
cp "$tmp/mithunnallana_6img.in/"{cameras,images}.txt "$tmp/behind/"
/usr/bin/python3 - "$tmp/mithunnallana_6img.in" "$tmp/behind" <<'PY'
import sys
import numpy as np
src, dst = sys.argv[1], sys.argv[2]
lines = [l for l in open(f"{src}/images.txt") if not l.startswith("#")]
pose = {}
for l in lines[0::2]:
    v = l.split()
    w, x, y, z = (float(a) for a in v[1:5])
    R = np.array([[1 - 2*(y*y + z*z), 2*(x*y - w*z), 2*(x*z + w*y)],
                  [2*(x*y + w*z), 1 - 2*(x*x + z*z), 2*(y*z - w*x)],
                  [2*(x*z - w*y), 2*(y*z + w*x), 1 - 2*(x*x + y*y)]])
    pose[v[0]] = -R.T @ np.array([float(a) for a in v[5:8]])
out, done = [], False
for l in open(f"{src}/points3D.txt"):
    v = l.split()
    if not done and v and not l.startswith("#"):
        C = pose[v[8]]  # the first image of its track
        X = 2 * C - np.array([float(a) for a in v[1:4]])
        v[1:4] = [repr(a) for a in X]
        l, done = " ".join(v) + "\n", True
    out.append(l)
open(f"{dst}/points3D.txt", "w").writelines(out)
PY
"$dba" solve "$tmp/behind" -q --max-iterations 1 --report "$tmp/behind.json" >"$tmp/out" 2>&1
check "an observation behind its camera is counted" json "$tmp/behind.json" "d['observations_behind_cameras'] >= 1"
check "... and said" contains "$tmp/out" "observations had their point behind the camera at the start"

# One fixed image holds the pose (it is not moved at all); the scale is held
# by its distance to the first other image. Two fixed images hold everything.
m=$colmap/statue_of_liberty_small_txt/sparse/0
first_ids=$(awk '!/^#/ && NF >= 10 {print $1}' "$m/images.txt" | sort -n | head -3 | paste -sd' ')
read -r id0 id1 id2 <<<"$first_ids"
"$dba" solve "$m" -q --fix-images "$id2" -o "$tmp/fix1" --colmap-format text --report "$tmp/fix1.json" >/dev/null 2>&1
check "a fixed image keeps its pose and its distance to another" held "$tmp/statue_of_liberty_small_txt.in" "$tmp/fix1" "$id2"
check "a fixed image holds the gauge (summary)" json "$tmp/fix1.json" "d['gauge'].startswith('fixed image 2, and its distance to image 0')"
"$dba" solve "$m" -q --fix-images "$id1,$id2" --report "$tmp/fix2.json" >/dev/null 2>&1
check "two fixed images hold it" json "$tmp/fix2.json" "d['gauge'] == 'the images held fixed'"
"$dba" solve "$m" -q --fix-images all --report "$tmp/fixall.json" >"$tmp/out" 2>&1
check "--fix-images all leaves only the intrinsics and points" grep -qE "unknowns +[0-9]+ \(2 camera-side" "$tmp/out"
name=$(awk '!/^#/ && NF >= 10 && $1 == '"$id1"' {print $10}' "$m/images.txt")
"$dba" solve "$m" -q --fix-images "$name,$id2" --report "$tmp/fixnames.json" >/dev/null 2>&1
check "--fix-images takes image names" json "$tmp/fixnames.json" "d['gauge'] == 'the images held fixed'"
"$dba" solve "$m" -q --fix-images nosuch.jpg >"$tmp/out" 2>&1
check "an unknown image name exits 2" test $? -eq 2
check "an unknown image name is named" contains "$tmp/out" "has no image named 'nosuch.jpg'"

# BAL: the first camera keeps its pose (ω, t exactly) and its distance to
# the second; the cost is the free gauge's.
bal=$root/../shared/data/bal/problem-49-7776-pre.txt.bz2
"$dba" solve "$bal" -q -o "$tmp/bal.txt" --report "$tmp/bal.json" >/dev/null 2>&1
"$dba" solve "$bal" -q --gauge free --report "$tmp/balfree.json" >/dev/null 2>&1
check "BAL: the first camera keeps its pose and its distance to the second" /usr/bin/python3 - "$bal" "$tmp/bal.txt" <<'PY'
import bz2, sys
import numpy as np
def cams(path):
    f = bz2.open(path, "rt") if path.endswith(".bz2") else open(path)
    v = f.read().split(); nc, no = int(v[0]), int(v[2])
    return np.array(v[3 + 4 * no:3 + 4 * no + 9 * nc], dtype=float).reshape(nc, 9)
def centre(c):
    w = c[:3]; th = np.linalg.norm(w); k = w / th
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    R = np.eye(3) + np.sin(th) * K + (1 - np.cos(th)) * K @ K
    return -R.T @ c[3:6]
a, b = cams(sys.argv[1]), cams(sys.argv[2])
same = np.allclose(a[0, :6], b[0, :6], rtol=1e-15, atol=0)
d0 = np.linalg.norm(centre(a[1]) - centre(a[0])); d1 = np.linalg.norm(centre(b[1]) - centre(b[0]))
sys.exit(0 if same and abs(d1 / d0 - 1) < 1e-9 else 1)
PY
check "BAL: the cost is the free gauge's" json "$tmp/bal.json" \
  "near(d['final_cost'], $(json_value "$tmp/balfree.json" final_cost), 1e-12)"
"$dba" solve "$tmp/bal.txt" -q --max-iterations 0 --report "$tmp/balre.json" >/dev/null 2>&1
check "BAL: the output re-reads at the final cost" json "$tmp/balre.json" \
  "near(d['initial_cost'], $(json_value "$tmp/bal.json" final_cost), 1e-9)"
finish
