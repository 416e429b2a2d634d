#!/usr/bin/env bash
# Installs the Debian 12 packages photoscene builds with, skipping those already present.
# Run as root (or with sudo available). README.md says why each dependency is here.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config
  libopencv-dev libopencv-contrib-dev   # image work, ximgproc segmentation, quality metrics
  libeigen3-dev                         # small linear algebra, least squares
  libopenimageio-dev openimageio-tools  # PNG / JPEG / EXR / HDR reading and writing (its CMake package names /usr/bin/iconvert)
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
  nodejs                                # report viewer: three.js vendored and bundled at build time
  clang libclang-rt-14-dev              # sanitizer build (scripts/sanitize.sh) and libFuzzer targets
  llvm                                  # llvm-symbolizer: LSan suppressions (tests/fuzz/lsan.supp) match symbolized frames only
  slurm-wlm munge                       # tests/slurm: photoscene batch --slurm against a real one-node Slurm
)
# Optional: installed when the distribution has it, never failing the setup (the headless-browser
# test of report.html skips without it).
OPTIONAL_PACKAGES=(
  chromium                              # headless browser for tests/browser/test_report.mjs
)
# npm: Debian's package, unless an npm is already there (NodeSource's nodejs bundles its own and
# conflicts with Debian's npm)
command -v npm >/dev/null 2>&1 || OPTIONAL_PACKAGES+=(npm)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

# The report's web dependencies (third_party/web/package-lock.json): three.js for the viewer,
# esbuild to bundle it, playwright-core for the browser test. Needs the npm registry; without it
# the report is written without its 3D viewer and the browser test skips.
install_web() {
  local web
  web="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)/third_party/web"
  if ! command -v npm >/dev/null 2>&1; then echo "[setup] npm missing: no 3D viewer in report.html"; return 0; fi
  if [ -f "$web/node_modules/.package-lock.json" ] && [ "$web/node_modules/.package-lock.json" -nt "$web/package-lock.json" ]; then
    return 0
  fi
  echo "[setup] npm ci in third_party/web"
  (cd "$web" && npm ci --no-audit --no-fund --loglevel=error) || echo "[setup] npm ci failed: no 3D viewer in report.html" >&2
}

optional_missing=()
for p in "${OPTIONAL_PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    optional_missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ] && [ ${#optional_missing[@]} -eq 0 ]; then
  echo "[setup] all ${#PACKAGES[@]} packages present"
  install_web
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; elif [ ${#missing[@]} -eq 0 ]; then
    echo "[setup] optional packages not installed (not root): ${optional_missing[*]}" >&2
    install_web
    exit 0
  else
    echo "[setup] missing packages: ${missing[*]}" >&2
    echo "[setup] run as root (or install sudo) to install them" >&2
    exit 1
  fi
fi
echo "[setup] installing: ${missing[*]} ${optional_missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
if [ ${#missing[@]} -gt 0 ]; then
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
for p in "${optional_missing[@]}"; do
  $SUDO apt-get install -y -qq --no-install-recommends "$p" || echo "[setup] optional package $p not installed" >&2
done
install_web
