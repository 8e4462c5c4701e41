#!/usr/bin/env bash
# Nothing lost, even when the user errs: every output of dba follows one
# rule (src/dba/io/output_target.h), checked before the solve, and a run
# whose outputs are refused or fail leaves every file as it was. Each case
# asserts the exit status, the message, and that no input, output or
# temporary was written, changed or left behind. Never the real /dev/null
# or the machine's devices: FIFOs, and private device nodes where the test
# runs as root (skipped otherwise, saying so).
# Usage: cli_outputs.sh PATH_TO_DBA PROJECT_ROOT
set -uo pipefail
source "$(dirname "$0")/lib/check.sh"
dba=$1
root=$2
bal5=$root/../shared/data/bal/balbianello-5-544-from-bundler.txt.bz2
colmap=$root/../shared/data/colmap/mithunnallana_6img/sparse/0
need_shared "$bal5" "$colmap"
bzip2 -dc "$bal5" >"$tmp/a.txt"
cp "$tmp/a.txt" "$tmp/a.orig"
cp -r "$colmap" "$tmp/m"
cp -r "$colmap" "$tmp/m.orig"
chmod -R u+w "$tmp/m" "$tmp/m.orig"
# A COLMAP >= 3.12 model with (trivial) rigs and frames, text (mr) and binary (mrb).
mkdir -p "$tmp/mr"
cp "$colmap/"{cameras,images,points3D}.txt "$tmp/mr/"
echo "1 1 CAMERA 1" >"$tmp/mr/rigs.txt"
awk '!/^#/ && n++ % 2 == 0 {print $1, 1, $2, $3, $4, $5, $6, $7, $8, 1, "CAMERA", 1, $1}' \
  "$colmap/images.txt" >"$tmp/mr/frames.txt"
"$dba" convert "$tmp/mr" "$tmp/mrb" --colmap-format binary >/dev/null 2>&1
check "the binary rig model is written" test -s "$tmp/mrb/rigs.bin" -a -s "$tmp/mrb/frames.bin"
cp -r "$tmp/mr" "$tmp/mr.orig"
cp -r "$tmp/mrb" "$tmp/mrb.orig"
no_temporaries() {
  test -z "$(find "$tmp" -name '*.tmp.*' -o -name '*.dba-old.*' -o -name '*.dba-journal.*' \
    -o -name '*.dba-done.*' -o -name '*.dba-member.*')"
}
same_model() { diff -r "$1" "$2" >/dev/null; }

# refused STATUS MESSAGE ARGS...: `dba ARGS` exits STATUS, says MESSAGE, never
# starts the solve, and leaves the inputs as they were and no temporary.
n=0
refused() {
  local status=$1 message=$2; shift 2
  n=$((n + 1))
  timeout -k 5 120 "$dba" "$@" >"$tmp/log" 2>&1
  local got=$?
  local name="[$n] dba $*"
  check "$name: exit $status (got $got)" test "$got" -eq "$status"
  check "$name: says '$message'" contains "$tmp/log" "$message"
  check "$name: before the solve" lacks "$tmp/log" "iter "
  check "$name: the BAL input unchanged" cmp -s "$tmp/a.txt" "$tmp/a.orig"
  check "$name: the COLMAP input unchanged" same_model "$tmp/m" "$tmp/m.orig"
  check "$name: the rig models unchanged" same_model "$tmp/mr" "$tmp/mr.orig"
  check "$name: ... binary too" same_model "$tmp/mrb" "$tmp/mrb.orig"
  check "$name: no temporary" no_temporaries
  [ "$got" -eq "$status" ] || cat "$tmp/log" >&2
}

