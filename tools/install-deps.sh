#!/usr/bin/env bash
# Installs the Debian 12 packages Atmo builds, tests and runs with.
# Idempotent: installs only what is missing, so a warm machine pays nothing.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config python3 python3-glad
  libglm-dev libegl-dev libgl-dev libgl1-mesa-dri libegl-mesa0 mesa-utils xvfb xauth
  libglfw3-dev libimgui-dev
  libopenexr-dev libpng-dev
  nlohmann-json3-dev libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libgeographiclib-dev liberfa-dev libnova-dev
  libvtk9-dev libopenvdb-dev libboost-iostreams-dev
  openimageio-tools binutils
  clang libclang-rt-14-dev
  colord-data
  kstars-data
  openmpi-bin libopenmpi-dev
  libopenscenegraph-dev libpugixml-dev
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "[atmo] all ${#PACKAGES[@]} Debian packages present"
  exit 0
fi

echo "[atmo] installing ${#missing[@]} missing Debian packages: ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
