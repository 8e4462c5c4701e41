#!/usr/bin/env bash
# Distributed runs against the single-process run: on every BAL problem in
# ../shared/data/bal, `mpirun -np N dba solve` for N = 1..4 with both point
# partitions reaches the single-process final cost to 1e-9 relative; so do
# COLMAP models in the photogrammetric model (shared and per-image
# intrinsics, fixed images and intrinsics) and a generated photogrammetric
# .dba read by the ranks themselves, and rigs (a .dba and a COLMAP model).
# These compare the distributed
# arithmetic, so they run with an explicitly exact linear solve (the dense
# factorization, which gathers the RCS on rank 0): with inexact PCG steps
# runs differ by up to 1e-5. The RCS spread over the ranks (the default with
# PCG) is checked against one process with a tight PCG solve (1e-9) and
# with the defaults (1e-5), BAL and photogrammetric with fixings. Then a
# failing rank (injected fault) and bad input must end the whole job quickly
# with a clear message, a non-zero status and no output file.
# Usage: mpi_solve.sh PATH_TO_DBA PROJECT_ROOT
set -uo pipefail
dba=$1
root=$2
source "$(dirname "$0")/lib/need_shared.sh"
need_shared "$root/../shared/data/bal" "$root/../shared/data/colmap"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mpirun_n() { local n=$1; shift; timeout -k 10 300 mpirun --allow-run-as-root --oversubscribe --bind-to none -np "$n" "$@"; }
source "$root/tests/lib/json.sh"
final_cost() { json_value "$1" final_cost; }
initial_cost() { json_value "$1" initial_cost; }
tight=(--linear-solver dense)
passes=0
failures=0
fail() { echo "FAILED: $*" >&2; failures=$((failures + 1)); }

