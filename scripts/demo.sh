#!/usr/bin/env bash
# README command 1: set up, build, and run `photoscene` on the bundled sample (./photoscene-demo).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
# A fresh build compiles in unity batches (CMakeLists.txt, PS_UNITY_BUILD): about 2/3 of the
# time. PS_UNITY_BUILD=OFF keeps one object per source (faster rebuilds after an edit).
bash scripts/build.sh -DPS_UNITY_BUILD="${PS_UNITY_BUILD:-ON}"
exec ./"${BUILD_DIR:-build}"/bin/photoscene
