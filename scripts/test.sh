#!/usr/bin/env bash
# README command 2: set up, build, and run every test (ctest). CI runs exactly this.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
cd "${BUILD_DIR:-build}"
ctest --output-on-failure --parallel "$(nproc)" --timeout 1200
cd - >/dev/null
# The sanitizer configuration (ASan + UBSan) on the modules that read untrusted input.
bash scripts/sanitize.sh --ci
