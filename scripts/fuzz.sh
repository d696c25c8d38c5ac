#!/usr/bin/env bash
# Runs the front end's fuzz targets, one per stage (parse, flatten, lower,
# cpp: fuzz/stage_fuzzer.cpp), for a bounded total time split evenly between
# them: scripts/fuzz.sh [SECONDS] [STAGE...]. Seeds: every .mo/.mop/.opt file
# of the repository. Crashes are written to build-fuzz/crashes/STAGE/, printed
# in base64, and make the script fail.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-60}
build=$root/build-fuzz
export CCACHE_DIR=${CCACHE_DIR:-$HOME/.cache/ccache}
export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$root} CCACHE_NOHASHDIR=${CCACHE_NOHASHDIR:-true}
# clang rejects one constructor in Debian's ANTLR 4.9 runtime headers that
# g++ accepts (a defaulted member with a deleted default constructor); the
# fuzz build uses a copy of the headers with that unused constructor removed.
headers=$build/antlr4-runtime
if [ ! -f "$headers/antlr4-runtime.h" ]; then
  mkdir -p "$build"
  cp -r /usr/include/antlr4-runtime "$headers"
  sed -i 's/InterpreterData() {}; \/\/ For invalid content./InterpreterData() = delete;/' \
    "$headers/misc/InterpreterDataReader.h"
fi
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_COMPILER=clang++-14 -DMO_FUZZ=ON -DMO_BUILD_TESTS=OFF \
  -DMO_ANTLR4_INCLUDE_DIR="$headers" >/dev/null
stages=("${@:2}")
[ ${#stages[@]} -gt 0 ] || stages=(parse flatten lower cpp)
targets=()
for stage in "${stages[@]}"; do targets+=("fuzz_$stage"); done
cmake --build "$build" --target "${targets[@]}" -j "$(nproc)"
seeds=$build/seeds
max_len=8192
rm -rf "$seeds" && mkdir -p "$seeds"
i=0
while IFS= read -r -d '' f; do
  # seeds no longer than the inputs libFuzzer makes (-max_len): a larger one
  # is truncated anyway, and parsing 64 KB seeds at start-up took the whole
  # time budget (1-3 executions a second)
  if [ "$(stat -c %s "$f")" -le "$max_len" ]; then cp "$f" "$seeds/seed_$i.mo"; i=$((i + 1)); fi
done < <(find "$root/modelica" "$root/tests" \( -name '*.mo' -o -name '*.mop' -o -name '*.opt' \) -print0)
each=$(( seconds / ${#stages[@]} ))
[ "$each" -ge 1 ] || each=1
echo "fuzz: $i seeds, ${#stages[@]} stages, $each s each"
status=0
for stage in "${stages[@]}"; do
  corpus=$build/corpus/$stage crashes=$build/crashes/$stage
  mkdir -p "$corpus" "$crashes"
  echo "== fuzz_$stage"
  if ! "$build/fuzz/fuzz_$stage" -max_total_time="$each" -max_len="$max_len" -timeout=30 \
    -rss_limit_mb=4096 -print_final_stats=1 -artifact_prefix="$crashes/" "$corpus" "$seeds" \
    >"$build/fuzz_$stage.log" 2>&1; then
    status=1
    grep -E "ERROR|SUMMARY|Test unit written" "$build/fuzz_$stage.log" | head -20
    # CI keeps only the log: print each failing input (at most max_len bytes)
    # so that it can be rebuilt with `base64 -d` and run again.
    for unit in "$crashes"/*; do
      [ -f "$unit" ] || continue
      echo "-- $(basename "$unit") (base64):"
      base64 -w 120 "$unit"
    done
  fi
  tail -3 "$build/fuzz_$stage.log"
done
exit $status