# 1. An output naming an input, or another output: exit 2, both named.
refused 2 "--checkpoint $tmp/a.txt names INPUT $tmp/a.txt" solve "$tmp/a.txt" --checkpoint "$tmp/a.txt"
refused 2 "--report $tmp/a.txt names INPUT $tmp/a.txt" solve "$tmp/a.txt" --report "$tmp/a.txt"
refused 2 "--ply $tmp/m/points3D.txt names INPUT $tmp/m/points3D.txt" solve "$tmp/m" --ply "$tmp/m/points3D.txt"
refused 2 "--camera-centres $tmp/m/images.txt names INPUT" solve "$tmp/m" --camera-centres "$tmp/m/images.txt"
refused 2 "-o $tmp/b.txt and --report $tmp/b.txt name one file" solve "$tmp/a.txt" -o "$tmp/b.txt" --report "$tmp/b.txt"
refused 2 "name one file" solve "$tmp/a.txt" -o "$tmp/b.txt" --ply "$tmp/./b.txt"
refused 2 "-o $tmp/a.txt names --truth $tmp/a.txt" solve "$bal5" -o "$tmp/a.txt" --truth "$tmp/a.txt"
refused 2 "--checkpoint $tmp/a.txt names --truth" solve "$bal5" --truth "$tmp/a.txt" --checkpoint "$tmp/a.txt"
refused 2 "name one file" solve "$tmp/m" -o "$tmp/out_m" --report "$tmp/out_m/cameras.txt"
# A model's rigs and frames are its files: no output replaces an input's
# (text or binary), nor lands in a model written where its reader would take
# it for the model's own (its format's files or the other's).
refused 2 "--report $tmp/mr/rigs.txt names INPUT $tmp/mr/rigs.txt" solve "$tmp/mr" --report "$tmp/mr/rigs.txt"
refused 2 "--ply $tmp/mr/frames.txt names INPUT $tmp/mr/frames.txt" solve "$tmp/mr" --ply "$tmp/mr/frames.txt"
refused 2 "--checkpoint $tmp/mrb/frames.bin names INPUT" solve "$tmp/mrb" --checkpoint "$tmp/mrb/frames.bin"
refused 2 "--camera-centres $tmp/mrb/rigs.bin names INPUT" solve "$tmp/mrb" --camera-centres "$tmp/mrb/rigs.bin"
refused 2 "--checkpoint $tmp/out_r/frames.txt is frames.txt of the COLMAP model -o $tmp/out_r: a reader" \
  solve "$tmp/m" -o "$tmp/out_r" --checkpoint "$tmp/out_r/frames.txt"
refused 2 "--report $tmp/out_r/rigs.bin is rigs.bin of the COLMAP model -o $tmp/out_r" \
  solve "$tmp/mr" -o "$tmp/out_r" --report "$tmp/out_r/rigs.bin"
check "no model written" test ! -e "$tmp/out_r"
# "link/.." is beside the link's target, not the link: two new paths, one file.
mkdir -p "$tmp/deep/sub" && ln -s deep/sub "$tmp/lnk"
refused 2 "--report $tmp/deep/c2.ckpt and --checkpoint $tmp/lnk/../c2.ckpt name one file" \
  solve "$tmp/a.txt" --checkpoint "$tmp/lnk/../c2.ckpt" --report "$tmp/deep/c2.ckpt"
check "neither written" test ! -e "$tmp/deep/c2.ckpt" -a ! -e "$tmp/c2.ckpt"
ln -s a.txt "$tmp/link_to_a.txt"
refused 2 "--report $tmp/link_to_a.txt names INPUT $tmp/a.txt" solve "$tmp/a.txt" --report "$tmp/link_to_a.txt"
check "a refused run left no output" test ! -e "$tmp/b.txt" -a ! -e "$tmp/out_m"
refused 2 "OUTPUT $tmp/x.txt and --truth $tmp/x.txt name one file" generate "$tmp/x.txt" --images 20 --truth "$tmp/x.txt"
refused 2 "name one file" generate "$tmp/x.dba" --model photo --images 20 --priors "$tmp/p.txt" --gcps "$tmp/p.txt" --control-points 3
check "generate refused: nothing written" test ! -e "$tmp/x.txt" -a ! -e "$tmp/x.dba" -a ! -e "$tmp/p.txt"

# 2. What is not a file, a character device or a FIFO is refused before the
# solve, exit 2: a directory, a link to nothing, a regular file behind /proc.
mkdir -p "$tmp/dir.txt"
refused 2 "$tmp/dir.txt: is a directory" solve "$tmp/a.txt" -o "$tmp/out1.txt" --report "$tmp/dir.txt"
refused 2 "is a directory" solve "$tmp/a.txt" -o "$tmp/dir.txt"
refused 2 "is a directory" solve "$tmp/a.txt" --checkpoint "$tmp/dir.txt"
# A checkpoint is replaced at every write and read back by --resume: a FIFO
# would block the second (a reader would see two checkpoints run together).
mkfifo "$tmp/fifo_ckpt"
refused 2 "--checkpoint $tmp/fifo_ckpt: is a FIFO; --checkpoint writes a file that it replaces" \
  solve "$tmp/a.txt" --checkpoint "$tmp/fifo_ckpt"
