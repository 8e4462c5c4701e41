#!/usr/bin/env bash
# Builds the readers' libFuzzer targets with clang (coverage, AddressSanitizer,
# UndefinedBehaviorSanitizer) and runs each for SECONDS (default 60), at most
# 2 GiB of memory and 10 s per input. Seeds: small files dba writes (a
# generated survey as BAL text and .dba) and a COLMAP model of ../shared.
# Every input that crashes, hangs or runs out of memory is copied to
# fuzz/regressions/TARGET/, which the unit tests read back (ReaderRegressions
# in src/dba/io/fuzz_regressions_test.cc). Prints per target the executions,
# coverage and findings.
#
#   bash fuzz/run.sh [SECONDS] [TARGET...]   TARGET: bal_text dba_binary colmap_text colmap_binary
set -uo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-60}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(bal_text dba_binary colmap_text colmap_binary)
command -v clang++ >/dev/null || { echo "fuzz/run.sh: clang++ is needed (apt-get install clang)" >&2; exit 2; }
build=$root/build-fuzz
flags="-g -O1 -fno-omit-frame-pointer -fsanitize=fuzzer-no-link,address,undefined"
CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDBA_FUZZ=ON \
  -DDBA_BUILD_TESTS=OFF -DDBA_BUILD_BENCHMARKS=OFF -DDBA_PYTHON=OFF \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_C_FLAGS="$flags" >/dev/null || exit 1
for t in "${targets[@]}"; do
  cmake --build "$build" -j"$(nproc)" --target "fuzz_$t" >/dev/null || exit 1
done
work=$build/work
mkdir -p "$work/seeds"
# Seeds, made once: a small generated survey (BAL text and .dba) and a COLMAP
# model in both formats.
if [ ! -f "$work/seeds/s.dba" ]; then
  [ -x "$root/build/dba" ] || bash "$root/scripts/build.sh" >/dev/null
  "$root/build/dba" generate "$work/seeds/s.txt" --images 6 --features 40 >/dev/null
  "$root/build/dba" generate "$work/seeds/s.dba" --images 6 --features 40 >/dev/null
  "$root/build/dba" generate "$work/seeds/p.dba" --images 6 --features 40 --model photo >/dev/null
  colmap=$root/../shared/data/colmap/mithunnallana_6img/sparse/0
  if [ -d "$colmap" ]; then
    { head -c 20000 "$colmap/cameras.txt"; printf '\0'; head -c 20000 "$colmap/images.txt"; printf '\0';
      head -c 20000 "$colmap/points3D.txt"; } >"$work/seeds/model.colmap_text"
    "$root/build/dba" solve "$colmap" -q --max-iterations 0 -o "$work/seeds/model_bin" \
      --colmap-format binary >/dev/null 2>&1
    { cat "$work/seeds/model_bin/cameras.bin"; printf '\n--\n'; cat "$work/seeds/model_bin/images.bin";
      printf '\n--\n'; head -c 30000 "$work/seeds/model_bin/points3D.bin"; } >"$work/seeds/model.colmap_binary"
  fi
fi
printf '| target | seconds | executions | coverage (edges) | features | corpus | findings |\n|---|---:|---:|---:|---:|---:|---:|\n'
for t in "${targets[@]}"; do
  corpus=$work/corpus_$t
  rm -rf "$work/artifacts_$t"
  mkdir -p "$corpus" "$work/artifacts_$t" "$root/fuzz/regressions/$t"
  case $t in
    bal_text) cp "$work/seeds/s.txt" "$corpus/" ;;
    dba_binary) cp "$work/seeds/s.dba" "$work/seeds/p.dba" "$corpus/" ;;
    colmap_text) cp "$work/seeds/model.colmap_text" "$corpus/" 2>/dev/null ;;
    colmap_binary) cp "$work/seeds/model.colmap_binary" "$corpus/" 2>/dev/null ;;
  esac
  "$build/fuzz/fuzz_$t" "$corpus" -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 \
    -artifact_prefix="$work/artifacts_$t/" -print_final_stats=1 >"$work/$t.log" 2>&1
  findings=0
  for a in "$work/artifacts_$t"/*; do
    [ -e "$a" ] || continue
    cp "$a" "$root/fuzz/regressions/$t/"; findings=$((findings + 1))
  done
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$work/$t.log" | grep -o '[0-9]*$')
  cov=$(grep -o 'cov: [0-9]*' "$work/$t.log" | tail -1 | grep -o '[0-9]*')
  ft=$(grep -o 'ft: [0-9]*' "$work/$t.log" | tail -1 | grep -o '[0-9]*')
  corp=$(grep -o 'corp: [0-9]*' "$work/$t.log" | tail -1 | grep -o '[0-9]*')
  printf '| %s | %s | %s | %s | %s | %s | %s |\n' "$t" "$seconds" "${execs:-?}" "${cov:-?}" "${ft:-?}" "${corp:-?}" "$findings"
done
