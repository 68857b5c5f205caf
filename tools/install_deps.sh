#!/usr/bin/env bash
# Installs what quadcage needs from Debian 12 packages, and nothing when all of it is present.
# Run as root (or with sudo available). Idempotent.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libosd-dev libopenmesh-dev libceres-dev libembree-dev libeigen3-dev libgtest-dev
  libcli11-dev nlohmann-json3-dev libpng-dev
  python3 python3-numpy python3-scipy
  clang libclang-rt-14-dev
  # OpenBLAS takes over libblas.so.3 / liblapack.so.3 (Debian's alternatives) from the ATLAS that
  # libceres-dev pulls in: CHOLMOD's dense kernels in the fit's solver, about 12% less solve time
  # on botijo (tools/bench/fit_speed.sh).
  libopenblas0-pthread
  # OpenCASCADE 7.6 for the CAD export (module cad only: B-spline faces, sewing, STEP and IGES).
  libocct-foundation-dev libocct-modeling-data-dev libocct-modeling-algorithms-dev libocct-data-exchange-dev
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install_deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq "${missing[@]}"