refused 2 "is a directory" convert "$tmp/a.txt" "$tmp/dir.txt"
refused 2 "is not a directory" solve "$tmp/m" -o "$tmp/a.orig"
ln -s "$tmp/nowhere/x.json" "$tmp/dangling.json"
refused 2 "symbolic link to nothing" solve "$tmp/a.txt" -o "$tmp/out1.txt" --report "$tmp/dangling.json"
refused 2 "under /proc" solve "$tmp/a.txt" -o "$tmp/out1.txt" --report /proc/dba-report.json
refused 2 "through /proc or /dev/fd" solve "$tmp/a.txt" -o "$tmp/out1.txt" --report /proc/self/status
refused 2 "an empty value" solve "$tmp/a.txt" -o ""
refused 2 "an empty value" solve "$tmp/a.txt" --report ""
refused 2 "an empty path" convert "$tmp/a.txt" ""
check "no output after the refusals" test ! -e "$tmp/out1.txt"
# A directory that refuses new files (read-only): exit 1, before the solve.
if [ "$(id -u)" -ne 0 ]; then
  mkdir -p "$tmp/ro" && chmod 555 "$tmp/ro"
  refused 1 "cannot create a file in $tmp/ro" solve "$tmp/a.txt" -o "$tmp/out1.txt" --report "$tmp/ro/r.json"
  chmod 755 "$tmp/ro"
else
  echo "skipped (root writes anywhere): a read-only directory"
fi
# /dev/stdout redirected into a file would be replaced under the shell: refused.
"$dba" solve "$tmp/a.txt" -q --report /dev/stdout >"$tmp/stdout_file" 2>"$tmp/log"
check "/dev/stdout on a file exits 2" test $? -eq 2
check "/dev/stdout on a file: says why" contains "$tmp/log" "through /proc or /dev/fd"

# Deliberate in-place work: -o over the problem read, a COLMAP model written
# back over itself (replaced whole), --checkpoint F --resume F, convert in place.
"$dba" solve "$tmp/a.txt" -q -t 2 -o "$tmp/elsewhere.txt" >/dev/null 2>&1
cp "$tmp/a.txt" "$tmp/inplace.txt"
"$dba" solve "$tmp/inplace.txt" -q -t 2 -o "$tmp/inplace.txt" >"$tmp/log" 2>&1
check "-o over the input exits 0" test $? -eq 0
check "-o over the input: the same bytes as elsewhere" cmp -s "$tmp/inplace.txt" "$tmp/elsewhere.txt"
cp -r "$colmap" "$tmp/m_in_place" && chmod -R u+w "$tmp/m_in_place"
"$dba" solve "$tmp/m" -q -t 2 -o "$tmp/m_elsewhere" >/dev/null 2>&1
"$dba" solve "$tmp/m_in_place" -q -t 2 -o "$tmp/m_in_place" >"$tmp/log" 2>&1
check "a COLMAP model over itself exits 0" test $? -eq 0
check "a COLMAP model over itself: as written elsewhere" same_model "$tmp/m_in_place" "$tmp/m_elsewhere"
"$dba" solve "$tmp/a.txt" -q -t 2 --max-iterations 3 --checkpoint "$tmp/c.ckpt" >/dev/null 2>&1
"$dba" solve "$tmp/a.txt" -q -t 2 --resume "$tmp/c.ckpt" --checkpoint "$tmp/c.ckpt" -o "$tmp/resumed.txt" >"$tmp/log" 2>&1
check "--checkpoint F --resume F exits 0" test $? -eq 0
check "--checkpoint F --resume F resumed" contains "$tmp/log" "resumed from"
cp "$tmp/a.txt" "$tmp/conv.txt"
"$dba" convert "$tmp/conv.txt" "$tmp/conv.txt" >/dev/null 2>&1
check "convert in place exits 0" test $? -eq 0
"$dba" solve "$tmp/conv.txt" -q --max-iterations 0 --report "$tmp/conv.json" >/dev/null 2>&1
"$dba" solve "$tmp/a.txt" -q --max-iterations 0 --report "$tmp/orig.json" >/dev/null 2>&1
check "convert in place: the same problem" test "$(json_value "$tmp/conv.json" initial_cost)" = "$(json_value "$tmp/orig.json" initial_cost)"

