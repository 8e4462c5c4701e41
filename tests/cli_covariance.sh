#!/usr/bin/env bash
# --covariance end to end (precision/camera_covariance.h, README.md
# "Precision"): the file's shape and blocks (symmetric positive
# semi-definite, sigmas their diagonal's roots) on a shipped BAL problem and
# a COLMAP model; the datum named (inner, absolute, held images); unit
# against a-posteriori by the report's variance factor; the same blocks on 2
# ranks as in one process and whatever the input's order; what it cannot do
# refused by name with nothing written. The blocks' values against dense
# inverses are unit tests (camera_covariance_test.cc).
# Usage: cli_covariance.sh PATH_TO_DBA PROJECT_ROOT
set -uo pipefail
source "$(dirname "$0")/lib/check.sh"
dba=$1
root=$2
data=$root/../shared/data
need_shared "$data/bal" "$data/colmap"
not() { ! "$@" 2>/dev/null; }
cov() { /usr/bin/python3 "$root/tests/lib/covariance_check.py" "$@"; }
mpirun_n() { local n=$1; shift; timeout -k 10 300 mpirun --allow-run-as-root --oversubscribe --bind-to none -np "$n" "$@"; }
p16=$data/bal/problem-16-22106-pre.txt.bz2
tight=(--linear-solver dense --function-tolerance 1e-12 --parameter-tolerance 1e-14)

"$dba" solve "$p16" -q "${tight[@]}" --covariance "$tmp/p16.csv" --report "$tmp/p16.json" >"$tmp/out" 2>&1
check "problem-16: exits 0" test $? -eq 0
check "problem-16: a valid file, 16 images, inner constraints" cov valid "$tmp/p16.csv" 16 inner
check "problem-16: the report's covariance section" json "$tmp/p16.json" \
  "d['covariance']['datum'] == 'inner' and d['covariance']['scale'] == 'a-posteriori' and \
   d['covariance']['redundancy'] == 2 * 83718 - (16 * 9 + 3 * 22106) + 7 and d['covariance']['factor_nonzeros'] > 0"
check "problem-16: the summary says it" contains "$tmp/out" "covariance          inner constraints over the centres"
"$dba" solve "$p16" -q "${tight[@]}" --covariance "$tmp/p16u.csv" --covariance-scale unit >/dev/null 2>&1
vf=$(/usr/bin/python3 -c 'import json,sys; print(repr(json.load(open(sys.argv[1]))["covariance"]["variance_factor"]))' "$tmp/p16.json")
check "problem-16: a-posteriori is unit times the variance factor ($vf)" cov scaled "$tmp/p16u.csv" "$tmp/p16.csv" "$vf"
check "problem-16: the variance factor is the final cost over the redundancy" json "$tmp/p16.json" \
  "near(d['covariance']['variance_factor'], 2 * d['final_cost'] / d['covariance']['redundancy'], 1e-12)"

# The ranks gather S on rank 0 and take the same blocks.
mpirun_n 2 "$dba" solve "$p16" -q "${tight[@]}" --rcs gather --covariance "$tmp/p16r.csv" >/dev/null 2>&1
check "problem-16 on 2 ranks: exits 0" test $? -eq 0
check "problem-16 on 2 ranks: the blocks of one process (1e-7)" cov same "$tmp/p16.csv" "$tmp/p16r.csv" 1e-7
# With the defaults the ranks gather S for it (the RCS would be spread):
# the blocks of one process's default solve (the agreement rule's 1e-5 on
# the cost: 1e-4 on the blocks).
"$dba" solve "$p16" -q --covariance "$tmp/p16o.csv" >/dev/null 2>&1
mpirun_n 2 "$dba" solve "$p16" -q --covariance "$tmp/p16g.csv" --report "$tmp/p16g.json" >/dev/null 2>&1
check "problem-16 on 2 ranks, defaults: exits 0" test $? -eq 0
check "problem-16 on 2 ranks, defaults: S gathered" json "$tmp/p16g.json" "d['distributed']['rcs'] == 'gather'"
check "problem-16 on 2 ranks, defaults: one process's blocks (1e-4)" cov same "$tmp/p16o.csv" "$tmp/p16g.csv" 1e-4
mpirun_n 2 "$dba" solve "$p16" -q --rcs distributed --covariance "$tmp/p16d.csv" >"$tmp/out" 2>&1
check "2 ranks with the RCS spread asked for: refused" test $? -ne 0
check "2 ranks with the RCS spread asked for: said" contains "$tmp/out" "not with --rcs distributed"
check "2 ranks with the RCS spread asked for: nothing written" test ! -e "$tmp/p16d.csv"

