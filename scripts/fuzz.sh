#!/usr/bin/env bash
# Builds the libFuzzer targets with clang + ASan + UBSan into build-fuzz and runs each for
# FUZZ_SECONDS (default 60). Seeds: tests/fuzz/corpus/<target>; the growing corpus lives in
# build-fuzz/corpus/<target>. Every crash is copied into tests/fuzz/regressions/<target>/, which
# the normal test run replays (ps_test_fuzz_replay). Usage: scripts/fuzz.sh [target...]
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_PER_TARGET=${FUZZ_SECONDS:-60}
export CC=clang CXX=clang++
GENERATOR=()
if command -v ninja >/dev/null 2>&1 && [ ! -f build-fuzz/Makefile ]; then GENERATOR=(-G Ninja); fi
cmake -S . -B build-fuzz "${GENERATOR[@]}" -DPS_FUZZ=ON -DPS_SANITIZE=ON -DPS_BUILD_PERF=OFF \
  -DPS_BUILD_SAMPLES=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  targets=(scene_json obj label_image)
  grep -q "ps_fuzz_graph_json" build-fuzz/build.ninja build-fuzz/Makefile 2>/dev/null && targets+=(graph_json)
fi
cmake --build build-fuzz --parallel "$(nproc)" --target "${targets[@]/#/ps_fuzz_}"
status=0
for t in "${targets[@]}"; do
  corpus=build-fuzz/corpus/$t
  artifacts=build-fuzz/artifacts/$t
  mkdir -p "$corpus" "$artifacts"
  echo "== $t: ${SECONDS_PER_TARGET}s"
  if ! ASAN_OPTIONS=detect_leaks=1 LSAN_OPTIONS=suppressions=tests/fuzz/lsan.supp ./build-fuzz/bin/ps_fuzz_$t "$corpus" "tests/fuzz/corpus/$t" \
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