# Symbolic links are written through: the file they lead to is replaced, the
# link stays a link.
echo old >"$tmp/real.json"
ln -s real.json "$tmp/link.json"
"$dba" solve "$tmp/a.txt" -q --max-iterations 1 --report "$tmp/link.json" >/dev/null 2>&1
check "a linked output exits 0" test $? -eq 0
check "the link stays a link" test -L "$tmp/link.json"
check "the file it leads to holds the report" contains "$tmp/real.json" '"final_cost"'
chmod 600 "$tmp/real.json"
"$dba" solve "$tmp/a.txt" -q --max-iterations 1 --report "$tmp/real.json" >/dev/null 2>&1
check "a replaced file keeps its mode" test "$(stat -c %a "$tmp/real.json")" = 600

# FIFOs and character devices get a plain write, and stay what they are.
mkfifo "$tmp/fifo"
cat "$tmp/fifo" >"$tmp/from_fifo" &
reader=$!
"$dba" solve "$tmp/a.txt" -q --max-iterations 1 --report "$tmp/fifo" >"$tmp/log" 2>&1
check "a FIFO output exits 0" test $? -eq 0
wait "$reader"
check "the FIFO stays a FIFO" test -p "$tmp/fifo"
check "the FIFO's reader got the report" contains "$tmp/from_fifo" '"final_cost"'
"$dba" solve "$tmp/a.txt" -q --max-iterations 1 --report /dev/stdout 2>"$tmp/log" | cat >"$tmp/piped"
check "/dev/stdout on a pipe: the report comes through" contains "$tmp/piped" '"final_cost"'
if [ "$(id -u)" -eq 0 ] && mknod "$tmp/null" c 1 3 2>/dev/null && mknod "$tmp/full" c 1 7 2>/dev/null \
   && mknod "$tmp/block" b 7 0 2>/dev/null; then
  "$dba" solve "$tmp/a.txt" -q --max-iterations 1 --report "$tmp/null" --ply "$tmp/null" >"$tmp/log" 2>&1
  check "a private null device as two outputs exits 0" test $? -eq 0
  check "the null device stays a character device" test -c "$tmp/null"
  "$dba" solve "$tmp/a.txt" -q --max-iterations 1 --report "$tmp/full" >"$tmp/log" 2>&1
  check "a full device exits 1" test $? -eq 1
  check "a full device: says so" contains "$tmp/log" "No space left on device"
  ln -s full "$tmp/full.txt"
  "$dba" convert "$tmp/a.txt" "$tmp/full.txt" >"$tmp/log" 2>&1
  check "convert into a full device (through a link) exits 1" test $? -eq 1
  check "convert into a full device: says so" contains "$tmp/log" "No space left on device"
  check "the link stays a link to the device" test -L "$tmp/full.txt" -a -c "$tmp/full"
  rm -f "$tmp/full.txt"
  check "the full device stays a character device" test -c "$tmp/full"
  refused 2 "$tmp/block: is a block device" solve "$tmp/a.txt" --report "$tmp/block"
  check "the block device stays one" test -b "$tmp/block"
  rm -f "$tmp/null" "$tmp/full" "$tmp/block"
else
  echo "skipped (needs root and mknod): private character and block devices"
fi
/usr/bin/python3 -c "import socket,sys; s=socket.socket(socket.AF_UNIX); s.bind(sys.argv[1])" "$tmp/sock" 2>/dev/null \
  && refused 2 "$tmp/sock: is a socket" solve "$tmp/a.txt" --report "$tmp/sock"

# 3. Several outputs appear together or not at all: a run whose last output
# fails (here a file-size limit, as a full disk) leaves the earlier ones as
# they were, a COLMAP model whole.
cp -r "$colmap" "$tmp/m_target" && chmod -R u+w "$tmp/m_target"
cp -r "$tmp/m_target" "$tmp/m_target.orig"
echo old >"$tmp/r_keep.json"
# 100 KiB: the PLY (55 KB), cameras.txt and the report fit, images.txt (1 MB) not.
(trap '' XFSZ; ulimit -f 100; "$dba" solve "$tmp/m" -q -t 2 -o "$tmp/m_target" --ply "$tmp/p_keep.ply" \
  --report "$tmp/r_keep.json" --camera-centres "$tmp/centres_keep.txt" --colmap-format text >"$tmp/log" 2>&1)
