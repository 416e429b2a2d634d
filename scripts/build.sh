#!/usr/bin/env bash
# Configures (Release, Ninja when present) and builds photoscene into ${BUILD_DIR:-build}.
# Extra arguments go to the CMake configure step, e.g. scripts/build.sh -DPS_SANITIZE=ON
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${BUILD_DIR:-build}
GENERATOR=()
if command -v ninja >/dev/null 2>&1 && [ ! -f "$BUILD_DIR/Makefile" ]; then GENERATOR=(-G Ninja); fi
cmake -S . -B "$BUILD_DIR" "${GENERATOR[@]}" -DCMAKE_BUILD_TYPE=${BUILD_TYPE:-Release} "$@"
cmake --build "$BUILD_DIR" --parallel "$(nproc)"
