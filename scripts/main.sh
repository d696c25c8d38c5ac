#!/usr/bin/env bash
# The README's main command: installs what is missing, builds, and runs the
# main job. Until the optimisation stages land, the main job flattens the
# cart-pendulum (equation model and component model) and writes the results
# to results/cart-pendulum/.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh"
build=${MO_BUILD_DIR:-$root/build}
out=$root/results/cart-pendulum
mkdir -p "$out"
m=$root/modelica
echo "main: flattening the cart-pendulum equation model"
"$build/tools/mocompile" "$m/CartPendulum/CartPendulumODE.mo" --class CartPendulumODE -o "$out/CartPendulumODE.flat.mo"
echo "main: flattening the component model built from MoLib"
"$build/tools/mocompile" "$m/CartPendulum/CartPendulumComponents.mo" -L "$m/MoLib.mo" \
  --class CartPendulumComponents -o "$out/CartPendulumComponents.flat.mo"
echo "main: reading the Xcos flat form written by Scilab's modelicat"
"$build/tools/mocompile" "$m/CartPendulum/CartPendulumComponents_flat.mo" -o "$out/CartPendulumComponents_xcos.flat.mo"
echo "main: results in $out"
ls -l "$out"
