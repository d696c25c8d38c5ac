#!/usr/bin/env bash
# Regenerates the flat Modelica files that Scilab's translator `modelicat`
# writes for our models, so that they stay in step with their sources:
#   modelica/CartPendulum/*_flat.mo (+ *_flat_init.xml)   from MoLib.mo and the
#       cart-pendulum models (flat class name = file name without .mo)
#   tests/frontend/data/scilab/NAME.flat.mo                from the MANIFEST there,
#       and checks the unknown/equation/parameter counts listed in it.
# modelicat is taken from $MODELICAT, else $MO_SCILAB_DIR (default
# /opt/mocompile/scilab, see scripts/install-deps.sh), else /tmp/scilab/root.
# MoLibExamples are flattened into a scratch folder only (acceptance check).
# If Scilab's modelicac sits beside modelicat, every flat file is also compiled
# by it (into the scratch folder): modelicac checks that the equations are
# structurally solvable.
# Exit status is non-zero if modelicat/modelicac fails or a count differs.
set -euo pipefail

repo=$(cd "$(dirname "$0")/.." && pwd)
scilab_dir=${MO_SCILAB_DIR:-/opt/mocompile/scilab}
if [ -z "${MODELICAT:-}" ]; then
  for d in "$scilab_dir" /tmp/scilab/root; do
    if [ -x "$d/usr/bin/modelicat" ]; then scilab_dir=$d; MODELICAT=$d/usr/bin/modelicat; break; fi
  done
fi
if [ -z "${MODELICAT:-}" ] || [ ! -x "$MODELICAT" ]; then
  echo "make-flat-models: modelicat not found; run scripts/install-deps.sh or set MODELICAT" >&2
  exit 1
fi
macros=$scilab_dir/usr/share/scilab/modules/scicos_blocks/macros
MODELICAC=${MODELICAC:-$(dirname "$MODELICAT")/modelicac}
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
counts=$repo/scripts/flat-counts.sh
status=0

# flatten OUT COMMAND [LIB...]: run modelicat; on failure show its message
# and remove the partial output it may leave behind.
flatten() {
  local out=$1 command=$2; shift 2
  local args=() lib log
  for lib in "$@"; do args+=(-lib "$lib"); done
  log=$(mktemp)
  if ! "$MODELICAT" "${args[@]}" -o "$out" "${extra[@]}" -command "$command" >"$log" 2>&1; then
    echo "make-flat-models: modelicat failed on '$command':" >&2
    sed '1,7d' "$log" >&2
    rm -f "$out" "${out%.mo}_init.xml" "${out%.mo}_relations.xml" "$log"
    status=1
    return 1
  fi
  rm -f "$log" "${out%.mo}_relations.xml"
  compile "$out"
}

# compile FLAT: run modelicac on a flat file, if modelicac is there.
compile() {
  [ -x "$MODELICAC" ] || return 0
  local base log
  base=$(basename "${1%.mo}")
  log=$scratch/$base.modelicac.log
  if ! (cd "$scratch" && "$MODELICAC" "$1" -o "$scratch/$base.c" >"$log" 2>&1) ||
     grep -q "Fatal error" "$log"; then
    echo "make-flat-models: modelicac rejects $1:" >&2
    grep -i "error" "$log" >&2 || true
    status=1
    return 1
  fi
}

# --- cart-pendulum: Xcos flat form with the initialisation file -------------
cp_dir=$repo/modelica/CartPendulum
extra=(-with-init)
for model in CartPendulumODE CartPendulumSine CartPendulumODEPar CartPendulumSinePar; do
  flatten "$cp_dir/${model}_flat.mo" "$model ${model}_flat;" \
    "$cp_dir/CartPendulumODE.mo" && "$counts" "$cp_dir/${model}_flat.mo" | sed "s|$repo/||"
done
for model in CartPendulumComponents CartPendulumComponentsSine \
             CartPendulumComponentsPar CartPendulumComponentsSinePar; do
  flatten "$cp_dir/${model}_flat.mo" "$model ${model}_flat;" \
    "$repo/modelica/MoLib.mo" "$cp_dir/CartPendulumComponents.mo" &&
    "$counts" "$cp_dir/${model}_flat.mo" | sed "s|$repo/||"
done

# --- MoLib examples: flattened and compiled in the scratch folder only ------
for model in SpringMassPulse RotationalStep PlanarPendulum; do
  flatten "$scratch/$model.mo" "MoLibExamples.$model ${model}_flat;" \
    "$repo/modelica/MoLib.mo" "$repo/modelica/MoLibExamples.mo" &&
    "$counts" "$scratch/$model.mo" | sed "s|$scratch/|(scratch) |"
done

# --- Scilab library test circuits: regenerate and check MANIFEST counts -----
data=$repo/tests/frontend/data/scilab
extra=()
while read -r file library class instance unknowns equations parameters; do
  case $file in ''|'#'*) continue ;; esac
  out=$data/${file%.mo}.flat.mo
  flatten "$out" "$class $instance;" "$macros/$library/$library.mo" "$data/$file" || continue
  got=$("$counts" "$out")
  want="unknowns=$unknowns equations=$equations parameters=$parameters"
  case $got in
    *"$want "*) echo "ok   $file: $want" ;;
    *) echo "FAIL $file: want $want, got ${got#* }" >&2; status=1 ;;
  esac
done < "$data/MANIFEST"

exit $status
