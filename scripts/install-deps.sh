#!/usr/bin/env bash
# Installs what mocompile needs on Debian 12 (run as root); does nothing for
# what is already there. Also unpacks Scilab's Modelica translator `modelicat`
# and its component libraries (Electrical.mo, Hydraulics.mo) into
# $MO_SCILAB_DIR (default /opt/mocompile/scilab): the tests use them as the
# reference flattener. No Java, no GUI: modelicat needs only libc.
#
# --with-scilab also installs Debian's Scilab (with Java, about 1 GB) and
# xvfb-run, which mocompile runs to read Xcos diagrams (.zcos, .xcos); the
# test command (scripts/test.sh) uses it for the diagram tests. The main job
# does not need it.
set -euo pipefail

with_scilab=0
for arg in "$@"; do
  case "$arg" in
    --with-scilab) with_scilab=1 ;;
    *) echo "install-deps: unknown option $arg (known: --with-scilab)" >&2; exit 2 ;;
  esac
done

packages=(
  build-essential cmake ninja-build ccache pkg-config
  libeigen3-dev coinor-libipopt-dev libsundials-dev
  libsuitesparse-dev  # KLU, the sparse linear solver of large simulations (also pulled by libsundials-dev)
  antlr4 libantlr4-runtime-dev libfmt-dev catch2 libcli11-dev nlohmann-json3-dev
  libmatio-dev  # MATLAB .mat result and measurement files
  libexpat1-dev  # reads the init file Scilab writes beside a diagram's flat model
  gnuplot-nox jq clang-14 libclang-rt-14-dev
  chromium  # the test that opens report.html headless
  libopenmpi-dev openmpi-bin  # optional: multistart across machines (mpirun -n K morun)
  python3  # bench/msl_examples.py, run by the slow test msl_examples_pinned
)
if [ "$with_scilab" = 1 ]; then
  # Scilab itself (launcher, Java GUI libraries, Xcos, the Modelica translator
  # and libraries) and a virtual X server to run it without a window.
  packages+=(scilab scilab-cli scilab-full-bin scilab-data xvfb xauth)
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "install-deps: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

scilab_dir=${MO_SCILAB_DIR:-/opt/mocompile/scilab}
if [ ! -x "$scilab_dir/usr/bin/modelicat" ] || \
   [ ! -f "$scilab_dir/usr/share/scilab/modules/scicos_blocks/macros/Electrical/Electrical.mo" ]; then
  echo "install-deps: unpacking modelicat and Scilab's Modelica libraries into $scilab_dir"
  tmp=$(mktemp -d)
  trap 'rm -rf "$tmp"' EXIT
  (cd "$tmp" && apt-get download scilab-full-bin scilab-data >/dev/null 2>&1 || \
     { apt-get update -qq && apt-get download scilab-full-bin scilab-data; })
  mkdir -p "$scilab_dir"
  for deb in "$tmp"/*.deb; do dpkg -x "$deb" "$scilab_dir"; done
fi
echo "install-deps: ok"
