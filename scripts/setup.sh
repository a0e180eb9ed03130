#!/usr/bin/env bash
# Installs the Debian packages ictus needs (only those missing), then configures and builds
# ictus in BUILD_DIR (default: build/ in the repository). Safe to run again: a second run
# installs nothing and rebuilds only what changed.
#   scripts/setup.sh [Release|Debug]
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_type=${1:-Release}
build_dir=${BUILD_DIR:-$here/build}

packages=(gfortran cmake ninja-build libopenmpi-dev openmpi-bin libhdf5-openmpi-dev
  libmetis-dev liblapack-dev libopenblas-dev python3 python3-numpy python3-h5py
  python3-matplotlib hdf5-tools shellcheck gmsh python3-gmsh)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# Open MPI refuses to run as root without these (containers, CI); harmless otherwise.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

if [ ! -f "$build_dir/build.ninja" ]; then
  cmake -S "$here" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE="$build_type" \
    -DPython3_EXECUTABLE=/usr/bin/python3 >/dev/null
fi
cmake --build "$build_dir" -j "$(nproc)"
