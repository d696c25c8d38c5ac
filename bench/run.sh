#!/usr/bin/env bash
# Runs every benchmark and rewrites the "Latest run" section of
# docs/benchmarks.md (between its two marker comments) with the machine,
# compiler and library versions, the date and each program's figures.
# Tables report the median of $RUNS runs (default 5), each size in a fresh
# process so that peak RSS is that run's own; the per-program outputs say
# what they measured. FULL=1 adds the largest sizes (10^4-unit code
# generation, 20 000-unit flattening: several minutes each).
# Usage: bench/run.sh [BUILD_DIR]   (default build/)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
runs=${RUNS:-5}
median=$(( (runs + 1) / 2 ))
[ -x "$build/bench/frontend_scale" ] || { echo "build first: scripts/build.sh" >&2; exit 1; }
doc=$root/docs/benchmarks.md
section=$(mktemp)
trap 'rm -f "$section"' EXIT
big=""; [ "${FULL:-0}" = 1 ] && big="20000"

{
  echo "Machine: $(nproc) cores, $(awk '/MemTotal/ { printf "%.0f GiB", $2 / 1048576 }' /proc/meminfo),"
  echo "$(. /etc/os-release && echo "$PRETTY_NAME"), $(c++ --version | head -1); SUNDIALS"
  echo "$(dpkg-query -W -f='${Version}' libsundials-dev 2>/dev/null), Ipopt"
  echo "$(dpkg-query -W -f='${Version}' coinor-libipopt-dev 2>/dev/null); $(date -u +%Y-%m-%d), median of $runs runs."
  echo
  echo "### Parse + flatten (\`frontend_scale KIND N\`)"
  echo
  echo "| chain | N | flat equations | parse s | flatten s | peak RSS MB |"
  echo "|---|---:|---:|---:|---:|---:|"
  for kind in msd rc; do
    for n in 100 1000 10000 $big; do
      for r in $(seq "$runs"); do "$build/bench/frontend_scale" "$kind" "$n"; done |
        sort -k5 -g | awk -v m=$median 'NR == m { printf "| %s | %s | %s | %s | %s | %s |\n", $1, $2, $3, $4, $5, $6 }'
    done
  done
  echo
  echo "### Flatten + lower + sensitivities for K parameters (\`lower_scale KIND N K\`)"
  echo
  echo "| chain | N | K | flat equations | states | flatten s | lower s | sensitivities s | peak RSS MB |"
  echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|"
  for kind in msd rc; do
    for n in 100 1000 10000; do
      for k in 0 1 5; do
        for r in $(seq "$runs"); do "$build/bench/lower_scale" "$kind" "$n" "$k"; done |
          sort -k7 -g | awk -v m=$median 'NR == m { printf "| %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", $1, $2, $3, $4, $5, $6, $7, $8, $9 }'
      done
    done
  done
  echo
  echo "### Cart-pendulum simulation, 10 s (\`simulate_cart_pendulum $runs\`, median wall time)"
  echo
  echo '```'
  "$build/bench/simulate_cart_pendulum" "$runs"
  echo '```'
  echo
  echo "### Large sparse simulations, dense LU against KLU (\`simulate_scale\`)"
  echo
  echo '```'
  "$build/bench/simulate_scale" 50 200 1000 2000 2>&1
  echo '```'
  echo
  echo "### Generated-code compile time and cached rerun (\`codegen_scale\`)"
  echo
  echo '```'
  "$build/bench/codegen_scale" 100 1000 ${big:+10000} 2>&1
  echo '```'
  echo
  echo "### Cart-pendulum input designs, exact Hessians (\`optim_cart_pendulum\`, generated model)"
  echo
  echo '```'
  "$build/bench/optim_cart_pendulum" 2>&1 || true
  echo '```'
  report=$root/results/cart-pendulum/report.md
  if [ -f "$report" ]; then
    echo
    echo "### The main job (\`scripts/cart-pendulum-study.sh\`), from its last run"
    echo
    grep -E '^\| design|^\| noisy|^\| noise-free' "$report" | head -8 | sed 's/^/    /'
    echo
    echo "    total: $(grep -o 'done: .* ([0-9]* s)' "$root/results/cart-pendulum/logs/study.log" 2>/dev/null || echo 'see logs/')"
  fi
} > "$section"

awk -v file="$section" '
  /<!-- bench\/run.sh: begin -->/ { print; while ((getline line < file) > 0) print line; skip = 1; next }
  /<!-- bench\/run.sh: end -->/ { skip = 0 }
  !skip { print }' "$doc" > "$doc.tmp"
grep -q '<!-- bench/run.sh: begin -->' "$doc.tmp" || {
  { cat "$doc"; echo; echo "## Latest run (\`bench/run.sh\`)"; echo; echo "<!-- bench/run.sh: begin -->";
    cat "$section"; echo "<!-- bench/run.sh: end -->"; } > "$doc.tmp"; }
mv "$doc.tmp" "$doc"
echo "bench/run.sh: rewrote the latest-run section of $doc"