# Every rank count and both partitions over the problems (the i-th problem
# with 1 + i mod 4 and 1 + (i + 2) mod 4 ranks, partitions alternating), not
# their whole cross product: each rank count meets each partition.
i=0
for problem in "$root"/../shared/data/bal/*.bz2; do
  name=$(basename "$problem")
  "$dba" solve "$problem" -q "${tight[@]}" --report "$tmp/single.json" >/dev/null || { fail "$name single process"; continue; }
  single=$(final_cost "$tmp/single.json")
  partitions=(equal cameras); [ $((i % 2)) -eq 1 ] && partitions=(cameras equal)
  for run in 0 1; do
    n=$((1 + (i + 2 * run) % 4)); partition=${partitions[$run]}
    if ! mpirun_n "$n" "$dba" solve "$problem" -q "${tight[@]}" --partition "$partition" \
         --report "$tmp/mpi.json" >"$tmp/mpi.out" 2>&1; then
      fail "$name -np $n --partition $partition exited non-zero"; cat "$tmp/mpi.out" >&2; continue
    fi
    distributed=$(final_cost "$tmp/mpi.json")
    if awk -v a="$single" -v b="$distributed" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= 1e-9 * a) }'; then
      passes=$((passes + 1))
      echo "ok   $name -np $n --partition $partition: $distributed (single $single)"
    else
      fail "$name -np $n --partition $partition: final cost $distributed, single process $single"
    fi
  done
  i=$((i + 1))
done

# The RCS spread over the ranks (--rcs distributed, the default with more
# than one rank): reduce-scatter to the rows' owners, PCG across the ranks
# with the distributed two-level preconditioner. With a tight PCG solve the
# final cost matches one process's tight PCG solve to 1e-9 (1 to 4 ranks,
# both partitions, the main rank forming or not); with the defaults, to 1e-5.
# Tight runs stop after 10 LM iterations, one process's as the ranks': each
# iteration is the same arithmetic, and the 33 to the optimum take 15,000
# jacobi-preconditioned PCG iterations, each a halo exchange and reductions
# that cost 30 s on 3 ranks sharing 2 cores with a compiler.
pcg_tight=(--linear-solver pcg --eta 0 --pcg-tolerance 1e-12 --max-iterations 10)
problem=$root/../shared/data/bal/problem-49-7776-pre.txt.bz2
"$dba" solve "$problem" -q "${pcg_tight[@]}" --report "$tmp/dist_single.json" >/dev/null
"$dba" solve "$problem" -q --report "$tmp/dist_single_defaults.json" >/dev/null
check_distributed() {  # LABEL SINGLE_JSON REL NP ARGS...
  local label=$1 single=$2 rel=$3 n=$4; shift 4
  if ! mpirun_n "$n" "$dba" solve "$@" -q --report "$tmp/dist.json" </dev/null >"$tmp/dist.out" 2>&1; then
    fail "$label exited non-zero"; cat "$tmp/dist.out" >&2; return
  fi
  if ! grep -q "\"rcs\": \"${expect_rcs:-distributed}\"" "$tmp/dist.json" && [ "$n" -gt 1 ]; then
    fail "$label: the RCS was not ${expect_rcs:-distributed}"; return
  fi
  if awk -v a="$(final_cost "$single")" -v b="$(final_cost "$tmp/dist.json")" -v r="$rel" \
       'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= r * a) }'; then
    passes=$((passes + 1)); echo "ok   $label: $(final_cost "$tmp/dist.json") (single $(final_cost "$single"))"
  else
    fail "$label: final cost $(final_cost "$tmp/dist.json"), single process $(final_cost "$single")"
  fi
}
# Every rank count, both partitions on two ranks.
for run in "1 cameras" "2 equal" "2 cameras" "3 cameras" "4 equal"; do
  read -r n partition <<<"$run"
  check_distributed "distributed RCS, BAL 49, tight, -np $n --partition $partition" \
    "$tmp/dist_single.json" 1e-9 "$n" "$problem" "${pcg_tight[@]}" --rcs distributed --partition "$partition"
done
for n in 2 4; do
  check_distributed "distributed RCS, BAL 49, defaults, -np $n" "$tmp/dist_single_defaults.json" 1e-5 "$n" "$problem"
done
# Auto's mixed product drops its damping floor on every rank (the SOLVE
# command's flag): started under the floor, as a resumed solve may be, from
# 8 iterations into BAL 49, the product is double from LM iteration 1 and
# the ranks reach one process's optimum (1e-5).
"$dba" solve "$problem" -q --max-iterations 8 -o "$tmp/p49_8.txt" >/dev/null
below_floor=(--linear-solver pcg --initial-lambda 1e-8)
"$dba" solve "$tmp/p49_8.txt" -q "${below_floor[@]}" --report "$tmp/floor1.json" >/dev/null
for n in 2 3; do
  check_distributed "distributed RCS, BAL 49, damping floor dropped, -np $n" "$tmp/floor1.json" 1e-5 \
    "$n" "$tmp/p49_8.txt" "${below_floor[@]}"
  if grep -q '"pcg_double_from_iteration": 1,' "$tmp/dist.json" &&
     grep -q '"pcg_double_from_iteration": 1,' "$tmp/floor1.json"; then
    passes=$((passes + 1)); echo "ok   damping floor dropped from LM iteration 1, -np $n and one process"
  else
    fail "damping floor, -np $n: $(grep -o '"pcg_double_from_iteration": [0-9]*' "$tmp/dist.json" "$tmp/floor1.json")"
  fi
done
# An explicit --pcg-precision mixed keeps its floor, on the ranks too.
if mpirun_n 2 "$dba" solve "$tmp/p49_8.txt" -q "${below_floor[@]}" --pcg-precision mixed --max-iterations 3 \
     --report "$tmp/mixed.json" >"$tmp/mixed.out" 2>&1 &&
   grep -q '"pcg_double_from_iteration": 0,' "$tmp/mixed.json"; then
  passes=$((passes + 1)); echo "ok   --pcg-precision mixed keeps the damping floor, -np 2"
else
  fail "--pcg-precision mixed, -np 2: $(grep -o '"pcg_double_from_iteration": [0-9]*' "$tmp/mixed.json")"; cat "$tmp/mixed.out" >&2
fi
check_distributed "distributed RCS, BAL 49, tight, -np 3, main rank coordinates only" \
  "$tmp/dist_single.json" 1e-9 3 "$problem" "${pcg_tight[@]}" --main-rank coordinates
check_distributed "distributed RCS, BAL 49, tight, -np 3, block-Jacobi" \
  "$tmp/dist_single.json" 1e-9 3 "$problem" "${pcg_tight[@]}" --preconditioner jacobi
# The photogrammetric model, with fixed images and intrinsics.
statue=$root/../shared/data/colmap/statue_of_liberty_small_txt/sparse/0
statue_fix=(--fix-intrinsics cx,cy --fix-images 1,7)
"$dba" solve "$statue" -q "${pcg_tight[@]}" "${statue_fix[@]}" --report "$tmp/statue1.json" </dev/null >/dev/null 2>&1 \
  || fail "statue single process"
"$dba" solve "$statue" -q "${statue_fix[@]}" --report "$tmp/statue1d.json" </dev/null >/dev/null 2>&1 \
  || fail "statue single process, defaults"
for n in 2 3; do
  for partition in equal cameras; do
    check_distributed "distributed RCS, COLMAP statue, fixed parameters, tight, -np $n --partition $partition" \
      "$tmp/statue1.json" 1e-9 "$n" "$statue" "${pcg_tight[@]}" "${statue_fix[@]}" --partition "$partition"
  done
  check_distributed "distributed RCS, COLMAP statue, fixed parameters, defaults, -np $n" \
    "$tmp/statue1d.json" 1e-5 "$n" "$statue" "${statue_fix[@]}"
done
# The gathered RCS on request, and the combinations the distributed one refuses.
expect_rcs=gather check_distributed "gathered RCS on request, BAL 49, tight, -np 2" \
  "$tmp/dist_single.json" 1e-9 2 "$problem" "${pcg_tight[@]}" --rcs gather
"$dba" solve "$problem" -q --rcs distributed --linear-solver dense >"$tmp/refuse.out" 2>&1
status=$?
if [ "$status" -eq 2 ] && grep -q "needs --rcs gather" "$tmp/refuse.out"; then
  passes=$((passes + 1))
else
  fail "--rcs distributed --linear-solver dense: status $status, $(cat "$tmp/refuse.out")"
fi

# From a binary file every rank reads its own points: same result.
problem=$root/../shared/data/bal/problem-49-7776-pre.txt.bz2
"$dba" convert "$problem" "$tmp/p49.dba" >/dev/null
"$dba" solve "$problem" -q "${tight[@]}" --report "$tmp/single.json" >/dev/null
for n in 2 3; do
  for partition in equal cameras; do
    mpirun_n "$n" "$dba" solve "$tmp/p49.dba" -q "${tight[@]}" --partition "$partition" --report "$tmp/bin.json" >/dev/null 2>&1 \
      || fail "binary input -np $n --partition $partition exited non-zero"
    if awk -v a="$(final_cost "$tmp/single.json")" -v b="$(final_cost "$tmp/bin.json")" \
         'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= 1e-9 * a) }'; then
      passes=$((passes + 1)); echo "ok   binary input -np $n --partition $partition"
    else
      fail "binary input -np $n --partition $partition: $(final_cost "$tmp/bin.json") vs $(final_cost "$tmp/single.json")"
    fi
  done
done

# Binary in, binary out: the result streams through without re-reading.
mpirun_n 2 "$dba" solve "$tmp/p49.dba" -q "${tight[@]}" -o "$tmp/p49.out.dba" --report "$tmp/bin_out.json" >/dev/null 2>&1 \
  || fail "binary output under mpirun exited non-zero"
"$dba" solve "$tmp/p49.out.dba" -q "${tight[@]}" --max-iterations 0 --report "$tmp/bin_reread.json" >/dev/null
if awk -v a="$(final_cost "$tmp/bin_out.json")" -v b="$(final_cost "$tmp/bin_reread.json")" \
     'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= 1e-9 * a) }'; then
  passes=$((passes + 1))
else
  fail "binary output does not hold the adjusted parameters"
fi

# Each rank estimates its memory before its RCS's values exist: the reports
# carry it, near the rank's measured peak (the figures: bench/README.md).
if python3 - "$tmp/bin_out.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
ranks = d["distributed"]["ranks"]
ok = len(ranks) == 2 and all(0.5 < r["memory_estimate_bytes"] / r["peak_memory_bytes"] < 2 for r in ranks)
ok = ok and d["memory"]["estimate"]["total_bytes"] == ranks[0]["memory_estimate_bytes"]
sys.exit(0 if ok else 1)
PY
then
  passes=$((passes + 1))
else
  fail "the ranks' memory estimates are missing or far from their peaks"
fi

# The photogrammetric model (COLMAP input): poses and intrinsic groups spread
# over the ranks, fixed parameters included.
colmap=$root/../shared/data/colmap
same_cost() { awk -v a="$(final_cost "$1")" -v b="$(final_cost "$2")" \
                'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= 1e-9 * a) }'; }
while read -r model n partition args; do
  # shellcheck disable=SC2086
  "$dba" solve "$colmap/$model/sparse/0" -q "${tight[@]}" $args --report "$tmp/c1.json" </dev/null >/dev/null 2>&1 \
    || { fail "$model $args single process"; continue; }
  # shellcheck disable=SC2086
  if mpirun_n "$n" "$dba" solve "$colmap/$model/sparse/0" -q "${tight[@]}" $args --partition "$partition" \
       --report "$tmp/cn.json" </dev/null >"$tmp/cn.out" 2>&1 && same_cost "$tmp/c1.json" "$tmp/cn.json"; then
    passes=$((passes + 1)); echo "ok   $model $args -np $n --partition $partition: $(final_cost "$tmp/cn.json")"
  else
    fail "$model $args -np $n --partition $partition: $(final_cost "$tmp/cn.json") vs $(final_cost "$tmp/c1.json")"
    cat "$tmp/cn.out" >&2
  fi
done <<EOF2  # (mpirun reads stdin: every command in the loop reads /dev/null)
mithunnallana_6img 2 equal --intrinsics per-image
mithunnallana_6img 3 cameras --intrinsics per-image
mithunnallana_6img 2 cameras --intrinsics shared
statue_of_liberty_small_txt 2 cameras --fix-intrinsics cx,cy --fix-images 1,7
statue_of_liberty_small_txt 3 equal --fix-intrinsics cx,cy --fix-images 1,7
fountain_p11 3 cameras --fix-images 1
EOF2
# A COLMAP model written by a distributed run re-reads at its final cost.
mpirun_n 2 "$dba" solve "$colmap/mithunnallana_6img/sparse/0" -q "${tight[@]}" -o "$tmp/colmap_out" \
  --colmap-format binary --report "$tmp/co.json" --ply "$tmp/mpi.ply" >/dev/null 2>&1 || fail "COLMAP output under mpirun"
mpirun_n 2 "$dba" solve "$colmap/mithunnallana_6img/sparse/0" -q "${tight[@]}" -o "$tmp/colmap_text_out" \
  --ply "$tmp/mpi_text.ply" >/dev/null 2>&1 || fail "COLMAP text output under mpirun"
if ply_matches_points3d "$tmp/mpi_text.ply" "$tmp/colmap_text_out/points3D.txt"; then
  passes=$((passes + 1)); echo "ok   PLY of a distributed run holds the adjusted points and colours"
else
  fail "PLY of a distributed run does not match its points3D.txt"
fi
"$dba" solve "$tmp/colmap_out" -q "${tight[@]}" --max-iterations 0 --report "$tmp/co_reread.json" >/dev/null 2>&1
if test -s "$tmp/colmap_out/images.bin" && \
   awk -v a="$(final_cost "$tmp/co.json")" -v b="$(initial_cost "$tmp/co_reread.json")" \
     'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= 1e-9 * a) }'; then
  passes=$((passes + 1))
else
  fail "COLMAP output of a distributed run does not hold the adjusted parameters"
fi
# A photogrammetric .dba (poses, shared intrinsic groups): every rank reads its
# points and the whole camera side; same result as one process, the binary
# output holds it, and the ground truth is compared per group.
"$dba" generate "$tmp/photo.dba" --model photo --images 60 --cameras 2 --seed 4 \
  --truth "$tmp/photo.truth.dba" >/dev/null
"$dba" solve "$tmp/photo.dba" -q "${tight[@]}" --report "$tmp/photo_single.json" >/dev/null
for n in 2 3; do
  for partition in equal cameras; do
    mpirun_n "$n" "$dba" solve "$tmp/photo.dba" -q "${tight[@]}" --partition "$partition" --truth "$tmp/photo.truth.dba" \
      -o "$tmp/photo.out.dba" --report "$tmp/photo_mpi.json" >"$tmp/photo.out" 2>&1 \
      || { fail "photo -np $n --partition $partition exited non-zero"; cat "$tmp/photo.out" >&2; continue; }
    "$dba" solve "$tmp/photo.out.dba" -q "${tight[@]}" --max-iterations 0 --report "$tmp/photo_reread.json" >/dev/null
    if awk -v a="$(final_cost "$tmp/photo_single.json")" -v b="$(final_cost "$tmp/photo_mpi.json")" \
           -v c="$(initial_cost "$tmp/photo_reread.json")" \
         'BEGIN { d = a - b; if (d < 0) d = -d; e = b - c; if (e < 0) e = -e; exit !(d <= 1e-9 * a && e <= 1e-9 * a) }' \
       && grep -q "intrinsics 1 .*error f" "$tmp/photo.out"; then
      passes=$((passes + 1)); echo "ok   photo .dba -np $n --partition $partition"
    else
      fail "photo .dba -np $n --partition $partition: $(final_cost "$tmp/photo_mpi.json") vs $(final_cost "$tmp/photo_single.json")"
    fi
  done
done

# Rigs (docs/design.md §1.7): frames are the camera rows and a sensor shares
# its group's row; a stereo .dba read by the ranks and the same survey as a
# COLMAP model with a rig of two cameras (shares sent by rank 0), and the
# .dba with GNSS priors on its frames (a lever arm given) and control points,
# reach one process's final cost, tight (1e-9), and with the defaults (1e-5).
"$dba" generate "$tmp/rig.dba" --model photo --rig stereo --images 120 --seed 4 \
  --priors "$tmp/rig_gnss.txt" --gnss-sigma 0.05,0.05 --lever-arm 0.1,0.2,-0.3 \
  --gcps "$tmp/rig_gcps.txt" --control-points 4 --check-points 2 >/dev/null
PYTHONPATH="$(dirname "$dba")/python" /usr/bin/python3 "$root/tests/lib/rig_to_colmap.py" "$tmp/rig.dba" 2 "$tmp/rigm"
for input in rig.dba rigm rig.dba+gnss; do
  geo=()
  [ "$input" = rig.dba+gnss ] && geo=(--camera-priors "$tmp/rig_gnss.txt" --lever-arm 0.1,0.2,-0.3 --gcps "$tmp/rig_gcps.txt")
  file=${input%+gnss}
  "$dba" solve "$tmp/$file" -q "${geo[@]}" "${tight[@]}" --report "$tmp/rig_single.json" >/dev/null
  "$dba" solve "$tmp/$file" -q "${geo[@]}" --report "$tmp/rig_single_default.json" >/dev/null
  for n in 1 2 3; do
    for mode in tight default; do
      extra=("${tight[@]}"); reference=rig_single.json; tolerance=1e-9
      [ "$mode" = default ] && { extra=(); reference=rig_single_default.json; tolerance=1e-5; }
      mpirun_n "$n" "$dba" solve "$tmp/$file" -q "${geo[@]}" "${extra[@]}" --report "$tmp/rig_mpi.json" >"$tmp/rig.out" 2>&1 \
        || { fail "rigs $input -np $n $mode exited non-zero"; cat "$tmp/rig.out" >&2; continue; }
      if awk -v a="$(final_cost "$tmp/$reference")" -v b="$(final_cost "$tmp/rig_mpi.json")" -v t="$tolerance" \
           'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= t * a) }'; then
        passes=$((passes + 1)); echo "ok   rigs $input -np $n $mode"
      else
        fail "rigs $input -np $n $mode: $(final_cost "$tmp/rig_mpi.json") vs $(final_cost "$tmp/$reference")"
      fi
    done
  done
done
# --rig-geometry fixed and fixed:1 (by sensor): the ranks that read their
# own shares hold the same sensors as the main rank, so 3 iterations of a
# dense solve end where one process's do (1e-9, tight).
for g in fixed fixed:1; do
  "$dba" solve "$tmp/rig.dba" -q --rig-geometry "$g" "${tight[@]}" --max-iterations 3 \
    --report "$tmp/rig_g1.json" >/dev/null 2>&1
  mpirun_n 2 "$dba" solve "$tmp/rig.dba" -q --rig-geometry "$g" "${tight[@]}" --max-iterations 3 \
    --report "$tmp/rig_g2.json" >/dev/null 2>&1 || fail "rigs --rig-geometry $g -np 2 exited non-zero"
  if awk -v a="$(final_cost "$tmp/rig_g1.json")" -v b="$(final_cost "$tmp/rig_g2.json")" \
       'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= 1e-9 * a) }' &&
     [ "$(json_value "$tmp/rig_g2.json" camera_unknowns)" = 366 ]; then
    passes=$((passes + 1)); echo "ok   rigs --rig-geometry $g -np 2"
  else
    fail "rigs --rig-geometry $g -np 2: $(final_cost "$tmp/rig_g2.json") vs $(final_cost "$tmp/rig_g1.json")"
  fi
done
# A refined lever arm over ranks: its 3 unknowns are the last row of the RCS,
# gathered on the main rank (its row meets every frame's; auto gathers), and
# 2 and 3 ranks end where one process ends: cost and lever arm to 1e-9, tight.
lever=(--camera-priors "$tmp/rig_gnss.txt" --gcps "$tmp/rig_gcps.txt" --refine-lever-arm "${tight[@]}")
"$dba" solve "$tmp/rig.dba" -q "${lever[@]}" --report "$tmp/lever1.json" >/dev/null 2>&1 \
  || fail "a refined lever arm, one process"
lever_single=$(json "$tmp/lever1.json" 'd["camera_priors"]["lever_arm_refined"]' &&
  python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); print(repr([d["final_cost"]] + d["camera_priors"]["lever_arm"]))' "$tmp/lever1.json")
for n in 2 3; do
  mpirun_n "$n" "$dba" solve "$tmp/rig.dba" -q "${lever[@]}" --report "$tmp/lever_mpi.json" >"$tmp/rig.out" 2>&1 \
    || { fail "a refined lever arm -np $n exited non-zero: $(cat "$tmp/rig.out")"; continue; }
  if [ -n "$lever_single" ] && json "$tmp/lever_mpi.json" "all(near(a, b, 1e-9) for a, b in zip([d['final_cost']] + d['camera_priors']['lever_arm'], $lever_single)) and d['distributed']['rcs'] == 'gather'"; then
    passes=$((passes + 1)); echo "ok   a refined lever arm -np $n ends where one process ends"
  else
    fail "a refined lever arm -np $n: $(json_value "$tmp/lever_mpi.json" final_cost) vs $lever_single"
  fi
done
status=0
mpirun_n 2 "$dba" solve "$tmp/rig.dba" -q --camera-priors "$tmp/rig_gnss.txt" --refine-lever-arm \
  --rcs distributed >"$tmp/rig.out" 2>&1 || status=$?
if [ "$status" = 2 ] && grep -qF -- "--rcs distributed does not hold a refined lever arm" "$tmp/rig.out"; then
  passes=$((passes + 1)); echo "ok   a refined lever arm in an RCS spread over ranks is refused by name"
else
  fail "a refined lever arm with --rcs distributed is not refused: $(cat "$tmp/rig.out")"
fi

# A FOV camera started inside COLMAP's series branch (camera/fov_series_start.h):
# every rank that reads the .dba starts its omega where the main rank does,
# so the initial and final costs are one process's.
mkdir -p "$tmp/fov"
cp "$root/../shared/data/colmap/statue_of_liberty_small_txt/sparse/0/"{images,points3D}.txt "$tmp/fov/"
echo "1 FOV 800 1200 2395.65 2395.65 400 600 0.001" >"$tmp/fov/cameras.txt"
"$dba" convert "$tmp/fov" "$tmp/fov.dba" >/dev/null 2>&1
"$dba" solve "$tmp/fov.dba" -q "${tight[@]}" --report "$tmp/fov_single.json" >/dev/null 2>&1
mpirun_n 3 "$dba" solve "$tmp/fov.dba" -q "${tight[@]}" --report "$tmp/fov_mpi.json" >/dev/null 2>&1 \
  || fail "FOV .dba -np 3 exited non-zero"
if same_cost "$tmp/fov_single.json" "$tmp/fov_mpi.json" &&
   awk -v a="$(initial_cost "$tmp/fov_single.json")" -v b="$(initial_cost "$tmp/fov_mpi.json")" \
     -v f="$(final_cost "$tmp/fov_single.json")" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= 1e-12 * a && f < 8200) }'; then
  passes=$((passes + 1)); echo "ok   FOV from omega 0.001, .dba read by 3 ranks"
else
  fail "FOV .dba -np 3: initial $(initial_cost "$tmp/fov_mpi.json") vs $(initial_cost "$tmp/fov_single.json"), final $(final_cost "$tmp/fov_mpi.json") vs $(final_cost "$tmp/fov_single.json")"
fi

# Fixings given on the command line apply on every rank that reads the file.
fix=(--fix-images 0,7 --fix-intrinsics cx,cy)
"$dba" solve "$tmp/photo.dba" -q "${tight[@]}" "${fix[@]}" --report "$tmp/fix_single.json" >"$tmp/fix.out" 2>&1
mpirun_n 2 "$dba" solve "$tmp/photo.dba" -q "${tight[@]}" "${fix[@]}" --report "$tmp/fix_mpi.json" >/dev/null 2>&1 \
  || fail "photo .dba with fixings -np 2 exited non-zero"
if same_cost "$tmp/fix_single.json" "$tmp/fix_mpi.json" && \
   ! same_cost "$tmp/fix_single.json" "$tmp/photo_single.json"; then
  passes=$((passes + 1)); echo "ok   photo .dba with fixings -np 2"
else
  fail "photo .dba with fixings: $(final_cost "$tmp/fix_mpi.json") vs $(final_cost "$tmp/fix_single.json")"
fi

# Lens models with tangential, high-order and fisheye terms (.dba version 3,
# read by the ranks themselves): 1 and 4 ranks reach the same optimum with
# the default options (1e-5: inexact PCG steps), and a fixing by name applies
# on every rank. A COLMAP model in FULL_OPENCV, handed out by rank 0, matches
# one process to 1e-9 with the exact solve.
within() {  # within A B REL: |A - B| <= REL * A
  awk -v a="$1" -v b="$2" -v r="$3" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= r * a) }'
}
for spec in "OPENCV" "FULL_OPENCV 100" "OPENCV_FISHEYE 120" "BROWN 90"; do
  read -r model fov <<<"$spec"
  "$dba" generate "$tmp/lens.dba" --model photo --camera-model "$model" ${fov:+--field-of-view "$fov"} \
    --images 60 --cameras 2 --seed 6 >/dev/null || { fail "generate $model"; continue; }
  "$dba" solve "$tmp/lens.dba" -q --fix-intrinsics 1:cx --report "$tmp/lens1.json" >/dev/null 2>&1 \
    || { fail "$model single process exited non-zero"; continue; }
  mpirun_n 4 "$dba" solve "$tmp/lens.dba" -q --fix-intrinsics 1:cx --report "$tmp/lens4.json" \
    >"$tmp/lens.out" 2>&1 || { fail "$model -np 4 exited non-zero"; cat "$tmp/lens.out" >&2; continue; }
  if within "$(final_cost "$tmp/lens1.json")" "$(final_cost "$tmp/lens4.json")" 1e-5; then
    passes=$((passes + 1)); echo "ok   $model .dba -np 4 (defaults): $(final_cost "$tmp/lens4.json") (single $(final_cost "$tmp/lens1.json"))"
  else
    fail "$model .dba -np 4: $(final_cost "$tmp/lens4.json") vs single $(final_cost "$tmp/lens1.json")"
  fi
done
mkdir -p "$tmp/full_opencv"
cp "$root/../shared/data/colmap/mithunnallana_6img/sparse/0/"*.txt "$tmp/full_opencv/"
sed -i 's/^1 SIMPLE_RADIAL 1280 720 \([^ ]*\) \([^ ]*\) \([^ ]*\) \([^ \r]*\)\r\?$/1 FULL_OPENCV 1280 720 \1 \1 \2 \3 \4 0 0 0 0 0 0 0/' \
  "$tmp/full_opencv/cameras.txt"
"$dba" solve "$tmp/full_opencv" -q "${tight[@]}" --report "$tmp/fo1.json" >/dev/null 2>&1 || fail "FULL_OPENCV COLMAP single process"
mpirun_n 3 "$dba" solve "$tmp/full_opencv" -q "${tight[@]}" --report "$tmp/fo3.json" >/dev/null 2>&1 \
  || fail "FULL_OPENCV COLMAP -np 3 exited non-zero"
if grep -q "FULL_OPENCV" "$tmp/full_opencv/cameras.txt" && \
   within "$(final_cost "$tmp/fo1.json")" "$(final_cost "$tmp/fo3.json")" 1e-9; then
  passes=$((passes + 1)); echo "ok   FULL_OPENCV COLMAP -np 3"
else
  fail "FULL_OPENCV COLMAP -np 3: $(final_cost "$tmp/fo3.json") vs $(final_cost "$tmp/fo1.json")"
fi

# Camera priors: rank 0 computes their terms and sends each to the owner of
# its camera's row (the RCS spread over the ranks, the default), or adds it
# to the gathered RCS (--rcs gather). A BAL text survey on 1 and 4 ranks and
# a photogrammetric .dba on 2 and 4 ranks (georeferenced, rank 0 reads
# either, aligns it onto the priors and hands it out): the same optimum with
# defaults (1e-5). With a tight solve, 2 and 3 ranks spread, and 2 gathered,
# reach one process's cost to 1e-9 on both (the photo survey with its
# first image fixed: a prior on a fixed camera adds only its cost).
"$dba" generate "$tmp/gnss.txt" --images 80 --seed 8 --priors "$tmp/gnss.priors" --gnss-outliers 0.05 >/dev/null
"$dba" solve "$tmp/gnss.txt" -q --camera-priors "$tmp/gnss.priors" --report "$tmp/gnss1.json" >/dev/null 2>&1 \
  || fail "BAL with priors, one process"
mpirun_n 4 "$dba" solve "$tmp/gnss.txt" -q --camera-priors "$tmp/gnss.priors" --report "$tmp/gnss3.json" \
  >"$tmp/gnss.out" 2>&1 || { fail "BAL with priors -np 4 exited non-zero"; cat "$tmp/gnss.out" >&2; }
"$dba" generate "$tmp/gnssp.dba" --model photo --images 80 --cameras 2 --seed 8 --priors "$tmp/gnssp.priors" >/dev/null
mpirun_n 2 "$dba" solve "$tmp/gnssp.dba" -q --camera-priors "$tmp/gnssp.priors" --report "$tmp/gnssp2.json" >/dev/null 2>&1 \
  || fail "photo .dba with priors -np 2 exited non-zero"
mpirun_n 4 "$dba" solve "$tmp/gnssp.dba" -q --camera-priors "$tmp/gnssp.priors" --report "$tmp/gnssp3.json" >/dev/null 2>&1 \
  || fail "photo .dba with priors -np 4 exited non-zero"
if within "$(final_cost "$tmp/gnss1.json")" "$(final_cost "$tmp/gnss3.json")" 1e-5 && \
   within "$(final_cost "$tmp/gnssp2.json")" "$(final_cost "$tmp/gnssp3.json")" 1e-5 && \
   json "$tmp/gnss3.json" "d['camera_priors']['flagged'] == $(python3 -c "import json; print(json.load(open('$tmp/gnss1.json'))['camera_priors']['flagged'])")"; then
  passes=$((passes + 1)); echo "ok   camera priors: BAL -np 1 and 4, photo .dba -np 2 and 4"
else
  fail "camera priors: $(final_cost "$tmp/gnss3.json") vs $(final_cost "$tmp/gnss1.json"); $(final_cost "$tmp/gnssp3.json") vs $(final_cost "$tmp/gnssp2.json")"
fi

"$dba" solve "$tmp/gnss.txt" -q --camera-priors "$tmp/gnss.priors" "${pcg_tight[@]}" \
  --report "$tmp/gnss_tight1.json" >/dev/null 2>&1 || fail "BAL with priors, tight, one process"
gnssp_tight=(--camera-priors "$tmp/gnssp.priors" --fix-images 0 "${pcg_tight[@]}")
"$dba" solve "$tmp/gnssp.dba" -q "${gnssp_tight[@]}" --report "$tmp/gnssp_tight1.json" >/dev/null 2>&1 \
  || fail "photo .dba with priors, tight, one process"
for n in 2 3; do
  check_distributed "camera priors, BAL, RCS spread, tight, -np $n" "$tmp/gnss_tight1.json" 1e-9 "$n" \
    "$tmp/gnss.txt" --camera-priors "$tmp/gnss.priors" "${pcg_tight[@]}"
  check_distributed "camera priors, photo .dba, first image fixed, RCS spread, tight, -np $n" \
    "$tmp/gnssp_tight1.json" 1e-9 "$n" "$tmp/gnssp.dba" "${gnssp_tight[@]}"
done
expect_rcs=gather check_distributed "camera priors, BAL, RCS gathered, tight, -np 2" \
  "$tmp/gnss_tight1.json" 1e-9 2 "$tmp/gnss.txt" --camera-priors "$tmp/gnss.priors" "${pcg_tight[@]}" --rcs gather

# Ground control: control points are points with a prior, in whichever
# rank's share they fall; with GNSS priors too, on an unaligned survey, 1, 2
# and 4 ranks reach the same optimum (1e-5) and the same check points; with
# outlier rejection on 2 ranks, one process's rounds and optimum.
"$dba" generate "$tmp/gcp.dba" --model photo --images 120 --cameras 2 --seed 9 --unaligned --outliers 0.02 \
  --priors "$tmp/gcp.priors" --gcps "$tmp/gcp.txt" --control-points 6 --check-points 6 >/dev/null
# Cauchy loss: with the squared loss the 2% mismatches keep this block from
# converging in 100 iterations, and runs that end at the iteration limit
# compare unconverged costs (1e-5 apart from rounding alone). Its scale at
# 2 px, above the 1.3 px noise: at 1 px half the inliers sit beyond it, the
# model (√ρ' only, as Ceres's for every concave loss) converges linearly
# (347 iterations to a tight optimum) and the default stop lands 2.9e-5
# above it after 27 (one process), so runs stopped 3e-5 apart; at 2 px the
# default stop is 2.5e-6 from it (11 of 94 iterations).
geo=(--camera-priors "$tmp/gcp.priors" --gcps "$tmp/gcp.txt" --loss cauchy --loss-scale 2)
"$dba" solve "$tmp/gcp.dba" -q "${geo[@]}" --report "$tmp/gcp1.json" >/dev/null 2>&1 || fail "ground control, one process"
# With rejection, the defaults' costs agree to 1e-5, and the check points
# are compared after solves to 1e-8: this Cauchy solve converges linearly
# (14 iterations by default, 94 to a tight optimum without rejection), so
# default runs stop 2-3 mm apart in the check points.
reject=(--reject-outliers 4)
tight_reject=(--reject-outliers 4 --function-tolerance 1e-8)
"$dba" solve "$tmp/gcp.dba" -q "${geo[@]}" "${reject[@]}" --report "$tmp/gcpr1.json" >/dev/null 2>&1 \
  || fail "ground control with rejection, one process"
"$dba" solve "$tmp/gcp.dba" -q "${geo[@]}" "${tight_reject[@]}" --report "$tmp/gcprt1.json" >/dev/null 2>&1 \
  || fail "ground control with rejection to 1e-8, one process"
for n in 2 4; do
  mpirun_n "$n" "$dba" solve "$tmp/gcp.dba" -q "${geo[@]}" --report "$tmp/gcp$n.json" >"$tmp/gcp.out" 2>&1 \
    || { fail "ground control -np $n exited non-zero"; cat "$tmp/gcp.out" >&2; }
done
mpirun_n 2 "$dba" solve "$tmp/gcp.dba" -q "${geo[@]}" "${reject[@]}" --report "$tmp/gcpr2.json" \
  >"$tmp/gcp.out" 2>&1 || { fail "ground control with rejection -np 2 exited non-zero"; cat "$tmp/gcp.out" >&2; }
mpirun_n 2 "$dba" solve "$tmp/gcp.dba" -q "${geo[@]}" "${tight_reject[@]}" --report "$tmp/gcprt2.json" \
  >"$tmp/gcp.out" 2>&1 || { fail "ground control with rejection to 1e-8 -np 2 exited non-zero"; cat "$tmp/gcp.out" >&2; }
same_checks() {  # the check points' figures of two reports agree to 1 mm
  json "$1" "d['check_points']['count'] == 6 and abs(d['check_points']['rms_3d'] - $(python3 -c "import json; print(json.load(open('$2'))['check_points']['rms_3d'])")) < 1e-3"
}
if within "$(final_cost "$tmp/gcp1.json")" "$(final_cost "$tmp/gcp2.json")" 1e-5 && \
   within "$(final_cost "$tmp/gcp1.json")" "$(final_cost "$tmp/gcp4.json")" 1e-5 && \
   within "$(final_cost "$tmp/gcpr1.json")" "$(final_cost "$tmp/gcpr2.json")" 1e-5 && \
   within "$(final_cost "$tmp/gcprt1.json")" "$(final_cost "$tmp/gcprt2.json")" 1e-7 && \
   same_checks "$tmp/gcp4.json" "$tmp/gcp1.json" && same_checks "$tmp/gcprt2.json" "$tmp/gcprt1.json" && \
   json "$tmp/gcp4.json" "d['control_points']['count'] == 6 and d['num_points'] == $(json_value "$tmp/gcp1.json" num_points)"; then
  passes=$((passes + 1)); echo "ok   ground control: -np 1, 2 and 4; with rejection -np 1 and 2"
else
  fail "ground control: $(final_cost "$tmp/gcp1.json"), $(final_cost "$tmp/gcp2.json"), $(final_cost "$tmp/gcp4.json"); rejection $(final_cost "$tmp/gcpr1.json") vs $(final_cost "$tmp/gcpr2.json"), to 1e-8 $(final_cost "$tmp/gcprt1.json") vs $(final_cost "$tmp/gcprt2.json")"
fi

# Outlier rejection, distributed: each rank drops from its own points what
# one process drops, so with the same first optimum the rounds, the true
# outliers caught, the final cost (1e-9) and what is written (the points and
# observations left) are one process's. A photogrammetric .dba with 5%
# mismatches read by the ranks themselves, a BAL text problem handed out by
# the main rank, and a COLMAP model (its 2D-3D links and points left).
"$dba" generate "$tmp/outl.dba" --model photo --images 80 --cameras 2 --seed 5 --outliers 0.05 \
  --truth "$tmp/outl.truth.dba" >/dev/null
"$dba" generate "$tmp/outl.txt" --images 40 --seed 7 --outliers 0.02 --truth "$tmp/outl.truth.txt" >/dev/null
for input in "$tmp/outl.dba" "$tmp/outl.txt"; do
  name=$(basename "$input")
  ext=${name##*.}
  truth=${input%.*}.truth.$ext
  reject=(--loss cauchy --reject-outliers 4 --truth "$truth")
  "$dba" solve "$input" -q "${tight[@]}" "${reject[@]}" -o "$tmp/rej1.$ext" --report "$tmp/rej1.json" \
    >/dev/null 2>&1 || fail "$name --reject-outliers, one process, exited non-zero"
  "$dba" solve "$tmp/rej1.$ext" -q --max-iterations 0 --report "$tmp/rej1_out.json" >/dev/null 2>&1
  for n in 2 3; do
    if ! mpirun_n "$n" "$dba" solve "$input" -q "${tight[@]}" "${reject[@]}" -o "$tmp/rejn.$ext" \
         --report "$tmp/rejn.json" >"$tmp/rej.out" 2>&1; then
      fail "$name --reject-outliers -np $n exited non-zero"; cat "$tmp/rej.out" >&2; continue
    fi
    "$dba" solve "$tmp/rejn.$ext" -q --max-iterations 0 --report "$tmp/rejn_out.json" >/dev/null 2>&1
    if python3 - "$tmp/rej1.json" "$tmp/rejn.json" "$tmp/rej1_out.json" "$tmp/rejn_out.json" <<'PY'
import json, sys
a, b, ao, bo = (json.load(open(f)) for f in sys.argv[1:])
near = lambda x, y: abs(x - y) <= 1e-9 * abs(x)
ok = (near(a["final_cost"], b["final_cost"])
      and a["outlier_rejection"]["rounds"] == b["outlier_rejection"]["rounds"]
      and a["true_outliers"] == b["true_outliers"]
      and a["outlier_rejection"]["rounds"][0]["observations_dropped"] > 0
      and (ao["num_points"], ao["num_observations"]) == (bo["num_points"], bo["num_observations"])
      and near(ao["initial_cost"], bo["initial_cost"]))
sys.exit(0 if ok else 1)
PY
    then
      passes=$((passes + 1)); echo "ok   $name --reject-outliers -np $n: one process's rounds, cost and output"
    else
      fail "$name --reject-outliers -np $n differs from one process: $(cat "$tmp/rej.out")"
    fi
  done
done
colmap_model=$colmap/mithunnallana_6img/sparse/0
rm -rf "$tmp/rejc1" "$tmp/rejc3"
"$dba" solve "$colmap_model" -q "${tight[@]}" --reject-outliers 1 -o "$tmp/rejc1" >/dev/null 2>&1
mpirun_n 3 "$dba" solve "$colmap_model" -q "${tight[@]}" --reject-outliers 1 -o "$tmp/rejc3" >/dev/null 2>&1 \
  || fail "COLMAP --reject-outliers -np 3 exited non-zero"
links() { grep -v '^#' "$1/images.txt" | awk 'NR % 2 == 0' | tr ' ' '\n' | awk 'NR % 3 == 0'; }
tracks() { grep -v '^#' "$1/points3D.txt" | awk '{ printf "%s %d\n", $1, (NF - 8) / 2 }'; }
if [ -s "$tmp/rejc3/points3D.txt" ] && [ "$(links "$tmp/rejc1")" = "$(links "$tmp/rejc3")" ] \
   && [ "$(tracks "$tmp/rejc1")" = "$(tracks "$tmp/rejc3")" ] \
   && [ "$(tracks "$tmp/rejc1" | wc -l)" -lt "$(grep -vc '^#' "$colmap_model/points3D.txt" 2>/dev/null || echo 1000000)" ]; then
  passes=$((passes + 1)); echo "ok   COLMAP --reject-outliers -np 3: the same links and tracks left"
else
  fail "COLMAP --reject-outliers -np 3: other links or tracks than one process"
fi

# Without --loss the ranks start robust as one process does (every rank
# parses the same options: cauchy at 2 PX), with the same rounds and cost;
# and the guard stops 2 ranks where it stops one (40% mismatches): exit 1,
# the same share in the message, nothing written.
"$dba" solve "$tmp/outl.dba" -q "${tight[@]}" --reject-outliers 4 --report "$tmp/rd1.json" >/dev/null 2>&1
if mpirun_n 2 "$dba" solve "$tmp/outl.dba" -q "${tight[@]}" --reject-outliers 4 --report "$tmp/rd2.json" \
     >"$tmp/rd.out" 2>&1 && python3 - "$tmp/rd1.json" "$tmp/rd2.json" <<'PY'
import json, sys
a, b = (json.load(open(f)) for f in sys.argv[1:])
sys.exit(0 if a["loss"] == b["loss"] == {"type": "cauchy", "scale_px": 8.0}
         and a["outlier_rejection"]["rounds"] == b["outlier_rejection"]["rounds"]
         and abs(a["final_cost"] - b["final_cost"]) <= 1e-9 * a["final_cost"] else 1)
PY
then
  passes=$((passes + 1)); echo "ok   --reject-outliers without --loss -np 2: one process's robust start, rounds and cost"
else
  fail "--reject-outliers without --loss -np 2 differs from one process: $(cat "$tmp/rd.out")"
fi
"$dba" generate "$tmp/outl40.dba" --model photo --images 80 --cameras 2 --seed 5 --outliers 0.4 >/dev/null
"$dba" solve "$tmp/outl40.dba" -q --reject-outliers 4 -o "$tmp/g1.dba" >"$tmp/g1.out" 2>&1
status1=$?
mpirun_n 2 "$dba" solve "$tmp/outl40.dba" -q --reject-outliers 4 -o "$tmp/g2.dba" >"$tmp/g2.out" 2>&1
status2=$?
share=$(grep -o 'would drop [0-9]* of [0-9]* observations ([0-9.]*%), more than --reject-max-share 0.25' "$tmp/g1.out")
if [ "$status1" = 1 ] && [ "$status2" = 1 ] && [ -n "$share" ] && grep -qF "$share" "$tmp/g2.out" \
   && [ ! -e "$tmp/g1.dba" ] && [ ! -e "$tmp/g2.dba" ]; then
  passes=$((passes + 1)); echo "ok   the guard stops 40% mismatches on 2 ranks as in one process: $share"
else
  fail "the guard on 2 ranks: exit $status1 and $status2, $(cat "$tmp/g1.out" "$tmp/g2.out")"
fi

# Checkpoint and resume, distributed: a 3-rank run killed (SIGKILL on rank 0)
# right after its second accepted iteration's checkpoint, resumed on 2 ranks
# and in one process, ends at the uninterrupted single-process cost (1e-9)
# after as many iterations; for a BAL text input (the main rank holds the
# problem) and a .dba the ranks read themselves (the fingerprint summed over
# the ranks). A checkpoint of another input is refused, nothing written.
for input in "$root/../shared/data/bal/problem-49-7776-pre.txt.bz2" "$tmp/photo.dba"; do
  name=$(basename "$input")
  "$dba" solve "$input" -q "${tight[@]}" --report "$tmp/ck_whole.json" >/dev/null 2>&1
  rm -f "$tmp/run.ckpt"
  DBA_KILL_AFTER_CHECKPOINT=2 mpirun_n 3 "$dba" solve "$input" -q "${tight[@]}" \
    --checkpoint "$tmp/run.ckpt" >"$tmp/ck.out" 2>&1 && fail "$name: the killed run exited 0"
  [ -s "$tmp/run.ckpt" ] || fail "$name: no checkpoint after the kill"
  for run in "mpirun_n 2 $dba" "$dba"; do
    $run solve "$input" -q "${tight[@]}" --resume "$tmp/run.ckpt" --report "$tmp/ck_resumed.json" \
      >"$tmp/ck.out" 2>&1 || { fail "$name: resume ($run) exited non-zero"; cat "$tmp/ck.out" >&2; continue; }
    if python3 - "$tmp/ck_whole.json" "$tmp/ck_resumed.json" <<'PY'
import json, sys
w, r = (json.load(open(f)) for f in sys.argv[1:])
ok = abs(w["final_cost"] - r["final_cost"]) <= 1e-9 * w["final_cost"] and \
     w["iterations"] == r["iterations"] and r["history"][0]["iteration"] == 3
sys.exit(0 if ok else 1)
PY
    then
      passes=$((passes + 1)); echo "ok   $name killed on 3 ranks, resumed ($run)"
    else
      fail "$name resumed ($run): $(final_cost "$tmp/ck_resumed.json") vs $(final_cost "$tmp/ck_whole.json")"
    fi
  done
done
# At the same rank count with a direct solver, bit for bit: killed after its
# third checkpoint and resumed, the outputs byte for byte the uninterrupted
# run's, with and without camera priors (whose alignment is not done again).
"$dba" generate "$tmp/ckp.dba" --model photo --images 60 --unaligned --priors "$tmp/ckp.priors" \
  --seed 5 >/dev/null
for priors in "" "--camera-priors $tmp/ckp.priors"; do
  mpirun_n 2 "$dba" solve "$tmp/ckp.dba" -q "${tight[@]}" $priors -o "$tmp/ckp_whole.dba" >/dev/null 2>&1
  rm -f "$tmp/ckp.ckpt"
  DBA_KILL_AFTER_CHECKPOINT=3 mpirun_n 2 "$dba" solve "$tmp/ckp.dba" -q "${tight[@]}" $priors \
    --checkpoint "$tmp/ckp.ckpt" >/dev/null 2>&1
  mpirun_n 2 "$dba" solve "$tmp/ckp.dba" -q "${tight[@]}" $priors --resume "$tmp/ckp.ckpt" \
    -o "$tmp/ckp_resumed.dba" >"$tmp/ck.out" 2>&1
  if cmp -s "$tmp/ckp_whole.dba" "$tmp/ckp_resumed.dba"; then
    passes=$((passes + 1)); echo "ok   killed on 2 ranks and resumed on 2 ${priors:+with priors }: the output byte for byte"
  else
    fail "killed on 2 ranks and resumed on 2 ${priors:+with priors}: another output"; cat "$tmp/ck.out" >&2
  fi
done
"$dba" convert "$root/../shared/data/bal/problem-49-7776-pre.txt.bz2" "$tmp/p49ck.dba" >/dev/null
mpirun_n 2 "$dba" solve "$tmp/p49ck.dba" -q "${tight[@]}" --resume "$tmp/run.ckpt" -o "$tmp/ck_wrong.dba" \
  >"$tmp/ck.out" 2>&1 && fail "a checkpoint of another input was resumed (-np 2, .dba)"
if grep -q "written for another input" "$tmp/ck.out" && [ ! -e "$tmp/ck_wrong.dba" ]; then
  passes=$((passes + 1)); echo "ok   a checkpoint of another input is refused (-np 2, .dba)"
else
  fail "a checkpoint of another input (-np 2, .dba): $(cat "$tmp/ck.out")"
fi

# With outlier rejection: a 2-rank run killed inside its second round's solve
# (after its 33rd checkpoint; 35 accepted steps in all) resumes in that round,
# on 2 ranks and in one process, with the same rounds, to the uninterrupted
# 2-rank run's final cost (1e-9; 4e-15 measured: not bit for bit, unlike a
# resume in the first round).
"$dba" generate "$tmp/ckrej.txt" --images 40 --seed 7 --outliers 0.02 >/dev/null
ckrej=(--loss cauchy --reject-outliers 4 "${tight[@]}")
mpirun_n 2 "$dba" solve "$tmp/ckrej.txt" -q "${ckrej[@]}" --checkpoint "$tmp/ckrej_whole.ckpt" \
  --report "$tmp/ckrej_whole.json" >"$tmp/ck.out" 2>&1 || fail "rejection with checkpoints -np 2 exited non-zero"
rm -f "$tmp/ckrej.ckpt"
DBA_KILL_AFTER_CHECKPOINT=33 mpirun_n 2 "$dba" solve "$tmp/ckrej.txt" -q "${ckrej[@]}" \
  --checkpoint "$tmp/ckrej.ckpt" >/dev/null 2>&1 && fail "rejection: the killed run exited 0"
for run in "mpirun_n 2 $dba" "$dba"; do
  $run solve "$tmp/ckrej.txt" -q "${ckrej[@]}" --resume "$tmp/ckrej.ckpt" --report "$tmp/ckrej_resumed.json" \
    >"$tmp/ck.out" 2>&1 || { fail "rejection: resume ($run) exited non-zero"; cat "$tmp/ck.out" >&2; continue; }
  if grep -q "of the solve after rejection round 1" "$tmp/ck.out" && python3 - "$tmp/ckrej_whole.json" "$tmp/ckrej_resumed.json" <<'PY'
import json, sys
w, r = (json.load(open(f)) for f in sys.argv[1:])
ok = abs(w["final_cost"] - r["final_cost"]) <= 1e-9 * w["final_cost"] and \
     len(w["outlier_rejection"]["rounds"]) == 2 and w["outlier_rejection"] == r["outlier_rejection"]
sys.exit(0 if ok else 1)
PY
  then
    passes=$((passes + 1)); echo "ok   rejection: killed on 2 ranks in round 2, resumed there ($run)"
  else
    fail "rejection: killed on 2 ranks, resumed ($run): $(final_cost "$tmp/ckrej_resumed.json") vs $(final_cost "$tmp/ckrej_whole.json")"
  fi
done

# The same with its cameras and points renumbered at random (dba convert
# --shuffle), handed out (BAL text) and read by the ranks (.dba): killed on 3
# ranks in the first solve (after checkpoint 3) and in the solve after the
# first round (after 33), resumed on 3 ranks, the uninterrupted run's cost
# to 1e-12 (the shares walked as in the uninterrupted run: by the walk
# taken at the load, or by each rank as read).
for ext in txt dba; do
  "$dba" convert "$tmp/ckrej.txt" "$tmp/ckrejs.$ext" --shuffle 5 >/dev/null
  mpirun_n 3 "$dba" solve "$tmp/ckrejs.$ext" -q "${ckrej[@]}" --report "$tmp/ckrejs_whole.json" \
    >"$tmp/ck.out" 2>&1 || { fail "shuffled .$ext with rejection -np 3 exited non-zero"; continue; }
  for kill in 3 33; do
    rm -f "$tmp/ckrejs.ckpt"
    DBA_KILL_AFTER_CHECKPOINT=$kill mpirun_n 3 "$dba" solve "$tmp/ckrejs.$ext" -q "${ckrej[@]}" \
      --checkpoint "$tmp/ckrejs.ckpt" >/dev/null 2>&1 && fail "shuffled .$ext: the run killed after $kill exited 0"
    mpirun_n 3 "$dba" solve "$tmp/ckrejs.$ext" -q "${ckrej[@]}" --resume "$tmp/ckrejs.ckpt" \
      --report "$tmp/ckrejs_resumed.json" >"$tmp/ck.out" 2>&1 \
      || { fail "shuffled .$ext: resume after $kill exited non-zero"; cat "$tmp/ck.out" >&2; continue; }
    if within "$(final_cost "$tmp/ckrejs_whole.json")" "$(final_cost "$tmp/ckrejs_resumed.json")" 1e-12; then
      passes=$((passes + 1)); echo "ok   shuffled .$ext with rejection: killed on 3 ranks after checkpoint $kill, resumed on 3"
    else
      fail "shuffled .$ext killed after $kill, resumed: $(final_cost "$tmp/ckrejs_resumed.json") vs $(final_cost "$tmp/ckrejs_whole.json")"
    fi
  done
done

# A robust loss: the distributed run reaches the single-process optimum of
# the robust cost (1e-9), both camera models, and differs from the squared
# loss's.
for input in "$root/../shared/data/bal/problem-21-11315-pre.txt.bz2" "$tmp/photo.dba"; do
  loss=(--loss cauchy --loss-scale 2)
  "$dba" solve "$input" -q "${tight[@]}" "${loss[@]}" --report "$tmp/loss_single.json" >/dev/null 2>&1 \
    || fail "robust single-process run of $input exited non-zero"
  mpirun_n 3 "$dba" solve "$input" -q "${tight[@]}" "${loss[@]}" --report "$tmp/loss_mpi.json" >/dev/null 2>&1 \
    || fail "robust -np 3 run of $input exited non-zero"
  "$dba" solve "$input" -q "${tight[@]}" --report "$tmp/squared_single.json" >/dev/null 2>&1
  if same_cost "$tmp/loss_single.json" "$tmp/loss_mpi.json" && \
     ! same_cost "$tmp/loss_single.json" "$tmp/squared_single.json" && \
     json "$tmp/loss_mpi.json" 'd["loss"]["type"] == "cauchy"'; then
    passes=$((passes + 1)); echo "ok   --loss cauchy -np 3 $(basename "$input")"
  else
    fail "--loss cauchy -np 3 $(basename "$input"): $(final_cost "$tmp/loss_mpi.json") vs $(final_cost "$tmp/loss_single.json")"
  fi
done

# The distributed summary reports every rank and the communication.
problem=$root/../shared/data/bal/problem-21-11315-pre.txt.bz2
mpirun_n 3 "$dba" solve "$problem" -q "${tight[@]}" --main-rank coordinates -o "$tmp/out3.txt" \
  --report "$tmp/r3.json" >"$tmp/out" 2>&1 || fail "-np 3 --main-rank coordinates"
for want in "rank 0 " "rank 1 " "rank 2 " "sub_rcs" "camera_update" "distribution" "coordinates only"; do
  if grep -qF -- "$want" "$tmp/out"; then passes=$((passes + 1)); else fail "summary lacks '$want'"; fi
done
if json "$tmp/r3.json" 'len(d["distributed"]["ranks"]) == 3 and len(d["distributed"]["communication_per_iteration"]) >= d["iterations"]' && test -s "$tmp/out3.txt"; then
  passes=$((passes + 1))
else
  fail "report or output of the distributed run missing"
fi
# The written result re-reads at the final cost of the run.
"$dba" solve "$tmp/out3.txt" -q "${tight[@]}" --max-iterations 0 --report "$tmp/reread.json" >/dev/null
if awk -v a="$(final_cost "$tmp/r3.json")" -v b="$(final_cost "$tmp/reread.json")" \
     'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= 1e-9 * a) }'; then
  passes=$((passes + 1))
else
  fail "distributed output does not hold the adjusted parameters"
fi

# A rank that fails stops the whole job: clear message naming the rank, non-zero
# status, no output; a job that hangs instead fails by the timeout (status
# 124; the healthy job takes seconds, so the limit is no timing claim).
mpirun_hang_guard() { local n=$1; shift; timeout -k 10 120 mpirun --allow-run-as-root --oversubscribe --bind-to none -np "$n" "$@"; }
DBA_INJECT_FAULT=2:3 mpirun_hang_guard 3 "$dba" solve "$problem" -q "${tight[@]}" -o "$tmp/fault.txt" >"$tmp/fault.out" 2>&1
status=$?
if [ "$status" -ne 0 ] && [ "$status" -ne 124 ] && grep -q "rank 2: error: injected fault" "$tmp/fault.out" \
   && [ ! -e "$tmp/fault.txt" ]; then
  passes=$((passes + 1))
else
  fail "injected fault on rank 2: status $status (124: it hung)"; cat "$tmp/fault.out" >&2
fi
# A fault at every protocol step, on the main rank and on another: reading a
# .dba share, formation, step evaluation, finish, end, and rank 0 writing after
# the solve. Each: non-zero status, "rank N: error: injected fault", no
# output, no hang (the guard's timeout).
"$dba" convert "$problem" "$tmp/faults.dba" >/dev/null
# (Not a rank other than 0 at `end`: there Open MPI's mpirun sometimes
# hangs, under load, after MPI_Abort of a rank whose peers have already
# finalized, even though every process has exited; seen with ctest -j8.)
for spec in 1:read:1 0:read:1 1:form:2 0:form:1 2:step:2 0:step:1 1:finish:1 0:finish:2 \
            0:end:1 0:write:1; do
  rank=${spec%%:*}
  rm -f "$tmp/fault.dba"
  DBA_INJECT_FAULT=$spec mpirun_hang_guard 3 "$dba" solve "$tmp/faults.dba" -q "${tight[@]}" \
    -o "$tmp/fault.dba" >"$tmp/fault.out" 2>&1
  status=$?
  if [ "$status" -ne 0 ] && [ "$status" -ne 124 ] && grep -q "rank $rank: error: injected fault" "$tmp/fault.out" \
     && [ ! -e "$tmp/fault.dba" ] && [ -z "$(ls "$tmp" | grep 'fault.dba.tmp')" ]; then
    passes=$((passes + 1)); echo "ok   injected fault $spec"
  else
    fail "injected fault $spec: status $status (124: it hung)"; cat "$tmp/fault.out" >&2
  fi
done
# Bad input read by the main rank stops every rank too.
printf '2 1 2\n0 0 1.0 2.0\n1 0 1.0 abc\n' >"$tmp/bad.txt"
mpirun_n 3 "$dba" solve "$tmp/bad.txt" -o "$tmp/bad_out.txt" >"$tmp/bad.out" 2>&1
status=$?
if [ "$status" -ne 0 ] && [ "$status" -ne 124 ] && grep -q "rank 0: error: .*bad.txt:3" "$tmp/bad.out" \
   && [ ! -e "$tmp/bad_out.txt" ]; then
  passes=$((passes + 1))
else
  fail "bad input under mpirun: status $status"; cat "$tmp/bad.out" >&2
fi

echo "$passes passed, $failures failed"
test "$failures" -eq 0
