#!/usr/bin/env bash
# The module graph declared in src/dba/CMakeLists.txt is the one the code
# uses: every #include "dba/M/..." in a library source of module N (tests
# excepted, they link everything) names N itself or a module N declares
# with DEPS. Prints each wrong-way include as file:line and fails.
# A negative control runs the same check on a copy with one wrong-way
# include added, and must see it fail.
# Usage: check_includes.sh MODULE_DEPS_TXT SRC_DBA_DIR
set -uo pipefail
deps_file=$1
src=$2

# check DEPS_FILE SRC_DIR: prints violations, exit 1 if any.
check() {
  awk -v deps_file="$1" -v src="$2" '
    BEGIN {
      while ((getline line < deps_file) > 0) {
        split(line, kv, ": ")
        name = kv[1]; declared[name] = 1
        n = split(kv[2], d, ";")
        for (i = 1; i <= n; i++) if (d[i] != "") allowed[name, d[i]] = 1
      }
    }
    FNR == 1 {
      rel = substr(FILENAME, length(src) + 2)
      split(rel, parts, "/"); module = parts[1]
      if (!(module in declared)) {
        print FILENAME ": module " module " is not declared in src/dba/CMakeLists.txt"; bad = 1
      }
    }
    /^#include "dba\// {
      split($0, q, "\""); split(q[2], p, "/"); target = p[2]
      if (target != module && !((module, target) in allowed)) {
        print FILENAME ":" FNR ": " module " includes " q[2] " but does not declare DEPS " target; bad = 1
      }
    }
    END { exit bad }
  ' $(find "$2" -mindepth 2 \( -name '*.h' -o \( -name '*.cc' ! -name '*_test.cc' \) \) | sort)
}

check "$deps_file" "$src" || { echo "FAIL: wrong-way includes (above)"; exit 1; }

# Negative control: bsmc (no DEPS) including lm must be caught.
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cp -r "$src" "$tmp/dba"
printf '#include "dba/lm/bundle_adjust.h"\n' >>"$tmp/dba/bsmc/bsmc_matrix.h"
if out=$(check "$deps_file" "$tmp/dba"); then
  echo "FAIL: the check missed an include of lm from bsmc"; exit 1
fi
grep -q 'bsmc includes dba/lm/bundle_adjust.h' <<<"$out" || { echo "FAIL: unexpected report: $out"; exit 1; }
echo "module graph: $(wc -l <"$deps_file") modules, every include declared"
