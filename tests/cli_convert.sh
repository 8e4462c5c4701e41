#!/usr/bin/env bash
# `dba convert` and `dba info`: BAL -> binary -> BAL is lossless (the solver
# sees the same problem), info prints the counts, bad input is refused.
# Usage: cli_convert.sh PATH_TO_DBA PROJECT_ROOT
set -uo pipefail
source "$(dirname "$0")/lib/check.sh"
dba=$1
root=$2
data=$root/../shared/data/bal
need_shared "$data"

"$dba" convert "$data/problem-49-7776-pre.txt.bz2" "$tmp/p.dba" >/dev/null; check "convert to binary" test $? -eq 0
"$dba" convert "$tmp/p.dba" "$tmp/p.txt" >/dev/null; check "convert back to text" test $? -eq 0
"$dba" convert "$tmp/p.txt" "$tmp/p2.dba" >/dev/null
check "binary -> text -> binary is byte-identical" cmp -s "$tmp/p.dba" "$tmp/p2.dba"
bzcat "$data/problem-49-7776-pre.txt.bz2" | head -1 >"$tmp/header"
check "text keeps the header" test "$(head -1 "$tmp/p.txt")" = "$(cat "$tmp/header")"
"$dba" solve "$tmp/p.dba" -q --max-iterations 0 >"$tmp/s1"
check "solver reads binary at the same initial cost" grep -q "initial cost        8.509125e+05" "$tmp/s1"

"$dba" info "$tmp/p.dba" >"$tmp/info"; check "info exits 0" test $? -eq 0
for want in "cameras       49" "points        7776" "observations  31843" "track length" "RCS in BSMC" \
            "dba solve's peak memory" "dense solver"; do
  check "info shows '$want'" grep -qF "$want" "$tmp/info"
done

check "info shows the BAL model" grep -qF "model         BAL" "$tmp/info"
# The camera graph (from the RCS's pattern when its rows are the cameras, else
# built apart): problem-49's figures, and a COLMAP model's, whose RCS has its
# intrinsic groups' rows too.
check "info's camera graph of problem-49" \
  grep -qF "cameras sharing a point with a camera   min 29  mean 39.9  max 48" "$tmp/info"
"$dba" info "$root/../shared/data/colmap/statue_of_liberty_small_txt/sparse/0" >"$tmp/info_statue" 2>&1
check "info's camera graph of a COLMAP model" \
  grep -qF "cameras sharing a point with a camera   min 20  mean 35.9  max 39" "$tmp/info_statue"
check "info's RCS of the COLMAP model: its images' and groups' rows" \
  grep -qF "RCS: 41 block rows, 242 unknowns" "$tmp/info_statue"

differ() { ! cmp -s "$1" "$2"; }

# --shuffle SEED: the same problem renumbered (the same initial cost, the
# same final cost to rounding), the same seed the same bytes, another seed
# other bytes; a COLMAP input is refused (its ids are its own).
"$dba" convert "$tmp/p.dba" "$tmp/s1.dba" --shuffle 7 >"$tmp/sconv"; check "shuffle exits 0" test $? -eq 0
check "shuffle says so" grep -q "(renumbered at random)" "$tmp/sconv"
"$dba" convert "$tmp/p.dba" "$tmp/s2.dba" --shuffle 7 >/dev/null
"$dba" convert "$tmp/p.dba" "$tmp/s3.dba" --shuffle 8 >/dev/null
check "shuffle: the same seed, the same bytes" cmp -s "$tmp/s1.dba" "$tmp/s2.dba"
check "shuffle: another seed, other bytes" differ "$tmp/s1.dba" "$tmp/s3.dba"
check "shuffle: other bytes than the input" differ "$tmp/s1.dba" "$tmp/p.dba"
"$dba" solve "$tmp/s1.dba" -q --max-iterations 0 >"$tmp/s1log"
check "shuffled: the same initial cost" grep -q "initial cost        8.509125e+05" "$tmp/s1log"
"$dba" solve "$tmp/p.dba" -q -t 2 --linear-solver dense --report "$tmp/po.json" >/dev/null
"$dba" solve "$tmp/s1.dba" -q -t 2 --linear-solver dense --report "$tmp/ps.json" >/dev/null
check "shuffled: the same final cost (1e-9)" json "$tmp/ps.json" \
  "near(d['final_cost'], $(json_value "$tmp/po.json" final_cost), 1e-9)"
