#!/usr/bin/env bash
# Checkpoints: a solve killed (SIGKILL, right after its N-th checkpoint) and
# resumed ends where the uninterrupted solve ends, bit for bit with a direct
# solver (its outputs compared byte for byte) and to 1e-9 with a tight PCG
# solve: plain, with camera priors (whose alignment is not done again), with
# control points, with outlier rejection (killed inside a later round), with
# rigs and a refined lever arm, and
# resumed from the checkpoint of the step that ended the solve (no further
# iteration, however often). A checkpoint written with other priors, loss,
# rejection or rig geometry is refused naming what differs; a damaged one is
# refused.
# Usage: cli_checkpoints.sh PATH_TO_DBA PROJECT_ROOT
set -uo pipefail
source "$(dirname "$0")/lib/check.sh"
dba=$1
root=$2
p49=$root/data/problem-49-7776-pre.txt.bz2

# killed_and_resumed NAME N OUTPUT_EXT ARGS...: the uninterrupted solve of
# ARGS (with --checkpoint), then one killed after its N-th checkpoint and
# resumed: the same -o bytes, final cost and iteration count.
killed_and_resumed() {
  local name=$1 n=$2 ext=$3; shift 3
  local full=$tmp/$name.full$ext resumed=$tmp/$name.resumed$ext ckpt=$tmp/$name.ckpt
  "$dba" solve "$@" -q -t 2 --checkpoint "$tmp/$name.full.ckpt" -o "$full" \
    --report "$tmp/$name.full.json" >/dev/null 2>&1
  check "$name: the uninterrupted solve exits 0" test $? -eq 0
  DBA_KILL_AFTER_CHECKPOINT=$n "$dba" solve "$@" -q -t 2 --checkpoint "$ckpt" -o "$resumed" \
    >/dev/null 2>&1
  check "$name: killed after checkpoint $n" test $? -eq 137
  check "$name: no output from the killed run" test ! -e "$resumed"
  "$dba" solve "$@" -q -t 2 --resume "$ckpt" --checkpoint "$ckpt" -o "$resumed" \
    --report "$tmp/$name.resumed.json" >"$tmp/$name.log" 2>&1
  check "$name: the resume exits 0" test $? -eq 0
  check "$name: resumed, the same output bytes" cmp -s "$full" "$resumed"
  check "$name: resumed, the same final cost" test \
    "$(json_value "$tmp/$name.full.json" final_cost)" = "$(json_value "$tmp/$name.resumed.json" final_cost)"
  check "$name: resumed, the same termination" test \
    "$(json_value "$tmp/$name.full.json" termination)" = "$(json_value "$tmp/$name.resumed.json" termination)"
}

# Plain: killed early, and killed at its last checkpoint (the one written by
# the step that ended the solve).
"$dba" solve "$p49" -q -t 2 --report "$tmp/p49.json" >/dev/null 2>&1
accepted=$(json_value "$tmp/p49.json" accepted_iterations)
killed_and_resumed p49_early 2 .txt "$p49"
killed_and_resumed p49_last "$accepted" .txt "$p49"
check "p49_last: the resume takes no iteration" contains "$tmp/p49_last.log" "which had ended the solve"
check "p49_last: the same iteration count" test \
  "$(json_value "$tmp/p49_last.full.json" iterations)" = "$(json_value "$tmp/p49_last.resumed.json" iterations)"
# Resumed again from the checkpoint the resume left: still no iteration.
cp "$tmp/p49_last.ckpt" "$tmp/again.ckpt"
for k in 1 2; do
  "$dba" solve "$p49" -q -t 2 --resume "$tmp/again.ckpt" --checkpoint "$tmp/again.ckpt" \
    -o "$tmp/again.txt" --report "$tmp/again.json" >/dev/null 2>&1
  check "resumed again ($k): the same output bytes" cmp -s "$tmp/p49_last.full.txt" "$tmp/again.txt"
  check "resumed again ($k): no more iterations" test \
    "$(json_value "$tmp/p49_last.full.json" iterations)" = "$(json_value "$tmp/again.json" iterations)"
