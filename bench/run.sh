#!/usr/bin/env bash
# Runs the benchmarks and prints a Markdown table (median of $RUNS runs,
# each N in a fresh process so peak RSS is that run's own).
# Usage: bench/run.sh [BUILD_DIR]   (default build/)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
runs=${RUNS:-5}
bin=$build/bench/frontend_scale
[ -x "$bin" ] || { echo "build first: scripts/build.sh" >&2; exit 1; }
echo "| chain | N | flat equations | parse s | flatten s | peak RSS MB |"
echo "|---|---:|---:|---:|---:|---:|"
for kind in msd rc; do
  for n in 100 1000 10000 20000; do
    for r in $(seq "$runs"); do "$bin" "$kind" "$n"; done |
      sort -k5 -g | awk -v m=$(( (runs + 1) / 2 )) 'NR == m { printf "| %s | %s | %s | %s | %s | %s |\n", $1, $2, $3, $4, $5, $6 }'
  done
done

lower=$build/bench/lower_scale
echo
echo "| chain | N | sensitivities | flat equations | states | flatten s | lower s | sensitivities s | peak RSS MB |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|"
for kind in msd rc; do
  for n in 100 1000 10000; do
    for k in 0 1 5; do
      for r in $(seq "$runs"); do "$lower" "$kind" "$n" "$k"; done |
        sort -k7 -g | awk -v m=$(( (runs + 1) / 2 )) 'NR == m { printf "| %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", $1, $2, $3, $4, $5, $6, $7, $8, $9 }'
    done
  done
done
