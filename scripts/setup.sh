#!/usr/bin/env bash
# Installs the Debian 12 packages photoscene builds with, skipping those already present.
# Run as root (or with sudo available). README.md says why each dependency is here.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config
  libopencv-dev libopencv-contrib-dev   # image work, ximgproc segmentation, quality metrics
  libeigen3-dev                         # small linear algebra, least squares
  libopenimageio-dev                    # PNG / JPEG / EXR / HDR reading and writing
  libtinyobjloader-dev                  # OBJ parsing
  libflann-dev liblz4-dev               # kNN index (FLANN needs lz4)
  libembree-dev                         # ray tracing BVH
  libtbb-dev                            # parallel loops
  nlohmann-json3-dev                    # JSON
  libcli11-dev                          # command line
  libspdlog-dev libfmt-dev              # logging
  libtinygltf-dev                       # glTF export
  libgtest-dev libgmock-dev             # unit tests
  libbenchmark-dev                      # micro benchmarks
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "[setup] all ${#PACKAGES[@]} packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "[setup] missing packages: ${missing[*]}" >&2
    echo "[setup] run as root (or install sudo) to install them" >&2
    exit 1
  fi
fi
echo "[setup] installing: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
