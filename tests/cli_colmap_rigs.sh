#!/usr/bin/env bash
# COLMAP >= 3.12's rigs and frames: a model with trivial ones (one camera
# per rig, one image per frame) is read; a rig of several cameras and binary
# rigs/frames are refused naming the file; a directory holding rigs or
# frames files is never written into (they would give COLMAP >= 3.12 the
# old poses with the new points), and nothing is written.
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
awk '!/^#/ && NF >= 10 {print $1, 1, $2, $3, $4, $5, $6, $7, $8, 1, "CAMERA", 1, $1}' "$src/images.txt" >"$tmp/m/frames.txt"
cp -r "$tmp/m" "$tmp/before"
"$dba" solve "$tmp/m" -q -o "$tmp/out" --report "$tmp/r.json" >"$tmp/log" 2>&1
check "trivial rigs and frames are read" test $? -eq 0
check "... and the model written elsewhere holds none" test ! -e "$tmp/out/frames.txt" -a -s "$tmp/out/images.txt"
"$dba" solve "$tmp/m" -q -o "$tmp/m" >"$tmp/log" 2>&1
check "in place, beside its frames, is refused (exit 2)" test $? -eq 2
check "... naming the rigs file" contains "$tmp/log" "holds rigs.txt (COLMAP >= 3.12 rigs and frames)"
check "... and the model is untouched" diff -r "$tmp/m" "$tmp/before"
mkdir -p "$tmp/old"
touch "$tmp/old/rigs.bin"
"$dba" solve "$src" -q -o "$tmp/old" >"$tmp/log" 2>&1
check "an old model's directory with rigs is refused (exit 2)" test $? -eq 2
check "... and nothing is written there" test ! -e "$tmp/old/images.txt"

# A rig of two cameras, and binary rigs: refused naming the file and line.
echo "1 2 CAMERA 1 CAMERA 2 1 1 0 0 0 0.1 0 0" >"$tmp/m/rigs.txt"
"$dba" solve "$tmp/m" -q >"$tmp/log" 2>&1
check "a rig of two cameras exits 1" test $? -eq 1
check "... naming the file and line" contains "$tmp/log" "$tmp/m/rigs.txt:1: 2 sensors: a rig of several cameras is not modelled yet"
rm "$tmp/m/rigs.txt"; touch "$tmp/m/frames.bin"
"$dba" solve "$tmp/m" -q >"$tmp/log" 2>&1
check "binary frames are refused by name" contains "$tmp/log" "frames.bin: COLMAP >= 3.12 binary rigs and frames are not read yet"
finish
