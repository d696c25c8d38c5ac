#!/usr/bin/env bash
# Prints the pass table of the Xcos corpus (issue 10): every diagram of
# ../shared/xcos-corpus (or $MO_SHARED_DIR/xcos-corpus) flattened from both
# files, lowered, simulated and compared with Scilab's simulation.
# Usage: bench/xcos_corpus.sh [BUILD_DIR] [DIAGRAM...]   (default build/)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
shift || true
[ -x "$build/bench/xcos_corpus_table" ] || { echo "build first: cmake --build $build --target xcos_corpus_table" >&2; exit 1; }
export XDG_CACHE_HOME=${XDG_CACHE_HOME:-$build/morun-test-cache}
exec "$build/bench/xcos_corpus_table" "$@"