# The input's order does not change the blocks (images named in it).
"$dba" convert "$p16" "$tmp/s16.txt" --shuffle 3 >/dev/null 2>&1
"$dba" solve "$tmp/s16.txt" -q "${tight[@]}" --covariance "$tmp/s16.csv" >/dev/null 2>&1
check "problem-16 shuffled: the same blocks (1e-7)" cov matched "$tmp/p16.csv" "$tmp/s16.csv" 1e-7
check "problem-16 shuffled: not line for line (the test can fail)" not cov same "$tmp/p16.csv" "$tmp/s16.csv" 1e-7

# Points: every point, by its index in the input; after a rejection round
# those kept.
"$dba" solve "$p16" -q --covariance "$tmp/c.csv" --point-covariance "$tmp/p16p.csv" >/dev/null 2>&1
check "problem-16 points: one line per point, positive definite" cov points "$tmp/p16p.csv" 22106
"$dba" solve "$p16" -q --reject-outliers 2 --covariance "$tmp/c.csv" --point-covariance "$tmp/p16k.csv" \
  --report "$tmp/p16k.json" >/dev/null 2>&1
kept=$(/usr/bin/python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); print(d["outlier_rejection"]["rounds"][-1]["points_left"])' "$tmp/p16k.json" 2>/dev/null || echo 0)
check "problem-16 points after rejection: the kept ones ($kept)" cov points "$tmp/p16k.csv" "$kept"
check "problem-16 points after rejection: fewer than loaded" test "$kept" -lt 22106 -a "$kept" -gt 20000
# A point left with one observation: its line empty, counted; the rest
# computed (the point absorbs its observation).
bzcat "$p16" | /usr/bin/python3 -c '
import sys
lines = sys.stdin.read().split("\n")
c, p, o = map(int, lines[0].split())
obs = lines[1:1 + o]
seven = [x for x in obs if x.split()[1] == "7"]
keep = [x for x in obs if x.split()[1] != "7" or x == seven[0]]
print("\n".join([f"{c} {p} {len(keep)}"] + keep + lines[1 + o:]))' >"$tmp/p16_one.txt"
"$dba" solve "$tmp/p16_one.txt" -q --covariance "$tmp/c.csv" --point-covariance "$tmp/one.csv" \
  --report "$tmp/one.json" >/dev/null 2>&1
check "a point seen once: exits 0" test $? -eq 0
check "a point seen once: its line empty, the others positive definite" cov points "$tmp/one.csv" 22106 7
check "a point seen once: counted in the report" json "$tmp/one.json" "d['covariance']['undetermined_points'] == 1"
check "a point seen once: the images' blocks valid" cov valid "$tmp/c.csv" 16 inner
# An image left with two observations (4 equations, 9 unknowns): marked
# undetermined, named, the rest computed.
bzcat "$p16" | /usr/bin/python3 -c '
import sys
from collections import Counter
lines = sys.stdin.read().split("\n")
c, p, o = map(int, lines[0].split())
obs = lines[1:1 + o]
track = Counter(x.split()[1] for x in obs)
kept, keep = 0, []
for x in obs:
    if x.split()[0] == "3" and (kept == 2 or track[x.split()[1]] < 3):
        continue
    kept += x.split()[0] == "3"
    keep.append(x)
