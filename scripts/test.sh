#!/usr/bin/env bash
# The README's test command: installs what is missing (Scilab included, for
# the tests that read Xcos diagrams), builds, runs the tests.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/install-deps.sh" --with-scilab
"$root/scripts/build.sh" "$@"
build=${MO_BUILD_DIR:-$root/build}
ctest --test-dir "$build" --output-on-failure -j "$(nproc)"