status=$?
if grep -q "write failed" "$tmp/log"; then
  check "a failed output exits 1 (got $status)" test "$status" -eq 1
  check "the model written into is whole, as it was" same_model "$tmp/m_target" "$tmp/m_target.orig"
  check "an earlier output not replaced" contains "$tmp/r_keep.json" old
  check "no new output appeared" test ! -e "$tmp/p_keep.ply" -a ! -e "$tmp/centres_keep.txt"
  check "no temporary after a failed output" no_temporaries
else
  check "the file-size limit made an output fail (status $status)" false
  cat "$tmp/log" >&2
fi

# 4. What a killed run left (FILE.tmp.PID of a dead process) is cleaned by
# the next write of FILE; another live process's temporary is not touched;
# a COLMAP model whose replacement a kill interrupted (FILE.dba-old.PID) is
# put back whole when next read.
sh -c 'exit 0' & dead=$!; wait "$dead"
sleep 60 & live=$!
echo stale >"$tmp/o.txt.tmp.$dead"
echo live >"$tmp/o.txt.tmp.$live"
echo unrelated >"$tmp/o.txt.tmp.x$dead"
"$dba" solve "$tmp/a.txt" -q --max-iterations 1 -o "$tmp/o.txt" >/dev/null 2>&1
check "a dead process's temporary is removed" test ! -e "$tmp/o.txt.tmp.$dead"
check "a live process's temporary is kept" test -e "$tmp/o.txt.tmp.$live"
check "a file not named as ours is kept" test -e "$tmp/o.txt.tmp.x$dead"
kill "$live" 2>/dev/null; wait "$live" 2>/dev/null
rm -f "$tmp/o.txt.tmp.$live" "$tmp/o.txt.tmp.x$dead"
cp -r "$colmap" "$tmp/m_killed" && chmod -R u+w "$tmp/m_killed"
"$dba" solve "$tmp/m" -q -t 2 --max-iterations 2 -o "$tmp/m_new" >/dev/null 2>&1
for f in cameras images; do  # killed after two of three renames
  ln "$tmp/m_killed/$f.txt" "$tmp/m_killed/$f.txt.dba-old.$dead"
  cp "$tmp/m_new/$f.txt" "$tmp/m_killed/$f.txt.new" && mv "$tmp/m_killed/$f.txt.new" "$tmp/m_killed/$f.txt"
done
ln "$tmp/m_killed/points3D.txt" "$tmp/m_killed/points3D.txt.dba-old.$dead"
"$dba" solve "$tmp/m_killed" -q --max-iterations 0 --report "$tmp/killed.json" >"$tmp/log" 2>&1
check "an interrupted model is read" test $? -eq 0
check "an interrupted model is put back whole" same_model "$tmp/m_killed" "$tmp/m.orig"
"$dba" solve "$tmp/m" -q --max-iterations 0 --report "$tmp/whole.json" >/dev/null 2>&1
check "and solves as the old model" test "$(json_value "$tmp/killed.json" initial_cost)" = "$(json_value "$tmp/whole.json" initial_cost)"

