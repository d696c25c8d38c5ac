#!/usr/bin/env bash
# The README's main command: installs what is missing, builds, and runs the
# main job — the cart-pendulum study of the paper end to end (simulation
# check, input design, estimation, the design <-> estimation loop and a
# Monte-Carlo check), writing results/cart-pendulum/ with report.md and its
# plots. SEEDS sets the Monte-Carlo size (default 100).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh"
"$root/scripts/cart-pendulum-study.sh" "${MO_BUILD_DIR:-$root/build}"
