#!/usr/bin/env bash
# COLMAP >= 3.12's rigs and frames: a model with trivial ones (one camera
# per rig, one image per frame, text) is read and written back with each
# frame at its image's solved pose, in place too; a rig of several cameras
# and binary rigs/frames are refused naming the file; a model without rigs
# is never written into a directory holding rigs or frames files (they
# would give COLMAP >= 3.12 the old poses with the new points).
# Usage: cli_colmap_rigs.sh PATH_TO_DBA PROJECT_ROOT
set -uo pipefail
source "$(dirname "$0")/lib/check.sh"
dba=$1
root=$2
colmap=$root/../shared/data/colmap
need_shared "$colmap"
src=$colmap/mithunnallana_6img/sparse/0

# A 3.12-style text model with trivial rigs and frames.
mkdir -p "$tmp/m"
cp "$src/"{cameras,images,points3D}.txt "$tmp/m/"
echo "1 1 CAMERA 1" >"$tmp/m/rigs.txt"
awk '!/^#/ && n++ % 2 == 0 {print $1, 1, $2, $3, $4, $5, $6, $7, $8, 1, "CAMERA", 1, $1}' "$src/images.txt" >"$tmp/m/frames.txt"
cp -r "$tmp/m" "$tmp/before"
differ() { ! cmp -s "$1" "$2"; }
# consistent DIR: every frame's pose is its image's, in DIR.
consistent() {
  python3 - "$1" <<'PY'
import sys
d = sys.argv[1]
lines = [l for l in open(f"{d}/images.txt") if not l.startswith("#")]
images = {v[0]: v[1:8] for v in (l.split() for l in lines[0::2])}
frames = [v for v in (l.split() for l in open(f"{d}/frames.txt") if not l.startswith("#")) if v]
sys.exit(0 if frames and len(frames) == len(images) and all(f[2:9] == images[f[12]] for f in frames) else 1)
PY
}
"$dba" solve "$tmp/m" -q -o "$tmp/out" --report "$tmp/r.json" >"$tmp/log" 2>&1
check "trivial rigs and frames are read" test $? -eq 0
check "... and written back with the model, each frame at its image's solved pose" consistent "$tmp/out"
check "... the poses did move" differ "$tmp/m/frames.txt" "$tmp/out/frames.txt"
check "... the rigs as they were" diff <(grep -v '^#' "$tmp/m/rigs.txt") <(grep -v '^#' "$tmp/out/rigs.txt")
"$dba" solve "$tmp/m" -q -o "$tmp/m" >"$tmp/log" 2>&1
check "in place, the frames are written anew" consistent "$tmp/m"
"$dba" solve "$tmp/before" -q -o "$tmp/bin" --colmap-format binary >"$tmp/log" 2>&1
check "binary output of rigs and frames is refused (exit 2)" test $? -eq 2
check "... naming why" contains "$tmp/log" "which dba writes as text only"
check "... and writes nothing" test ! -e "$tmp/bin"
mkdir -p "$tmp/old"
touch "$tmp/old/rigs.bin"
"$dba" solve "$src" -q -o "$tmp/old" >"$tmp/log" 2>&1
check "an old model's directory with rigs is refused (exit 2)" test $? -eq 2
check "... and nothing is written there" test ! -e "$tmp/old/images.txt"

# A rig of two cameras, and binary rigs: refused naming the file and line.
cp "$tmp/before/frames.txt" "$tmp/m/"
echo "1 2 CAMERA 1 CAMERA 2 1 1 0 0 0 0.1 0 0" >"$tmp/m/rigs.txt"
"$dba" solve "$tmp/m" -q >"$tmp/log" 2>&1
check "a rig of two cameras exits 1" test $? -eq 1
check "... naming the file and line" contains "$tmp/log" "$tmp/m/rigs.txt:1: 2 sensors: a rig of several cameras is not modelled yet"
rm "$tmp/m/rigs.txt"; touch "$tmp/m/frames.bin"
"$dba" solve "$tmp/m" -q >"$tmp/log" 2>&1
check "binary frames are refused by name" contains "$tmp/log" "frames.bin: COLMAP >= 3.12 binary rigs and frames are not read yet"
finish
