#!/usr/bin/env bash
# The design <-> estimation loop (the paper's future work) on the
# cart-pendulum: design the input at the current estimate of m2, run the
# experiment (the plant simulated at the true m2 = 1 with sigma = 0.01 noise,
# a new seed per round), estimate m2, and repeat until the estimate moves
# less than its standard error. Every round is logged in OUT/loop.csv.
# Usage: scripts/design-estimate-loop.sh BUILD_DIR OUT M2_START [MAX_ROUNDS]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$1 out=$2 m2=$3 rounds=${4:-6}
morun=$build/tools/morun
cp=$root/modelica/CartPendulum
ode=$cp/CartPendulumODE.mo
mkdir -p "$out"
echo "round,m2_design,information_T,m2_estimate,standard_error,ci_lo,ci_hi,design_iterations,design_solve_s,estimate_iterations,estimate_solve_s" \
  > "$out/loop.csv.tmp"
for round in $(seq "$rounds"); do
  r=$out/round$round
  mkdir -p "$r"
  # One start and at most 400 iterations: an iteration-limited design is
  # still a usable (if not optimal) experiment, so the loop goes on with it.
  "$morun" "$cp/CartPendulumDesign.opt" -L "$ode" --set "m2=$m2" -o "$r/design" \
    --option 'starts={"const:0"}' --option max_iter=400 >"$r/design.log" 2>&1 ||
    [ -f "$r/design/designed_input.csv" ] || { tail "$r/design.log"; exit 1; }
  "$morun" "$ode" -c CartPendulumODE --stop-time 5 --intervals 500 --rtol 1e-10 --atol 1e-12 \
    --input "F=pwc:$r/design/designed_input.csv" --measure y_x,y_phi --noise 0.01 --seed "$round" \
    -o "$r/data" >"$r/data.log" 2>&1 || { tail "$r/data.log"; exit 1; }
  "$morun" "$cp/CartPendulumEstimate.opt" -L "$ode" -o "$r/estimate" \
    --option "data={\"$r/data/measurements.csv\"}" \
    --option "inputs={\"F=pwc:$r/design/designed_input.csv\"}" >"$r/estimate.log" 2>&1 ||
    { tail "$r/estimate.log"; exit 1; }
  info=$(jq -r '.design.information_resimulated' "$r/design/summary.json")
  read -r est se lo hi < <(jq -r '.estimates[0] | "\(.estimate) \(.standard_error) \(.ci[0]) \(.ci[1])"' \
    "$r/estimate/summary.json")
  read -r d_it d_s < <(jq -r '"\(.iterations) \(.timings_seconds.solve)"' "$r/design/summary.json")
  read -r e_it e_s < <(jq -r '"\(.iterations) \(.timings_seconds.solve)"' "$r/estimate/summary.json")
  echo "$round,$m2,$info,$est,$se,$lo,$hi,$d_it,$d_s,$e_it,$e_s" >> "$out/loop.csv.tmp"
  printf "loop round %d: designed at m2 = %.4f (F = %.1f), estimate %.4f +- %.4f\n" \
    "$round" "$m2" "$info" "$est" "$se"
  done=$(awk -v a="$m2" -v b="$est" -v s="$se" 'BEGIN { d = a - b; if (d < 0) d = -d; print (d < s) }')
  m2=$est
  [ "$done" = 1 ] && break
done
mv "$out/loop.csv.tmp" "$out/loop.csv"