"$dba" convert "$root/tests/data/colmap_models/PINHOLE/text" "$tmp/colmap_shuffled" --shuffle 1 >"$tmp/err" 2>&1
check "shuffle of a COLMAP model: exit 2" test $? -eq 2
check "shuffle of a COLMAP model: says why" grep -q "apply to a BAL or .dba input" "$tmp/err"
check "shuffle of a COLMAP model: nothing written" test ! -e "$tmp/colmap_shuffled"

# A photogrammetric .dba: info shows the model and groups; it converts to
# .dba (byte-identical) but not to BAL text.
"$dba" generate "$tmp/photo.dba" --model photo --images 40 --cameras 3 --seed 5 >/dev/null
"$dba" info "$tmp/photo.dba" >"$tmp/pinfo"; check "photo info exits 0" test $? -eq 0
for want in "model         photogrammetric" "images        40" "intrinsic groups  3"; do
  check "photo info shows '$want'" grep -qF "$want" "$tmp/pinfo"
done
"$dba" convert "$tmp/photo.dba" "$tmp/photo2.dba" >"$tmp/pconv"; check "photo .dba -> .dba" test $? -eq 0
check "photo .dba -> .dba is byte-identical" cmp -s "$tmp/photo.dba" "$tmp/photo2.dba"
check "photo convert names the groups" grep -q "40 images, 3 intrinsic groups" "$tmp/pconv"
"$dba" convert "$tmp/photo.dba" "$tmp/photo.txt" >"$tmp/err" 2>&1; check "photo -> BAL text exits 2 (arguments that do not fit the input)" test $? -eq 2
check "photo -> BAL text says why" grep -q "cannot hold shared intrinsics, so it converts to .dba only" "$tmp/err"
check "no BAL text from photo" test ! -e "$tmp/photo.txt"

printf 'DBAPROB\nshort' >"$tmp/trunc.dba"
"$dba" convert "$tmp/trunc.dba" "$tmp/out.txt" >"$tmp/err" 2>&1; check "truncated binary exits 1" test $? -eq 1
check "truncated binary is named" grep -q "trunc.dba: truncated" "$tmp/err"
check "no output after failure" test ! -e "$tmp/out.txt"
"$dba" convert >/dev/null 2>&1; check "convert without arguments exits 2" test $? -eq 2
"$dba" convert --help >"$tmp/help"; check "convert --help" grep -q "losslessly" "$tmp/help"


# COLMAP models: to a COLMAP directory every value as read (binary byte for
# byte, text idempotent), in either form, and to a .dba in their own lens
# models (a fixture of every COLMAP camera model, tests/data/colmap_models).
fixtures="$root/tests/data/colmap_models"
for model in OPENCV FULL_OPENCV RAD_TAN_THIN_PRISM_FISHEYE EQUIRECTANGULAR; do
  "$dba" convert "$fixtures/$model/binary" "$tmp/cm_$model" >/dev/null 2>&1
  check "convert $model binary -> binary exits 0" test $? -eq 0
  check "$model: binary byte for byte" cmp -s "$tmp/cm_$model/cameras.bin" "$fixtures/$model/binary/cameras.bin"
  check "$model: points3D byte for byte" cmp -s "$tmp/cm_$model/points3D.bin" "$fixtures/$model/binary/points3D.bin"
  "$dba" convert "$fixtures/$model/text" "$tmp/ct_$model" >/dev/null 2>&1
  "$dba" convert "$tmp/ct_$model" "$tmp/ct2_$model" >/dev/null 2>&1
  check "$model: text idempotent" cmp -s "$tmp/ct_$model/cameras.txt" "$tmp/ct2_$model/cameras.txt"
  "$dba" convert "$fixtures/$model/binary" "$tmp/cb_$model" --colmap-format text >/dev/null 2>&1
  check "$model: binary -> text is the text fixture's cameras" cmp -s "$tmp/cb_$model/cameras.txt" "$tmp/ct_$model/cameras.txt"
  "$dba" convert "$fixtures/$model/binary" "$tmp/cm_$model.dba" >/dev/null 2>&1
  check "$model -> .dba exits 0" test $? -eq 0
  "$dba" info "$tmp/cm_$model.dba" >"$tmp/cm_info" 2>&1
  check "$model .dba holds its lens model" grep -q "^    $model " "$tmp/cm_info"
done
"$dba" convert "$fixtures/OPENCV/binary" "$tmp/cm_OPENCV" --colmap-format text >"$tmp/err" 2>&1
check "a COLMAP output that would be shadowed is refused" grep -q "other form" "$tmp/err"
"$dba" convert "$fixtures/OPENCV/binary" "$tmp/cm.txt" >"$tmp/err" 2>&1
check "COLMAP to BAL text is refused" grep -q "cannot hold shared intrinsics" "$tmp/err"