done

# The iteration limit: its last step writes a checkpoint even when
# --checkpoint-every has not passed, and a resume under a higher limit goes
# on, byte for byte where the uninterrupted solve goes.
"$dba" solve "$p49" -q -t 2 --max-iterations 3 --checkpoint "$tmp/lim.ckpt" --checkpoint-every 1e9 \
  --report "$tmp/lim3.json" >/dev/null 2>&1
check "limit: the first and the last step written" json "$tmp/lim3.json" "d['checkpoints']['written'] == 2"
"$dba" solve "$p49" -q -t 2 --max-iterations 6 --resume "$tmp/lim.ckpt" -o "$tmp/lim_resumed.txt" \
  --report "$tmp/lim_resumed.json" >/dev/null 2>&1
"$dba" solve "$p49" -q -t 2 --max-iterations 6 -o "$tmp/lim6.txt" >/dev/null 2>&1
check "limit: resumed under a higher one, the same bytes" cmp -s "$tmp/lim6.txt" "$tmp/lim_resumed.txt"
check "limit: resumed for 3 more iterations" json "$tmp/lim_resumed.json" "d['iterations'] == 6"

# A tight PCG solve: to 1e-9 relative.
tight_pcg=(--linear-solver pcg --eta 0 --pcg-tolerance 1e-14 --pcg-max-iterations 2000)
"$dba" solve "$p49" -q -t 2 "${tight_pcg[@]}" --report "$tmp/pcg.json" >/dev/null 2>&1
DBA_KILL_AFTER_CHECKPOINT=3 "$dba" solve "$p49" -q -t 2 "${tight_pcg[@]}" --checkpoint "$tmp/pcg.ckpt" >/dev/null 2>&1
"$dba" solve "$p49" -q -t 2 "${tight_pcg[@]}" --resume "$tmp/pcg.ckpt" --report "$tmp/pcg_resumed.json" >/dev/null 2>&1
check "PCG, tight: resumed to 1e-9" json "$tmp/pcg_resumed.json" \
  "near(d['final_cost'], $(json_value "$tmp/pcg.json" final_cost), 1e-9)"

# Camera priors (a block in a frame of its own, aligned onto them before
# LM) and control points: the resume neither aligns again nor loses them.
"$dba" generate "$tmp/s.dba" --model photo --images 60 --unaligned --priors "$tmp/s.priors" \
  --gcps "$tmp/s.gcps" --control-points 4 --check-points 2 --outliers 0.01 --seed 5 >/dev/null
killed_and_resumed priors 3 .dba "$tmp/s.dba" --camera-priors "$tmp/s.priors"
killed_and_resumed gcps 3 .dba "$tmp/s.dba" --gcps "$tmp/s.gcps"
killed_and_resumed both 4 .dba "$tmp/s.dba" --camera-priors "$tmp/s.priors" --gcps "$tmp/s.gcps"

# A scattered input (points and cameras renumbered at random) is solved in
# the walk's order, cameras renumbered: its checkpoints still hold the
# input's order, so the resume ends on the same bytes, rejection included.
"$dba" generate "$tmp/g.txt" --images 40 --seed 6 >/dev/null
/usr/bin/python3 "$root/bench/shuffle_bal.py" "$tmp/g.txt" "$tmp/shuffled.txt" 3
"$dba" solve "$tmp/shuffled.txt" -t 2 --max-iterations 0 >"$tmp/walk.log" 2>&1
check "shuffled: the solve walks it" contains "$tmp/walk.log" "points walked in a spatial order"
killed_and_resumed shuffled 3 .txt "$tmp/shuffled.txt"
killed_and_resumed shuffled_rej 4 .txt "$tmp/shuffled.txt" --reject-outliers 2

