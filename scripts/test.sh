#!/usr/bin/env bash
# README command 2: set up, build, and run every test (ctest). CI runs exactly this.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
# A fresh build compiles in unity batches (CMakeLists.txt, PS_UNITY_BUILD): about 2/3 of the
# time. PS_UNITY_BUILD=OFF keeps one object per source (faster rebuilds after an edit).
bash scripts/build.sh -DPS_UNITY_BUILD="${PS_UNITY_BUILD:-ON}"
cd "${BUILD_DIR:-build}"
ctest --output-on-failure --parallel "$(nproc)" --timeout 1200
cd - >/dev/null
# The sanitizer configuration (ASan + UBSan) on the modules that read untrusted input.
bash scripts/sanitize.sh --ci