print("\n".join([f"{c} {p} {len(keep)}"] + keep + lines[1 + o:]))' >"$tmp/p16_cam.txt"
"$dba" solve "$tmp/p16_cam.txt" --covariance "$tmp/cam.csv" --report "$tmp/cam.json" >"$tmp/out" 2>&1
check "an image seen twice: exits 0" test $? -eq 0
check "an image seen twice: marked undetermined" cov held "$tmp/cam.csv" 3 undetermined
check "an image seen twice: the others valid" cov valid "$tmp/cam.csv" 16 inner
check "an image seen twice: in the report" json "$tmp/cam.json" "d['covariance']['undetermined_images'] == ['3']"
check "an image seen twice: said" contains "$tmp/out" "1 image(s) the data do not determine (first: 3"
# --ply-colour sigma: each point on the ramp by its sigma, sqrt(trace/3):
# the largest red, the smallest blue, the colours not the heights'.
"$dba" solve "$p16" -q --covariance "$tmp/c.csv" --point-covariance "$tmp/ps.csv" --ply "$tmp/s.ply" \
  --ply-colour sigma >/dev/null 2>&1
check "--ply-colour sigma: exits 0" test $? -eq 0
check "--ply-colour sigma: red at the largest sigma, blue at the smallest" /usr/bin/python3 -c '
import csv, math, struct, sys
data = open(sys.argv[1], "rb").read()
head, body = data.split(b"end_header\n", 1)
n = int(head.split(b"element vertex ")[1].split()[0])
rgb = [struct.unpack_from("<3d3B", body, 27 * k)[3:] for k in range(n)]
rows = list(csv.reader(open(sys.argv[2])))[1:]
assert len(rows) == n == 22106, (len(rows), n)
sigma = [math.sqrt((float(r[4]) + float(r[7]) + float(r[9])) / 3) for r in rows]
top, low = max(range(n), key=sigma.__getitem__), min(range(n), key=sigma.__getitem__)
assert rgb[top] == (255, 0, 0) and rgb[low] == (0, 0, 255), (rgb[top], rgb[low])
assert len(set(rgb)) > 100' "$tmp/s.ply" "$tmp/ps.csv"
"$dba" solve "$p16" -q --covariance "$tmp/c.csv" --ply "$tmp/s2.ply" --ply-colour sigma >"$tmp/out" 2>&1
check "--ply-colour sigma without --point-covariance: exit 2" test $? -eq 2
check "--ply-colour sigma without --point-covariance: said" contains "$tmp/out" \
  "--ply-colour sigma needs --point-covariance"
check "--ply-colour sigma without --point-covariance: nothing written" test ! -e "$tmp/s2.ply"
"$dba" solve "$p16" -q --point-covariance "$tmp/x.csv" >"$tmp/out" 2>&1
check "--point-covariance alone: says what it needs" contains "$tmp/out" "--point-covariance needs --covariance"
mpirun_n 2 "$dba" solve "$p16" -q --rcs gather --covariance "$tmp/c2.csv" --point-covariance "$tmp/p2.csv" >"$tmp/out" 2>&1
check "--point-covariance on 2 ranks: refused" test $? -ne 0
check "--point-covariance on 2 ranks: said" contains "$tmp/out" "--point-covariance: one process only"

# COLMAP: images by name; one held image leaves the scale (inner), two
# hold the frame (absolute).
m6=$data/colmap/mithunnallana_6img/sparse/0
"$dba" solve "$m6" -q --covariance "$tmp/m6.csv" >/dev/null 2>&1
check "mithunnallana: 6 named images, inner" cov valid "$tmp/m6.csv" 6 inner
check "mithunnallana: named as in the model" contains "$tmp/m6.csv" "l-537.jpg,inner,"
"$dba" solve "$m6" -q --covariance "$tmp/m6.csv" --report "$tmp/m6.json" >/dev/null 2>&1
check "mithunnallana: the intrinsics' sigmas and correlations in the report" json "$tmp/m6.json" \
  "d['covariance']['intrinsics'][0]['parameters'] == ['f', 'k'] and d['covariance']['intrinsics'][0]['sigma'][0] > 0 and \
   abs(d['covariance']['intrinsics'][0]['correlation'][0][0] - 1) < 1e-12"
