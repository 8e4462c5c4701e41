#!/usr/bin/env bash
# COLMAP >= 3.12's rigs and frames: a model with trivial ones (one camera
# per rig, one image per frame, text or binary) is read and written back
# with each frame at its image's solved pose, in place too, in either
# format; rigs and frames that do not fit the model are refused naming the
# file (and byte); a model without rigs is never written into a directory holding
# rigs or frames files (they would give COLMAP >= 3.12 the old poses with
# the new points), nor a model with them beside the other format's.
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
"$dba" solve "$tmp/before" -q -o "$tmp/bin" --colmap-format binary --report "$tmp/rb.json" >"$tmp/log" 2>&1
check "binary output of rigs and frames" test $? -eq 0 -a -s "$tmp/bin/rigs.bin" -a -s "$tmp/bin/frames.bin"
# COLMAP's layout (colmap_rigs.cc): 8 + 16 bytes a rig, 8 + 84 a frame.
check "... rigs.bin in COLMAP's layout (one rig)" test "$(stat -c %s "$tmp/bin/rigs.bin")" -eq 24
check "... frames.bin in COLMAP's layout (six frames)" test "$(stat -c %s "$tmp/bin/frames.bin")" -eq $((8 + 6 * 84))
"$dba" solve "$tmp/bin" -q --max-iterations 0 -o "$tmp/bin2txt" --colmap-format text >"$tmp/log" 2>&1
check "... read back and written as text: each frame at its image's pose" consistent "$tmp/bin2txt"
check "... the rigs as they were" diff <(grep -v '^#' "$tmp/m/rigs.txt") <(grep -v '^#' "$tmp/bin2txt/rigs.txt")
check "... the frames' ids as they were" \
  diff <(awk '!/^#/ {print $1, $2, $10, $11, $12, $13}' "$tmp/before/frames.txt") \
       <(awk '!/^#/ {print $1, $2, $10, $11, $12, $13}' "$tmp/bin2txt/frames.txt")
"$dba" solve "$tmp/bin2txt" -q --max-iterations 0 --report "$tmp/c.json" >/dev/null 2>&1
check "... at the binary solve's final cost" json "$tmp/rb.json" \
  "near(d['final_cost'], $(json_value "$tmp/c.json" initial_cost), 1e-9)"
"$dba" convert "$tmp/before" "$tmp/binin" --colmap-format binary >"$tmp/log" 2>&1
check "dba convert carries the rigs and frames" test $? -eq 0 -a -s "$tmp/binin/frames.bin"
cp "$tmp/binin/frames.bin" "$tmp/frames.before"
"$dba" solve "$tmp/binin" -q -o "$tmp/binin" >"$tmp/log" 2>&1
check "binary in place exits 0" test $? -eq 0
check "... the frames written anew" differ "$tmp/frames.before" "$tmp/binin/frames.bin"
check "... the same as the binary solve's" cmp -s "$tmp/bin/frames.bin" "$tmp/binin/frames.bin"
"$dba" solve "$tmp/before" -q -o "$tmp/bin" --colmap-format text >"$tmp/log" 2>&1
check "text rigs beside binary ones are refused (exit 2)" test $? -eq 2
check "... naming the stale file" contains "$tmp/log" "holds rigs.bin"
mkdir -p "$tmp/old"
touch "$tmp/old/rigs.bin"
"$dba" solve "$src" -q -o "$tmp/old" >"$tmp/log" 2>&1
check "an old model's directory with rigs is refused (exit 2)" test $? -eq 2
check "... and nothing is written there" test ! -e "$tmp/old/images.txt"

# A rig naming a camera the model lacks, and binary rigs cut short:
# refused naming the file (and byte).
cp "$tmp/before/frames.txt" "$tmp/m/"
echo "1 2 CAMERA 1 CAMERA 2 1 1 0 0 0 0.1 0 0" >"$tmp/m/rigs.txt"
"$dba" solve "$tmp/m" -q >"$tmp/log" 2>&1
check "a rig naming a camera the model lacks exits 1" test $? -eq 1
check "... naming the file and the camera" contains "$tmp/log" "$tmp/m/rigs.txt: rig 1: camera 2 is not in the model"
rm "$tmp/m/rigs.txt"
"$dba" solve "$tmp/m" -q >"$tmp/log" 2>&1
check "frames without rigs are refused by name" contains "$tmp/log" "rigs.txt: missing: COLMAP >= 3.12 writes rigs and frames together"
# Frames that do not match the model: a rig that is missing, an image in two
# frames, an image in none.
frames_case() {  # frames_case NAME AWK: $tmp/before with frames.txt edited
  cp -r "$tmp/before" "$tmp/$1"
  awk "$2" "$tmp/before/frames.txt" >"$tmp/$1/frames.txt"
}
frames_case no_rig '!/^#/ && ++n == 2 {$2 = 9} {print}'
"$dba" solve "$tmp/no_rig" -q >"$tmp/log" 2>&1
check "a frame naming a missing rig is refused" contains "$tmp/log" "names rig 9, which the rigs do not hold"
frames_case twice '!/^#/ && ++n == 2 {$13 = first} !/^#/ && n == 1 {first = $13} {print}'
"$dba" solve "$tmp/twice" -q >"$tmp/log" 2>&1
check "an image in two frames is refused" contains "$tmp/log" "is also in frame"
frames_case none '!/^#/ && ++n == 3 {next} {print}'
"$dba" solve "$tmp/none" -q >"$tmp/log" 2>&1
check "an image in no frame is refused" contains "$tmp/log" "is in no frame"
# Binary: a rig said to have two sensors (num_sensors at byte 12) but
# holding one, a frame said to hold two images (num_data_ids at byte 8 +
# 64), a truncated frames.bin.
cp -r "$tmp/before" "$tmp/b2"
rm "$tmp/b2/"*.txt
"$dba" convert "$tmp/before" "$tmp/b2" --colmap-format binary >/dev/null 2>&1
patch_u32() { python3 -c "import struct, sys; f = open(sys.argv[1], 'r+b'); f.seek(int(sys.argv[2])); f.write(struct.pack('<I', int(sys.argv[3])))" "$@"; }
cp -r "$tmp/b2" "$tmp/b3"; cp -r "$tmp/b2" "$tmp/b4"
patch_u32 "$tmp/b2/rigs.bin" 12 2
"$dba" solve "$tmp/b2" -q >"$tmp/log" 2>&1
check "binary: a rig cut short exits 1" test $? -eq 1
check "... naming the file, the byte and the rig" contains "$tmp/log" "rigs.bin: at byte 24: file truncated: rig #0 (id 1)"
patch_u32 "$tmp/b3/frames.bin" 72 2
"$dba" solve "$tmp/b3" -q >"$tmp/log" 2>&1
check "binary: a frame read past its data is refused by name" contains "$tmp/log" "frames.bin: at byte 96: frame #0 (id 1) sensor type 2"
truncate -s -3 "$tmp/b4/frames.bin"
"$dba" solve "$tmp/b4" -q >"$tmp/log" 2>&1
check "binary: a truncated frames.bin is refused" contains "$tmp/log" "frames.bin: at byte"
finish