# dba info reads a COLMAP model directory like any problem.
"$dba" info "$fixtures/OPENCV/binary" >"$tmp/info" 2>&1
check "info on a COLMAP model exits 0" test $? -eq 0
check "info names it a COLMAP model" grep -q "(COLMAP model)" "$tmp/info"
check "info gives its lens model" grep -q "OPENCV" "$tmp/info"


# info's refusals: the exit status and what was wrong, before the usage.
for bad in ":2:missing FILE" "--bogus:2:unknown option '--bogus'" "a b:2:one FILE, not 2 arguments" \
           "$tmp/none.txt:1:$tmp/none.txt: cannot open"; do
  args=${bad%%:*}; rest=${bad#*:}; status=${rest%%:*}; says=${rest#*:}
  "$dba" info $args >"$tmp/ierr" 2>&1
  check "info $args: exit $status" test $? -eq "$status"
  check "info $args: says '$says'" grep -qF -- "$says" "$tmp/ierr"
done
"$dba" info '' >"$tmp/ierr" 2>&1
check "info '': exit 2, as other empty values" test $? -eq 2
check "info '': says so, then the usage" grep -qF -- "dba info: an empty path names no file" "$tmp/ierr"
check "info '': ... then the usage" grep -qF -- "Usage: dba info FILE" "$tmp/ierr"
# A multi-block .bz2 (bzip2 -1: 100 kB blocks) is decoded and parsed on
# every thread: info says what it says of the text, on 1 thread and 3; a
# flipped byte in a middle block is refused naming file, line and the
# block's bytes, and so is the file cut short.
bzcat "$data/problem-49-7776-pre.txt.bz2" >"$tmp/p49.txt"
bzip2 -1 -c "$tmp/p49.txt" >"$tmp/p49.bz2"
"$dba" info "$tmp/p49.txt" | tail -n +2 | grep -v "peak memory" >"$tmp/info_txt"
for t in 1 3; do
  OMP_NUM_THREADS=$t "$dba" info "$tmp/p49.bz2" | tail -n +2 | grep -v "peak memory" >"$tmp/info_bz2"
  check "info on a multi-block .bz2, $t threads, as on its text" cmp -s "$tmp/info_txt" "$tmp/info_bz2"
done
size=$(stat -c %s "$tmp/p49.bz2")
mid=$((size / 2))
cp "$tmp/p49.bz2" "$tmp/flipped.bz2"
byte=$(od -An -tu1 -j "$mid" -N1 "$tmp/p49.bz2" | tr -d ' ')
printf "\\$(printf %o $(((byte + 1) % 256)))" | dd of="$tmp/flipped.bz2" bs=1 seek="$mid" conv=notrunc 2>/dev/null
check "the flipped file differs in one byte" test "$(cmp -l "$tmp/p49.bz2" "$tmp/flipped.bz2" | wc -l)" -eq 1
"$dba" info "$tmp/flipped.bz2" >"$tmp/ierr" 2>&1
check "info on a flipped byte: exit 1" test $? -eq 1
check "info on a flipped byte names file, line and block" \
  grep -qE "^dba info: error: $tmp/flipped.bz2:[0-9]+: corrupt bzip2 data in the block at bytes [0-9]+-[0-9]+ \(checksum or format error\)$" "$tmp/ierr"
from=$(sed -E 's/.*bytes ([0-9]+)-([0-9]+).*/\1/' "$tmp/ierr")
to=$(sed -E 's/.*bytes ([0-9]+)-([0-9]+).*/\2/' "$tmp/ierr")
check "the block named holds the flipped byte ($from <= $mid < $to)" test "$from" -le "$mid" -a "$mid" -lt "$to"
head -c "$mid" "$tmp/p49.bz2" >"$tmp/cut.bz2"
"$dba" info "$tmp/cut.bz2" >"$tmp/ierr" 2>&1
check "info on a .bz2 cut short: exit 1" test $? -eq 1
check "info on a .bz2 cut short says so" \
  grep -qE "$tmp/cut.bz2:[0-9]+: truncated bzip2 data: the file ends inside the block at byte [0-9]+$" "$tmp/ierr"

printf '2 1 2\n0 0 1.0 2.0\n1 0 1.0 2.5' >"$tmp/cut_info.txt"
"$dba" info "$tmp/cut_info.txt" >"$tmp/ierr" 2>&1
check "info on a cut file: exit 1, file and line" test $? -eq 1
check "info on a cut file says so" grep -qF "$tmp/cut_info.txt:3: the file ends inside this line" "$tmp/ierr"

finish
