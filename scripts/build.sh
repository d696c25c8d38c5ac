#!/usr/bin/env bash
# Configures and builds mocompile into $MO_BUILD_DIR (default build/).
# Extra arguments go to CMake's configure step.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${MO_BUILD_DIR:-$root/build}
export CCACHE_DIR=${CCACHE_DIR:-$HOME/.cache/ccache}
# Paths relative to the checkout, so that clones and worktrees share the cache.
export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$root} CCACHE_NOHASHDIR=${CCACHE_NOHASHDIR:-true}
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=${MO_BUILD_TYPE:-RelWithDebInfo} \
  -DMO_SCILAB_DIR=${MO_SCILAB_DIR:-/opt/mocompile/scilab} "$@"
cmake --build "$build" -j "$(nproc)"
