#!/usr/bin/env bash
# Installs what mocompile needs on Debian 12 (run as root); does nothing for
# what is already there. Also unpacks Scilab's Modelica translator `modelicat`
# and its component libraries (Electrical.mo, Hydraulics.mo) into
# $MO_SCILAB_DIR (default /opt/mocompile/scilab): the tests use them as the
# reference flattener. No Java, no GUI: modelicat needs only libc.
set -euo pipefail

packages=(
  build-essential cmake ninja-build ccache pkg-config
  libeigen3-dev coinor-libipopt-dev libsundials-dev
  antlr4 libantlr4-runtime-dev libfmt-dev catch2 libcli11-dev nlohmann-json3-dev
  gnuplot-nox jq clang-14 libclang-rt-14-dev
  chromium  # the test that opens report.html headless
  libopenmpi-dev openmpi-bin  # optional: multistart across machines (mpirun -n K morun)
)

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
