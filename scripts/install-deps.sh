#!/usr/bin/env bash
# Installs every Debian package Signorini needs to build, test and run its examples.
# Idempotent and quick when everything is present (no apt-get update in that case).
set -euo pipefail
PKGS=(
  build-essential cmake ninja-build ccache pkg-config
  libeigen3-dev libsuitesparse-dev libopenblas0-pthread libgmsh-dev gmsh
  libyaml-cpp-dev libcli11-dev libfmt-dev
  libgtest-dev libgmock-dev googletest libbenchmark-dev
  python3-numpy python3-matplotlib
  petsc-dev libopenmpi-dev openmpi-bin
  pybind11-dev python3-dev python3-yaml
)
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps: done"
