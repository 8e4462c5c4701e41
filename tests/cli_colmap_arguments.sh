#!/usr/bin/env bash
# `dba colmap-bundle-adjuster` reads COLMAP's command line as Debian's
# COLMAP 3.8 (`colmap bundle_adjuster`, boost::program_options) does: each
# value below is accepted by both or refused by both (dba: exit 2, naming
# COLMAP's option; COLMAP: exit 1 "Failed to parse options"), booleans mean
# what they mean to COLMAP, an option given twice is refused, a name's
# unambiguous start stands for it, the word after an option is its value.
# dba's own refusals (a stray word, which COLMAP ignores; a value COLMAP's
# solver would abort on or outside dba's range) name COLMAP's option too,
# and so do dba solve's messages about the options the drop-in gave it.
# Without colmap the test fails and says why.
# Usage: cli_colmap_arguments.sh PATH_TO_DBA PROJECT_ROOT
set -uo pipefail
source "$(dirname "$0")/lib/check.sh"
dba=$1
root=$2
model=$root/../shared/data/colmap/mithunnallana_6img/sparse/0
need_shared "$model"
if ! command -v colmap >/dev/null; then
  echo "FAILED: colmap is not installed (scripts/install-deps.sh installs Debian's colmap package)" >&2
  exit 1
fi
export QT_QPA_PLATFORM=offscreen

n=0
# both ARGS...: runs colmap bundle_adjuster and dba colmap-bundle-adjuster
# on the model with ARGS (no iteration), each into a new directory; sets
# c_rc, d_rc and $tmp/c.log, $tmp/d.log.
both() {
  n=$((n + 1))
  mkdir -p "$tmp/c$n"
  colmap bundle_adjuster --input_path "$model" --output_path "$tmp/c$n" \
    --BundleAdjustment.max_num_iterations 0 "$@" >"$tmp/c.log" 2>&1
  c_rc=$?
  "$dba" colmap-bundle-adjuster --input_path "$model" --output_path "$tmp/d$n" \
    --BundleAdjustment.max_num_iterations 0 "$@" >"$tmp/d.log" 2>&1
  d_rc=$?
}
# same FLAG VALUE: both accept FLAG VALUE, or both refuse it (dba naming FLAG).
same() {
  both "$1" "$2"
  if [ $c_rc -eq 0 ]; then
    check "$1 '$2': accepted, as COLMAP accepts it" test $d_rc -eq 0
  else
    check "$1 '$2': COLMAP refuses it while parsing" contains "$tmp/c.log" "Failed to parse options"
    check "$1 '$2': refused, as COLMAP refuses it (exit 2)" test $d_rc -eq 2
    check "$1 '$2': the refusal names $1" contains "$tmp/d.log" "dba colmap-bundle-adjuster: $1: '$2' is not"
  fi
}

# Booleans: boost's spellings in any case (empty: true); what they mean.
for v in 1 true TRUE tRuE yes Yes on ON ""; do
  same --BundleAdjustment.refine_principal_point "$v"
  check "refine_principal_point '$v' refines it" contains "$tmp/d.log" " --refine-principal-point"
done
for v in 0 false False no NO off Off; do
  same --BundleAdjustment.refine_principal_point "$v"
  check "refine_principal_point '$v' holds it" lacks "$tmp/d.log" "--refine-principal-point"
done
for v in maybe 2 01 -1 +1 t f y n " 1" "1 " ye; do same --BundleAdjustment.refine_principal_point "$v"; done
same --log_to_stderr maybe
same --BundleAdjustment.refine_extrinsics OFF
check "refine_extrinsics OFF holds the images" contains "$tmp/d.log" " --fix-images all"

# Integers (COLMAP's int), also of the options that change nothing.
for v in 7 +7 07 -3 2147483647 -2147483648 2147483648 -2147483649 abc 1e2 0x10 " 3" "3 " 2.5 "" ++1 +-1; do
  same --random_seed "$v"
done
for v in 0 -0 1 abc; do same --log_level "$v"; done
# Numbers (COLMAP's double).
for v in 1e-3 .5 +0.5 1E-2 1e-400 1e400 0x1p3 " 1" 1e 1,5 abc ""; do
  same --BundleAdjustment.gradient_tolerance "$v"
done
both --BundleAdjustment.gradient_tolerance 1e-400
check "gradient_tolerance 1e-400 (an underflow) is 0, as COLMAP takes it" \
  contains "$tmp/d.log" " --gradient-tolerance 0 "

# An option given twice: COLMAP refuses it, and so does dba.
both --BundleAdjustment.max_num_iterations 5
check "max_num_iterations twice: COLMAP refuses it" contains "$tmp/c.log" \
  "option '--BundleAdjustment.max_num_iterations' cannot be specified more than once"
check "... dba too (exit 2)" test $d_rc -eq 2
check "... naming it" contains "$tmp/d.log" "--BundleAdjustment.max_num_iterations: given more than once"
both --input "$model"
check "--input after --input_path: COLMAP refuses it" contains "$tmp/c.log" "cannot be specified more than once"
check "... dba too, naming --input_path" contains "$tmp/d.log" "--input_path: given more than once"

# A name's unambiguous start stands for it, as boost guesses.
n=$((n + 1))
"$dba" colmap-bundle-adjuster --input "$model" --output "$tmp/d$n" --BundleAdjustment.max_num 0 \
  --BundleAdjustment.refine_f 0 >"$tmp/d.log" 2>&1
