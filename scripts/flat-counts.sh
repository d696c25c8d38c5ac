#!/usr/bin/env bash
# Counts what a flat Modelica file written by modelicat declares, so that the
# expected counts in tests/frontend/data/scilab/MANIFEST can be regenerated:
#   unknowns   = Real declarations that are not parameters and not top-level
#                inputs (a top-level input has no dot in its name; modelicat
#                also writes `input`/`output` on the signal variables of
#                nested components, and those are unknowns)
#   equations  = equation lines (one per line in modelicat output), including
#                `v = expr;` inside when-clauses (first branch only: the
#                elsewhen branches assign the same variables), excluding reinit
#   parameters = `parameter Real` declarations
#   inputs     = top-level inputs;  reinits = reinit(...) statements
# Usage: scripts/flat-counts.sh FILE.mo...   (prints one line per file)
set -euo pipefail
for f in "$@"; do
  awk -v file="$f" '
    /^equation$/ { in_eq = 1; next }
    /^end when;/ { in_when = 0; in_else = 0; next }
    /^end / && in_eq { in_eq = 0; next }
    !in_eq && /^\t/ {
      if ($0 ~ /^\tparameter /) { npar++; next }
      name = $0; sub(/^[^`]*`/, "", name); sub(/`.*/, "", name)
      if ($0 ~ /^\tinput / && name !~ /\./) { nin++; next }
      nunk++; next
    }
    in_eq {
      if ($0 ~ /^when /) { in_when = 1; next }
      if ($0 ~ /^elsewhen /) { in_else = 1; next }
      if ($0 ~ /^\treinit\(/) { if (!in_else) nre++; next }
      if (in_else) next
      if ($0 ~ /;[ \t]*$/) neq++
    }
    END { printf "%s unknowns=%d equations=%d parameters=%d inputs=%d reinits=%d\n",
          file, nunk, neq, npar, nin, nre }
  ' "$f"
done
