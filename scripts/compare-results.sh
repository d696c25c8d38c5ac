#!/usr/bin/env bash
# Compares the outputs y_x and y_phi of several morun results (the paper's
# Fig. 5 check): prints the largest absolute difference of each result from
# the first, and draws them over each other in DIR/fig5.png and fig5.svg
# (title, axes with the units from the first run's summary.json, legend).
# Usage: scripts/compare-results.sh DIR REF OTHER...   (DIR/NAME/result.csv each)
set -euo pipefail
dir=$1; ref=$2; shift 2
col() {  # the 1-based column of header name $2 in CSV $1
  head -1 "$1" | tr ',' '\n' | grep -nx "$2" | cut -d: -f1
}
for other in "$@"; do
  for y in y_x y_phi; do
    a=$dir/$ref/result.csv b=$dir/$other/result.csv
    paste -d, <(cut -d, -f"$(col "$a" "$y")" "$a") <(cut -d, -f"$(col "$b" "$y")" "$b") |
      awk -F, -v y="$y" -v r="$ref" -v o="$other" 'NR > 1 { d = $1 - $2; if (d < 0) d = -d; if (d > m) m = d }
        END { printf "largest |%s(%s) - %s(%s)| over t in [0, 10]: %.3g\n", y, o, y, r, m }'
  done
done
# Units of the outputs from the reference run's summary.json (morun writes them).
unit() { jq -r --arg y "$1" '.units[$y] // empty' "$dir/$ref/summary.json" 2>/dev/null || true; }
label() { local u; u=$(unit "$1"); [ -n "$u" ] && echo "$1 [$u]" || echo "$1"; }
body() {
  echo "set datafile separator ','"
  echo "set key outside right top"
  echo "set grid"
  echo "set multiplot layout 2,1 title 'Simulation check (paper Fig. 5): the same outputs from $ref and $*'"
  for y in y_x y_phi; do
    printf "set ylabel '%s'\n" "$(label "$y")"
    [ "$y" = y_phi ] && echo "set xlabel 'time [s]'" || echo "unset xlabel"
    printf "plot "
    sep=""
    for name in "$ref" "$@"; do
      printf "%s'%s' using 1:%s with lines lw %s title '%s'" "$sep" "$dir/$name/result.csv" \
        "$(col "$dir/$name/result.csv" "$y")" "$([ "$name" = "$ref" ] && echo 4 || echo 1.5)" "$name"
      sep=", "
    done
    echo
  done
  echo "unset multiplot"
}
{
  echo "set terminal pngcairo noenhanced size 900,600 font 'sans,10'"
  echo "set output '$dir/fig5.png'"
  body "$@"
  echo "set terminal svg noenhanced size 900,600 font 'sans,11' background '#ffffff'"
  echo "set output '$dir/fig5.svg'"
  body "$@"
} > "$dir/fig5.gp"
gnuplot "$dir/fig5.gp"
