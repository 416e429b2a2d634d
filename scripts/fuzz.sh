#!/usr/bin/env bash
# Builds the libFuzzer targets with clang + ASan + UBSan into build-fuzz and runs each for
# FUZZ_SECONDS (default 60). Seeds: tests/fuzz/corpus/<target>; the growing corpus lives in
# build-fuzz/corpus/<target>. Every crash is copied into tests/fuzz/regressions/<target>/, which
# the normal test run replays (ps_test_fuzz_replay). Usage: scripts/fuzz.sh [target...]
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_PER_TARGET=${FUZZ_SECONDS:-60}
export CC=clang CXX=clang++
BUILD_DIR=build-fuzz bash scripts/build.sh -DPS_FUZZ=ON -DPS_SANITIZE=ON -DPS_BUILD_PERF=OFF \
  -DPS_BUILD_SAMPLES=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  targets=()
  for exe in build-fuzz/bin/ps_fuzz_*; do targets+=("${exe##*/ps_fuzz_}"); done
fi
status=0
for t in "${targets[@]}"; do
  corpus=build-fuzz/corpus/$t
  artifacts=build-fuzz/artifacts/$t
  mkdir -p "$corpus" "$artifacts"
  echo "== $t: ${SECONDS_PER_TARGET}s"
  if ! ASAN_OPTIONS=detect_leaks=1 ./build-fuzz/bin/ps_fuzz_$t "$corpus" "tests/fuzz/corpus/$t" \
       -max_total_time="$SECONDS_PER_TARGET" -rss_limit_mb=4096 -timeout=10 \
       -artifact_prefix="$artifacts/" -print_final_stats=1 2>"build-fuzz/$t.log"; then
    status=1
  fi
  grep -E "^(stat::number_of_executed_units|stat::average_exec_per_sec|stat::peak_rss_mb)" "build-fuzz/$t.log" || true
  grep -E "^#[0-9]+.*(DONE|pulse)" "build-fuzz/$t.log" | tail -1 || true
  for crash in "$artifacts"/*; do
    [ -f "$crash" ] || continue
    cp "$crash" "tests/fuzz/regressions/$t/"
    echo "   kept finding: tests/fuzz/regressions/$t/${crash##*/}"
  done
done
exit $status
