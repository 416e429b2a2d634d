#!/usr/bin/env bash
# README command 1: set up, build, and run `photoscene` on the bundled sample (./photoscene-demo).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
exec ./"${BUILD_DIR:-build}"/bin/photoscene