# A SIGKILL at any step of a run's commit (DBA_KILL_IN_COMMIT=N: 1 the
# journal written, then each rename, the commit, each file's old copy
# removed) leaves, once the next run reads one of the files, every output
# of the run old whole or new whole and nothing else: a rig model written
# over itself with a report beside it (5 + 1 files, 14 steps; the next run
# reads the model), and a BAL output with its report (2 files, 6 steps; the
# next run reads the BAL output).
killed_commits() {  # NAME STEPS OLD_UP_TO READ REF_DIR SETUP ARGS...
  local name=$1 steps=$2 old_up_to=$3 read=$4 ref=$5 setup=$6; shift 6
  for k in $(seq "$steps"); do
    rm -rf "$tmp/k" && mkdir "$tmp/k" && $setup "$tmp/k" && echo old >"$tmp/k/r.json"
    { DBA_KILL_IN_COMMIT=$k "$dba" solve "$@" >/dev/null 2>&1; } 2>/dev/null  # (bash's "Killed")
    local status=$?
    check "$name: killed at step $k of $steps (status $status)" test "$status" -eq 137
    "$dba" solve "$tmp/k/$read" -q --max-iterations 0 >"$tmp/log" 2>&1
    check "$name, step $k: the next run reads it" test $? -eq 0
    if [ "$k" -le "$old_up_to" ]; then
      check "$name, step $k: all old" same_model "$tmp/k" "$tmp/$name.old"
    else
      check "$name, step $k: the report new" contains "$tmp/k/r.json" '"final_cost"'
      check "$name, step $k: the rest new" diff -r -x r.json "$tmp/k" "$ref"
    fi
    check "$name, step $k: nothing else left" test -z "$(find "$tmp/k" -name '*.tmp.*' -o -name '*.dba-*')"
  done
}
rig_setup() { cp -r "$tmp/mr" "$1/m"; }
bal_setup() { cp "$tmp/a.txt" "$1/b.txt"; }
mkdir "$tmp/rig.ref" "$tmp/rig.old" "$tmp/bal.ref" "$tmp/bal.old"
rig_setup "$tmp/rig.old" && echo old >"$tmp/rig.old/r.json"
bal_setup "$tmp/bal.old" && echo old >"$tmp/bal.old/r.json"
rig_setup "$tmp/rig.ref"
"$dba" solve "$tmp/rig.ref/m" -q -t 2 --max-iterations 2 -o "$tmp/rig.ref/m" >/dev/null 2>&1
"$dba" solve "$tmp/a.txt" -q -t 2 --max-iterations 2 -o "$tmp/bal.ref/b.txt" >/dev/null 2>&1
check "the uninterrupted runs moved the outputs" test -s "$tmp/bal.ref/b.txt" -a -n "$(diff -q "$tmp/rig.ref/m" "$tmp/mr")"
killed_commits rig 14 7 m "$tmp/rig.ref" rig_setup \
  "$tmp/k/m" -q -t 2 --max-iterations 2 -o "$tmp/k/m" --report "$tmp/k/r.json"
killed_commits bal 6 3 b.txt "$tmp/bal.ref" bal_setup \
  "$tmp/a.txt" -q -t 2 --max-iterations 2 -o "$tmp/k/b.txt" --report "$tmp/k/r.json"

# Distributed (3 ranks): the same checks on the main rank before any rank
# starts, exit 2, no output.
if command -v mpirun >/dev/null; then
  mpirun_n() { local n=$1; shift; timeout -k 10 120 mpirun --allow-run-as-root --oversubscribe --bind-to none -np "$n" "$@"; }
  mpirun_n 3 "$dba" solve "$tmp/a.txt" -q -o "$tmp/mpi_o.txt" --report "$tmp/dir.txt" >"$tmp/log" 2>&1
  check "MPI: a directory as --report exits 2" test $? -eq 2
  check "MPI: says so" contains "$tmp/log" "is a directory"
  check "MPI: no -o written" test ! -e "$tmp/mpi_o.txt"
  mpirun_n 3 "$dba" solve "$tmp/a.txt" -q -o "$tmp/mpi_o.txt" --checkpoint "$tmp/a.txt" >"$tmp/log" 2>&1
  check "MPI: --checkpoint over the input exits 2" test $? -eq 2
  check "MPI: the input unchanged" cmp -s "$tmp/a.txt" "$tmp/a.orig"
  check "MPI: no temporary" no_temporaries
else
  check "mpirun is installed (scripts/install-deps.sh)" false
fi

# 11. A limit on the address space (ulimit -v): every command runs or says
# why; none hangs (OpenBLAS retried its refused buffers forever).
for args in "--help" "solve --help" "solve $tmp/a.txt -q" "solve $tmp/a.txt -q --linear-solver sparse" \
            "convert $tmp/a.txt $tmp/as.dba" "info $tmp/a.txt" "generate $tmp/as_gen.txt --images 20"; do
  (ulimit -v 200000; timeout -k 5 60 "$dba" $args >"$tmp/log" 2>&1)
  status=$?
  check "ulimit -v 200000: dba $args does not hang (status $status)" test "$status" -ne 124 -a "$status" -ne 137
  if [ "$status" -ne 0 ]; then
    check "ulimit -v 200000: dba $args says why" contains "$tmp/log" "address-space limit"
  fi
done
(ulimit -v 1000000; timeout -k 5 60 "$dba" solve "$tmp/a.txt" -q --linear-solver sparse >"$tmp/log" 2>&1)
check "ulimit -v 1000000: the sparse factorization runs" test $? -eq 0

finish