# Outlier rejection: killed inside the first solve, and inside a later
# round's (the N-th checkpoint counts every accepted step of every round).
"$dba" solve "$tmp/s.dba" -q -t 2 --reject-outliers 3 --report "$tmp/rej.json" >/dev/null 2>&1
accepted=$(json_value "$tmp/rej.json" accepted_iterations)
check "rejection: more than one round" json "$tmp/rej.json" "len(d['outlier_rejection']['rounds']) >= 1"
killed_and_resumed rej_first 2 .dba "$tmp/s.dba" --reject-outliers 3
killed_and_resumed rej_later $((accepted - 1)) .dba "$tmp/s.dba" --reject-outliers 3
check "rej_later: resumed after a rejection round" contains "$tmp/rej_later.log" "after rejection round"
killed_and_resumed rej_last "$accepted" .dba "$tmp/s.dba" --reject-outliers 3
# Without --loss the first solve's is cauchy at 2 PX, in the setup as --loss:
# the same loss given resumes to the same bytes, the squared one is refused.
"$dba" solve "$tmp/s.dba" -q -t 2 --reject-outliers 3 --loss cauchy --loss-scale 6 \
  --resume "$tmp/rej_last.ckpt" -o "$tmp/rej_explicit.dba" >/dev/null 2>&1
check "rejection: resumed with its loss given, the same bytes" cmp -s "$tmp/rej_last.full.dba" "$tmp/rej_explicit.dba"
"$dba" solve "$tmp/s.dba" -q -t 2 --reject-outliers 3 --loss trivial --resume "$tmp/rej_last.ckpt" \
  -o "$tmp/rej_squared.dba" >"$tmp/log" 2>&1
check "rejection: resumed with --loss trivial, refused (exit 2)" test $? -eq 2
check "rejection: resumed with --loss trivial, says the loss differs" contains "$tmp/log" "written with other --loss"
# A run the guard stopped keeps the checkpoint of the solve before the
# round; resumed with the guard raised, it ends where an unstopped run ends.
"$dba" solve "$tmp/s.dba" -q -t 2 --reject-outliers 3 --loss trivial --checkpoint "$tmp/guard.ckpt" \
  -o "$tmp/guard.dba" >"$tmp/log" 2>&1
check "guard: a squared first solve is stopped (exit 1)" test $? -eq 1
check "guard: nothing written" test ! -e "$tmp/guard.dba"
"$dba" solve "$tmp/s.dba" -q -t 2 --reject-outliers 3 --loss trivial --reject-max-share 1 \
  --resume "$tmp/guard.ckpt" -o "$tmp/guard.dba" >/dev/null 2>&1
"$dba" solve "$tmp/s.dba" -q -t 2 --reject-outliers 3 --loss trivial --reject-max-share 1 \
  -o "$tmp/unguarded.dba" >/dev/null 2>&1
check "guard: resumed with --reject-max-share 1, the unguarded run's bytes" cmp -s "$tmp/unguarded.dba" "$tmp/guard.dba"

# Rigs (frames and sensors are the parameters), and with GNSS on the frames
# and a refined lever arm (its 3 values in the checkpoint after the cameras):
# killed and resumed, the same bytes and lever arm.
"$dba" generate --model photo --rig stereo --images 120 --seed 4 "$tmp/rig.dba" \
  --priors "$tmp/rig.priors" --gnss-sigma 0.05,0.05 --lever-arm 0.2,0.1,-0.3 >/dev/null 2>&1
killed_and_resumed rig 2 .dba "$tmp/rig.dba" --linear-solver dense
killed_and_resumed lever 2 .dba "$tmp/rig.dba" --linear-solver dense --camera-priors "$tmp/rig.priors" \
  --refine-lever-arm