check "--input, --output, --BundleAdjustment.max_num, refine_f: accepted" test $? -eq 0
check "... as the options they start" contains "$tmp/d.log" " --max-iterations 0 "
check "... refine_f as refine_focal_length" contains "$tmp/d.log" " --fix-intrinsics focal"
both --BundleAdjustment.refine_e 0
check "refine_e: COLMAP refuses it as ambiguous" contains "$tmp/c.log" "is ambiguous"
check "... dba too (exit 2), naming both" contains "$tmp/d.log" \
  "--BundleAdjustment.refine_e is ambiguous: it starts --BundleAdjustment.refine_extra_params, --BundleAdjustment.refine_extrinsics"
both --foo 1
check "--foo: COLMAP refuses it" contains "$tmp/c.log" "unrecognised option '--foo'"
check "... dba too (exit 2), naming it" test $d_rc -eq 2
check "... naming it" contains "$tmp/d.log" "'--foo' is not an option of colmap bundle_adjuster"

# --help anywhere (after a parse COLMAP accepts) prints the help, exit 0.
"$dba" colmap-bundle-adjuster --input_path "$model" --help >"$tmp/d.log" 2>&1
check "--help after an option: exit 0" test $? -eq 0
check "... with the help" contains "$tmp/d.log" "Usage: dba colmap-bundle-adjuster"

# The word after an option is its value, also when it starts with '-':
# --input_path --help names the directory '--help' (COLMAP: not a
# directory, exit 1), and so does dba's.
mkdir -p "$tmp/cx"
colmap bundle_adjuster --input_path --help --output_path "$tmp/cx" >"$tmp/c.log" 2>&1
check "--input_path --help: COLMAP takes --help as the path" contains "$tmp/c.log" "\`input_path\` is not a directory"
"$dba" colmap-bundle-adjuster --input_path --help --output_path "$tmp/dx" >"$tmp/d.log" 2>&1
check "... dba too: exit 1" test $? -eq 1
check "... naming the input" contains "$tmp/d.log" "dba colmap-bundle-adjuster: --input_path --help: is not a directory"
check "... and writing nothing" test ! -e "$tmp/dx"

# A missing input is named, not blamed on an output directory that exists.
"$dba" colmap-bundle-adjuster --input_path "$tmp/none" --output_path "$tmp/cx" >"$tmp/d.log" 2>&1
check "a missing --input_path: exit 1" test $? -eq 1
check "... naming it" contains "$tmp/d.log" "--input_path $tmp/none: is not a directory"
mkdir -p "$tmp/empty"
"$dba" colmap-bundle-adjuster --input_path "$tmp/empty" --output_path "$tmp/dx" >"$tmp/d.log" 2>&1
check "an --input_path with no model: exit 1, named" contains "$tmp/d.log" \
  "--input_path $tmp/empty: holds no COLMAP model"
"$dba" colmap-bundle-adjuster --input_path "$model" --output_path "$model/cameras.txt" >"$tmp/d.log" 2>&1
check "an --output_path that is a file: exit 2" test $? -eq 2
check "... named" contains "$tmp/d.log" "--output_path $model/cameras.txt: is not a directory"

# What is wrong with the end of the command line is said.
"$dba" colmap-bundle-adjuster --input_path "$model" --output_path "$tmp/dx" extra >"$tmp/d.log" 2>&1
check "a stray word (COLMAP ignores it): exit 2" test $? -eq 2
check "... said to be unexpected" contains "$tmp/d.log" "unexpected argument 'extra'"
"$dba" colmap-bundle-adjuster --input_path "$model" --output_path >"$tmp/d.log" 2>&1
check "an option without its value: exit 2" test $? -eq 2
check "... naming it" contains "$tmp/d.log" "--output_path: needs a value (the command line ends)"

# Values dba cannot take name COLMAP's option and dba's range (COLMAP's
# solver aborts on the first two).
for case in "--BundleAdjustment.max_num_iterations -1|expected an integer in [0, 1000000000], got '-1'" \
  "--BundleAdjustment.max_linear_solver_iterations 0|expected an integer in [1, 1000000000], got '0'" \
  "--BundleAdjustment.function_tolerance 2|expected a number in [0, 1], got '2'" \
  "--BundleAdjustment.parameter_tolerance inf|expected a number in [0, 1], got 'inf'"; do
  args=${case%%|*}
  # shellcheck disable=SC2086
  "$dba" colmap-bundle-adjuster --input_path "$model" --output_path "$tmp/dx" $args >"$tmp/d.log" 2>&1
  check "$args: exit 2" test $? -eq 2
  check "$args: named as COLMAP's" contains "$tmp/d.log" "dba colmap-bundle-adjuster: ${args%% *}: ${case#*|}"
done
check "nothing written for the refusals" test ! -e "$tmp/dx"

# dba solve's messages about what the drop-in gave it name COLMAP's option.
mkdir -p "$tmp/rigs"
: >"$tmp/rigs/rigs.bin"
"$dba" colmap-bundle-adjuster --input_path "$model" --output_path "$tmp/rigs" >"$tmp/d.log" 2>&1
check "an output holding stale rigs: exit 2" test $? -eq 2
check "... named as --output_path" contains "$tmp/d.log" "dba solve: --output_path $tmp/rigs: holds rigs.bin"
finish
