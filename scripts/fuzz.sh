#!/usr/bin/env bash
# Runs the parser fuzzer for a bounded time: scripts/fuzz.sh [SECONDS].
# Seeds: every .mo file of the repository. Crashes are written to
# build-fuzz/crashes/ and make the script fail.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-60}
build=$root/build-fuzz
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
cmake --build "$build" --target parse_fuzzer -j "$(nproc)"
corpus=$build/corpus
mkdir -p "$corpus" "$build/crashes"
seeds=$build/seeds
rm -rf "$seeds" && mkdir -p "$seeds"
i=0
while IFS= read -r -d '' f; do
  # keep seeds small so mutations stay fast
  if [ "$(stat -c %s "$f")" -le 65536 ]; then cp "$f" "$seeds/seed_$i.mo"; i=$((i + 1)); fi
done < <(find "$root/modelica" "$root/tests" -name '*.mo' -print0)
echo "fuzz: $i seeds, $seconds s"
"$build/frontend/parse_fuzzer" -max_total_time="$seconds" -max_len=8192 -timeout=10 \
  -rss_limit_mb=4096 -print_final_stats=1 -artifact_prefix="$build/crashes/" "$corpus" "$seeds" 2>&1 | tail -15
