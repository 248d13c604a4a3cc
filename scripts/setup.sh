#!/usr/bin/env bash
# Installs what is missing (Debian 12 packages, through apt; as root or via sudo), then
# configures and builds asperity (Release by default, incremental). Executables land in
# build/bin/. Usage: scripts/setup.sh [extra cmake -D options]
# Environment: BUILD_DIR (default build), BUILD_TYPE (default Release), JOBS (default nproc).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"

packages=(
  build-essential cmake pkg-config git clang-format
  libeigen3-dev libfftw3-dev libsundials-dev libboost-graph-dev
  libgtest-dev libgmock-dev libbenchmark-dev libcli11-dev libtomlplusplus-dev nlohmann-json3-dev
  libnetcdf-dev netcdf-bin libspectra-dev gnuplot-nox
  python3-xarray python3-netcdf4 python3-ase python3-vtk9 python3-pytest python3-matplotlib
  pybind11-dev python3-pybind11
  libopenmpi-dev openmpi-bin libfftw3-mpi-dev
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}" >&2
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "setup: need root or sudo to install ${missing[*]}" >&2; exit 1; }
    sudo=sudo
  fi
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

build_dir=${BUILD_DIR:-build}
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE="${BUILD_TYPE:-Release}" "$@" >/dev/null
cmake --build "$build_dir" -j "${JOBS:-$(nproc)}"
