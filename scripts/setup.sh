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
  python3-matplotlib python3-meshio hdf5-tools shellcheck gmsh python3-gmsh)
# For the ParaView test of the XDMF sidecar (scripts/xdmf_paraview, skipped without them):
# about 135 MB to download, 700 MB installed, 45 s here. Tried, not required: set
# ICTUS_NO_PARAVIEW=1 to leave them out.
optional=(python3-paraview xvfb xauth)
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
# missing_of PACKAGE...: the ones not installed, one a line.
missing_of() {
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || echo "$p"
  done
}
apt_install() {
  $sudo apt-get update -qq &&
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "$@" >/dev/null
}
mapfile -t missing < <(missing_of "${packages[@]}")
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  apt_install "${missing[@]}"
fi
if [ -z "${ICTUS_NO_PARAVIEW:-}" ]; then
  mapfile -t missing < <(missing_of "${optional[@]}")
  if ((${#missing[@]})); then
    echo "setup: installing ${missing[*]} (optional: the ParaView test)"
    apt_install "${missing[@]}" ||
      echo "setup: could not install ${missing[*]}: the ParaView test will be skipped"
  fi
fi

# Open MPI refuses to run as root without these (containers, CI); harmless otherwise.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

if [ ! -f "$build_dir/build.ninja" ]; then
  cmake -S "$here" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE="$build_type" \
    -DPython3_EXECUTABLE=/usr/bin/python3 >/dev/null
fi
cmake --build "$build_dir" -j "$(nproc)"
