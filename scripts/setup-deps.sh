#!/usr/bin/env bash
# Installs the Debian packages Littoral builds against, skipping those already present.
# Idempotent: a second run installs nothing. Needs root (or sudo) on Debian 12.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config
  libcgal-dev libgmp-dev libmpfr-dev libboost-dev
  libopenmesh-dev
  libembree-dev
  libgeographiclib-dev
  libopenimageio-dev openimageio-tools
  libgtest-dev libgmock-dev libbenchmark-dev
  libtbb-dev
  libyaml-cpp-dev
  libcli11-dev
  libnanoflann-dev
  libfftw3-dev
  libfmt-dev
  nlohmann-json3-dev
  libgdal-dev                # GeoTIFF and ENVI georeferencing (pipelines/lib_geotiff.cpp)
  python3-dev pybind11-dev python3-numpy python3-pytest python3-matplotlib   # the Python package (python/)
  clang libclang-rt-14-dev   # libFuzzer targets (fuzz/), smoke-run by the test suite
  libopenmpi-dev openmpi-bin # MPI runs (pipelines/lib_mpi.cpp) and their tests under mpirun
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup-deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "setup-deps: installing ${#missing[@]} package(s): ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
