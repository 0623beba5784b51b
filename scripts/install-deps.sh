#!/usr/bin/env bash
# Installs MotionMap's build and test dependencies from Debian's packages (Debian 12 "bookworm").
# Idempotent: packages already present are left alone and apt is not touched at all when nothing
# is missing, so `make test` on a prepared machine does not need the network.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config clang-format dpkg-dev
  libeigen3-dev libspectra-dev libnanoflann-dev libhnswlib-dev libhdf5-dev libxxhash-dev libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  # The GP-LVM (embed/gplvm.cpp) optimises with the LBFGS++ headers.
  liblbfgspp-dev
  # SHA-256 of clip files (core/sha256.cpp), by OpenSSL's libcrypto.
  libssl-dev
  qt6-base-dev libqt6opengl6-dev qt6-svg-dev libgl-dev libglx-mesa0 libgl1-mesa-dri fonts-dejavu-core
  clang libclang-rt-14-dev
  python3 python3-numpy python3-scipy python3-sklearn python3-h5py python3-xxhash
  pybind11-dev python3-pybind11 python3-pytest python3-dask python3-distributed python3-tqdm
  xvfb xauth
  # Studio's File → Export animation encodes MP4 with ffmpeg (its tests check it with ffprobe).
  ffmpeg
  # bench/*_figure.py draw the docs' pictures with it.
  python3-matplotlib
  # A test reference only: tests/reference/make_umap_fixtures.py regenerates umap's fixtures
  # with it (nothing builds or runs against it).
  umap-learn
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