"$dba" solve "$m6" -q --fix-images l-115.jpg --covariance "$tmp/m6a.csv" >/dev/null 2>&1
check "one held image: inner" cov valid "$tmp/m6a.csv" 6 inner
check "one held image: marked held" cov held "$tmp/m6a.csv" l-115.jpg
"$dba" solve "$m6" -q --fix-images l-115.jpg,l-537.jpg --covariance "$tmp/m6b.csv" >/dev/null 2>&1
check "two held images: absolute" cov valid "$tmp/m6b.csv" 6 absolute
check "two held images: both marked" cov held "$tmp/m6b.csv" l-537.jpg

# Georeferenced (priors and ground control): absolute; the control points'
# predicted sigma (unit scale) within their surveyed sigma, which they add to.
ex=$root/examples/georeferencing
"$dba" solve "$m6" -q --camera-priors "$ex/mithunnallana_6img.priors" --gcps "$ex/mithunnallana_6img.gcps" \
  --refine-principal-point --covariance "$tmp/geo.csv" --covariance-scale unit --report "$tmp/geo.json" >/dev/null 2>&1
check "georeferenced: absolute" cov valid "$tmp/geo.csv" 6 absolute
sigmas=$(awk '$NF == "control" {print $5, $6}' "$ex/mithunnallana_6img.gcps" | head -1)
check "georeferenced: the control points' predicted sigma, within the survey's ($sigmas)" json "$tmp/geo.json" \
  "len(d['covariance']['control_points']) == 3 and all(0 < p['sigma'][0] <= ${sigmas% *} and 0 < p['sigma'][2] <= ${sigmas#* } for p in d['covariance']['control_points'])"

# Priors along one straight strip hold the frame but the roll about it
# (only their noise would): named before the solve, nothing written; the
# whole survey's priors hold it.
"$dba" generate --model photo --images 100 --seed 3 "$tmp/s100.dba" --priors "$tmp/s100.txt" \
  --gnss-sigma 0.02,0.02 >/dev/null 2>&1
awk '!/^#/ && $3 < 5 {printf "%s %s %.4f %s %s %s\n", $1, $2, 0.01 * (NR % 3 - 1), 100, $5, $6}' \
  "$tmp/s100.txt" >"$tmp/strip.txt"
"$dba" solve "$tmp/s100.dba" -q --camera-priors "$tmp/strip.txt" --covariance "$tmp/strip.csv" \
  -o "$tmp/strip_out.dba" >"$tmp/out" 2>&1
check "priors along one strip: exit 2" test $? -eq 2
check "priors along one strip: the roll named" contains "$tmp/out" \
  "lie along one line (0.00813 m RMS off it, sigma 0.02 m): the rotation about it is free"
check "priors along one strip: nothing written" test ! -e "$tmp/strip.csv" -a ! -e "$tmp/strip_out.dba"
"$dba" solve "$tmp/s100.dba" -q --camera-priors "$tmp/s100.txt" --covariance "$tmp/all.csv" >/dev/null 2>&1
check "priors over the whole survey: absolute" cov valid "$tmp/all.csv" 100 absolute

# The analyse stage's factor in the memory estimate: under an address-space
# limit that leaves room for the solve but not the factor, refused before
# the solve (no cost printed) with what it needs, while the solve alone runs.
"$dba" generate --model photo --images 1000 --seed 2 "$tmp/s1000.dba" >/dev/null 2>&1
refused_up_front=0
for kb in 175000 200000 225000; do
  (ulimit -v "$kb"; "$dba" solve "$tmp/s1000.dba" --covariance "$tmp/lim.csv") >"$tmp/lim.out" 2>&1
  status=$?
  check "ulimit -v $kb: ends (status $status)" test "$status" -eq 0 -o "$status" -eq 1
  if [ "$status" -eq 1 ] && grep -q "the solve and --covariance need about" "$tmp/lim.out" \
      && ! grep -q "final cost" "$tmp/lim.out" && [ ! -e "$tmp/lim.csv" ] \
      && (ulimit -v "$kb"; "$dba" solve "$tmp/s1000.dba" -q) >/dev/null 2>&1; then
    refused_up_front=$((refused_up_front + 1))
  fi