check "lever: resumed, the same lever arm" test \
  "$(json_value "$tmp/lever.full.json" camera_priors | python3 -c 'import sys; print(eval(sys.stdin.read())["lever_arm"])')" = \
  "$(json_value "$tmp/lever.resumed.json" camera_priors | python3 -c 'import sys; print(eval(sys.stdin.read())["lever_arm"])')"
check "lever: it moved from 0" json "$tmp/lever.full.json" "d['camera_priors']['lever_arm'] != [0.0, 0.0, 0.0]"
"$dba" solve "$tmp/rig.dba" -q --camera-priors "$tmp/rig.priors" --resume "$tmp/lever.ckpt" \
  -o "$tmp/refused.dba" >"$tmp/log" 2>&1
check "a lever-arm checkpoint resumed without --refine-lever-arm is refused" \
  contains "$tmp/log" "written with --refine-lever-arm, which this run does not have"

# The rig's geometry refined or held is the setup's: a checkpoint of one is
# refused under the other (exit 2, nothing written), naming it.
"$dba" solve "$tmp/rig.dba" -q -t 2 --rig-geometry fixed --max-iterations 2 \
  --checkpoint "$tmp/rigfixed.ckpt" >/dev/null 2>&1
rig_refused() {  # rig_refused CHECKPOINT SAYS ARGS...
  local ckpt=$1 says=$2; shift 2
  "$dba" solve "$tmp/rig.dba" -q --resume "$ckpt" -o "$tmp/refused.dba" "$@" >"$tmp/log" 2>&1
  local status=$?
  check "rig resume of $(basename "$ckpt") with $*: exit 2 (got $status)" test "$status" -eq 2
  check "rig resume of $(basename "$ckpt") with $*: says '$says'" contains "$tmp/log" "$says"
  check "rig resume of $(basename "$ckpt") with $*: nothing written" test ! -e "$tmp/refused.dba"
}
rig_refused "$tmp/rig.ckpt" "written without --rig-geometry" --rig-geometry fixed
rig_refused "$tmp/rigfixed.ckpt" "written with --rig-geometry, which this run does not have"
rig_refused "$tmp/rigfixed.ckpt" "written with other --rig-geometry" --rig-geometry fixed:1

# What differs from the checkpoint's setup is refused (exit 2), naming it.
refused_resume() {
  local says=$1; shift
  "$dba" solve "$tmp/s.dba" -q --resume "$tmp/priors.ckpt" -o "$tmp/refused.dba" "$@" >"$tmp/log" 2>&1
  local status=$?
  check "resume with $*: exit 2 (got $status)" test "$status" -eq 2
  check "resume with $*: says '$says'" contains "$tmp/log" "$says"
  check "resume with $*: nothing written" test ! -e "$tmp/refused.dba"
}
refused_resume "written with --camera-priors, which this run does not have"
refused_resume "written with other --prior-loss" --camera-priors "$tmp/s.priors" --prior-loss huber
refused_resume "written with other --loss" --camera-priors "$tmp/s.priors" --loss cauchy
refused_resume "written without --gcps" --camera-priors "$tmp/s.priors" --gcps "$tmp/s.gcps"
refused_resume "written without --reject-outliers" --camera-priors "$tmp/s.priors" --reject-outliers 3

# A damaged checkpoint (one byte changed, or cut short) is refused (exit 1).
python3 - "$tmp/priors.ckpt" "$tmp/flipped.ckpt" <<'PY'
import sys
b = bytearray(open(sys.argv[1], "rb").read())
b[len(b) // 2] ^= 0x10
open(sys.argv[2], "wb").write(b)
PY
"$dba" solve "$tmp/s.dba" -q --camera-priors "$tmp/s.priors" --resume "$tmp/flipped.ckpt" -o "$tmp/refused.dba" >"$tmp/log" 2>&1
check "a flipped bit: exit 1" test $? -eq 1
check "a flipped bit: says so" contains "$tmp/log" "checksum does not match"
check "a flipped bit: nothing written" test ! -e "$tmp/refused.dba"

finish
