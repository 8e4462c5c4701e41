#!/usr/bin/env bash
# The drop-in holds COLMAP's gauge (--gauge colmap, camera/gauge_hold.h):
# against the real COLMAP (Debian's colmap 3.8), `dba
# colmap-bundle-adjuster`'s centres overlay `colmap bundle_adjuster`'s to
# 1e-6 of their RMS spread on the two small shipped models, and on one
# whose images.txt lists them out of id order (COLMAP holds the first two
# the file lists, not the lowest ids). The first image's pose and the
# second's x translation are the input's. Without colmap the test fails
# and says why. Usage: cli_colmap_gauge.sh PATH_TO_DBA PROJECT_ROOT
set -uo pipefail
source "$(dirname "$0")/lib/check.sh"
dba=$1
root=$2
colmap_data=$root/../shared/data/colmap
need_shared "$colmap_data"
need_colmap
gauge() { /usr/bin/python3 "$root/tests/lib/gauge_check.py" "$@"; }
not_overlay() { ! gauge overlay "$1" "$2" 1e-6 2>/dev/null; }
# as_text MODEL OUT: the model as it is, in COLMAP's text form (no iteration,
# nothing moved).
as_text() { "$dba" solve "$1" -q --max-iterations 0 --gauge free -o "$2" --colmap-format text >/dev/null 2>&1; }
# listed MODEL: the image ids in the order images.txt lists them.
listed() { awk '!/^#/ && n++ % 2 == 0 {print $1}' "$1/images.txt"; }

# mithunnallana_6img with its images listed 3 5 1 6 2 4.
reordered=$tmp/reordered
mkdir -p "$reordered"
cp "$colmap_data/mithunnallana_6img/sparse/0/"{cameras,points3D}.txt "$reordered/"
/usr/bin/python3 - "$colmap_data/mithunnallana_6img/sparse/0/images.txt" "$reordered/images.txt" <<'PY'
import sys
lines = open(sys.argv[1]).read().split("\n")
head = [l for l in lines if l.startswith("#")]
body = [l for l in lines if l and not l.startswith("#")]
image = {body[i].split()[0]: body[i] + "\n" + body[i + 1] for i in range(0, len(body), 2)}
open(sys.argv[2], "w").write("\n".join(head + [image[k] for k in "351624"]) + "\n")
PY
check "the reordered model lists image 3 first and 5 second" test "$(listed "$reordered" | head -2 | paste -sd' ')" = "3 5"

for m in mithunnallana_6img statue_of_liberty_small_txt reordered; do
  model=$colmap_data/$m/sparse/0
  [ "$m" = reordered ] && model=$reordered
  mkdir -p "$tmp/$m.c" "$tmp/$m.d"
  colmap bundle_adjuster --input_path "$model" --output_path "$tmp/$m.c" >"$tmp/$m.c.log" 2>&1
  check "$m: colmap bundle_adjuster exits 0" test $? -eq 0
  "$dba" colmap-bundle-adjuster --input_path "$model" --output_path "$tmp/$m.d" >"$tmp/$m.d.log" 2>&1
  check "$m: dba colmap-bundle-adjuster exits 0" test $? -eq 0
  check "$m: the drop-in runs dba solve with --gauge colmap" contains "$tmp/$m.d.log" "--gauge colmap"
  as_text "$tmp/$m.c" "$tmp/$m.ct"
  as_text "$tmp/$m.d" "$tmp/$m.dt"  # the drop-in writes binary, as COLMAP 3.8 does
  as_text "$model" "$tmp/$m.in"
  check "$m: dba's centres overlay COLMAP's (1e-6 of their spread)" gauge overlay "$tmp/$m.ct" "$tmp/$m.dt" 1e-6
  read -r first second < <(listed "$model" | head -2 | paste -sd' ')
  check "$m: the first image listed ($first) keeps its pose, the second ($second) its x translation" \
    gauge colmap "$tmp/$m.in" "$tmp/$m.dt" "$first" "$second"
  check "$m: ... as COLMAP's do" gauge colmap "$tmp/$m.in" "$tmp/$m.ct" "$first" "$second"
done
check "the summary names COLMAP's gauge by image id" \
  contains "$tmp/reordered.d.log" "gauge held by       COLMAP's: image 3's pose and image 5's x translation"

# dba solve's default gauge (the centres' mean) is another frame: the
# overlay can fail.
"$dba" solve "$colmap_data/statue_of_liberty_small_txt/sparse/0" -q --max-iterations 100 \
  --function-tolerance 0 --gradient-tolerance 0 --parameter-tolerance 0 -o "$tmp/hold" >/dev/null 2>&1
check "the held gauge does not overlay COLMAP's (the test can fail)" \
  not_overlay "$tmp/statue_of_liberty_small_txt.ct" "$tmp/hold"
finish