done
check "the covariance's memory refused up front where the solve alone fits ($refused_up_front of 3)" \
  test "$refused_up_front" -ge 1

# A covariance that fails after the solve does not take the solve with it:
# the other outputs written (the report says why), no covariance file, exit 1.
DBA_INJECT_FAULT=0:covariance:1 "$dba" solve "$p16" -q --covariance "$tmp/f.csv" --point-covariance "$tmp/fp.csv" \
  -o "$tmp/f_out.txt" --report "$tmp/f.json" >"$tmp/out" 2>&1
check "a covariance failing after the solve: exit 1" test $? -eq 1
check "a covariance failing after the solve: said, the outputs written" contains "$tmp/out" \
  "injected fault (DBA_INJECT_FAULT=0:covariance:1) at covariance 1 (the solve's other outputs are written; no covariance file)"
check "a covariance failing after the solve: -o and --report written" test -s "$tmp/f_out.txt" -a -s "$tmp/f.json"
check "a covariance failing after the solve: no covariance files" test ! -e "$tmp/f.csv" -a ! -e "$tmp/fp.csv"
check "a covariance failing after the solve: the report says why" json "$tmp/f.json" \
  "'injected fault' in d['covariance']['error'] and d['final_cost'] > 0"

# Refused by name, nothing written.
"$dba" solve "$p16" -q --covariance "$p16" >"$tmp/out" 2>&1
check "the input as the covariance file: exit 2" test $? -eq 2
check "the input as the covariance file: named" contains "$tmp/out" "--covariance $p16 names INPUT"
"$dba" solve "$p16" -q -o "$tmp/o.txt" --covariance "$tmp/o.txt" >"$tmp/out" 2>&1
check "another output as the covariance file: exit 2" test $? -eq 2
"$dba" solve "$p16" -q --covariance "$tmp/same.csv" --point-covariance "$tmp/same.csv" >"$tmp/out" 2>&1
check "the covariance files on one path: exit 2" test $? -eq 2
check "the covariance files on one path: said" contains "$tmp/out" "name one file"
"$dba" solve "$p16" -q --covariance "$tmp" >"$tmp/out" 2>&1
check "a directory as the covariance file: exit 2" test $? -eq 2
"$dba" solve "$p16" -q --covariance '' >"$tmp/out" 2>&1
check "an empty covariance path: exit 2" test $? -eq 2
"$dba" solve "$p16" -q -o "$tmp/full_out.txt" --covariance /dev/full >"$tmp/out" 2>&1
check "a full disk under the covariance file: exit 1" test $? -eq 1
check "a full disk under the covariance file: said" contains "$tmp/out" "No space left on device"
check "a full disk under the covariance file: the other outputs not written" test ! -e "$tmp/full_out.txt"
"$dba" solve "$p16" -q --covariance-scale unit >"$tmp/out" 2>&1
check "--covariance-scale alone: exit 2" test $? -eq 2
check "--covariance-scale alone: says what it needs" contains "$tmp/out" "--covariance-scale needs --covariance"
"$dba" generate --model photo --rig stereo --images 40 --seed 2 "$tmp/rig.dba" >/dev/null 2>&1
"$dba" solve "$tmp/rig.dba" -q -o "$tmp/rig_out.dba" --covariance "$tmp/rig.csv" >"$tmp/out" 2>&1
check "a rig model: exit 2" test $? -eq 2
check "a rig model: said" contains "$tmp/out" "rig models are not supported yet"
check "a rig model: nothing written" test ! -e "$tmp/rig.csv" -a ! -e "$tmp/rig_out.dba"
finish
