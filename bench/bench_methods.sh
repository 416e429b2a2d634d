#!/usr/bin/env bash
# Run time against error of every preset and baseline over a folder of cases (issue 7, `bench/`).
#
#   bench/bench_methods.sh [--quick] [--build DIR] [--out DIR] [--case DIR]... [--threads N]
#                          [--eval-spp N] [--methods "fast balanced paper pixel-median shading-median"]
#                          [--no-gt-twin] [--no-reeval]
#
# Cases: every --case DIR (a folder with scene.json), by default the bundled sample
# (samples/data/living-room) and ../shared/data/examples/* when present (--quick: the bundled
# sample only). Per case and method:
#   photoscene run CASE/scene.json -o OUT/<case>/<method> --preset P      (fast, balanced, paper)
#   photoscene run CASE/scene.json -o OUT/<case>/<method> --baseline B    (pixel-median, shading-median)
#   photoscene eval OUT/<case>/<method> --scene CASE/scene.json --spp N --rerender
#                                             (every method and the true twin scored at the same spp: the
#                                             run scores itself at its preset's spp, 32 fast, 64 balanced,
#                                             256 paper; --no-reeval keeps those numbers)
# and, when the case has gt/twin (the true materials), a row "gt-twin" that only evaluates it: the
# error left by render noise and the coarse geometry, the floor of what any method can reach.
# Prints one markdown table per case (ps_bench_methods_table: seconds per stage and total,
# input-view RMSE / SSIM / GMSD, novel-view and relit RMSE where the case has ground truth) and
# writes OUT/error_vs_time_<case>.png; everything printed also goes to OUT/bench_methods.md.
# --quick: presets fast only (no balanced, paper), eval at 32 spp, --texture-size 256.
# Times are those of metrics.json ("stages", "total_seconds"), as `photoscene run` measured them
# (its "metrics" stage is the scoring itself). The exemplar bank of graph selection is cached
# across runs (~/.cache/photoscene or $PS_CACHE_DIR): warm it with one run first for fair times.
# A run that fails is reported as "failed" with its log in OUT/<case>/<method>.log; the bench goes on.
set -uo pipefail

source "$(dirname "${BASH_SOURCE[0]}")/bench_common.sh"
OUT="${TMPDIR:-/tmp}/ps_bench_methods"
QUICK=0
THREADS=0
EVAL_SPP=""
METHODS=""
GT_TWIN=1
REEVAL=1
CASES=()
ARGS="$*"
while [[ $# -gt 0 ]]; do
  case "$1" in
    --quick) QUICK=1; shift ;;
    --case) CASES+=("$(cd "$2" && pwd)"); shift 2 ;;
    --threads) THREADS="$2"; shift 2 ;;
    --eval-spp) EVAL_SPP="$2"; shift 2 ;;
    --methods) METHODS="$2"; shift 2 ;;
    --no-gt-twin) GT_TWIN=0; shift ;;
    --no-reeval) REEVAL=0; shift ;;
    *) common_option "$@"; shift "$SHIFT" ;;
  esac
done
if [[ -z "$METHODS" ]]; then
  if [[ $QUICK -eq 1 ]]; then METHODS="fast pixel-median shading-median"
  else METHODS="fast balanced paper pixel-median shading-median"; fi
fi
[[ -z "$EVAL_SPP" ]] && { [[ $QUICK -eq 1 ]] && EVAL_SPP=32 || EVAL_SPP=64; }
RUN_EXTRA=()
[[ $QUICK -eq 1 ]] && RUN_EXTRA+=(--texture-size 256)
[[ "$THREADS" != 0 ]] && RUN_EXTRA+=(--threads "$THREADS")
if [[ ${#CASES[@]} -eq 0 ]]; then
  CASES+=("$ROOT/samples/data/living-room")
  if [[ $QUICK -eq 0 && -d "$ROOT/../shared/data/examples" ]]; then
    for c in "$ROOT"/../shared/data/examples/*/; do
      [[ -f "$c/scene.json" ]] && CASES+=("$(cd "$c" && pwd)")
    done
  fi
fi
PS="$BUILD/bin/photoscene"
TABLE="$BUILD/bin/ps_bench_methods_table"
need_programs "$PS" "$TABLE"
mkdir -p "$OUT"
REPORT="$OUT/bench_methods.md"
now() { date +%s.%N; }
{
  echo "bench/bench_methods.sh $ARGS"
  echo "commit $(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo '?'), $(nproc) cores, $(date -u +%Y-%m-%dT%H:%MZ)," \
       "methods: $METHODS; eval at $EVAL_SPP spp"
  echo
} | tee "$REPORT"

EVAL_THREADS=()
[[ "$THREADS" != 0 ]] && EVAL_THREADS=(--threads "$THREADS")

for CASE in "${CASES[@]}"; do
  NAME="$(basename "$CASE")"
  mkdir -p "$OUT/$NAME"
  ROWS=()
  for M in $METHODS; do
    DIR="$OUT/$NAME/$M"
    LOG="$OUT/$NAME/$M.log"
    rm -rf "$DIR"
    case "$M" in
      pixel-median|shading-median) SEL=(--baseline "$M") ;;
      *) SEL=(--preset "$M") ;;
    esac
    echo "[$NAME] $M: photoscene run ${SEL[*]} ${RUN_EXTRA[*]}" >&2
    T0=$(now)
    "$PS" -q run "$CASE/scene.json" -o "$DIR" "${SEL[@]}" "${RUN_EXTRA[@]}" >"$LOG" 2>&1
    RC=$?
    T1=$(now)
    WALL=$(awk "BEGIN { printf \"%.1f\", $T1 - $T0 }")
    if [[ $RC -eq 0 ]]; then
      # `photoscene run` scores its twin itself, at its preset's spp; score again at one spp for all.
      if [[ $REEVAL -eq 1 ]] || ! grep -q '"views"' "$DIR/metrics.json" 2>/dev/null; then
        "$PS" -q eval "$DIR" --scene "$CASE/scene.json" --spp "$EVAL_SPP" --rerender "${EVAL_THREADS[@]}" >>"$LOG" 2>&1 ||
          echo "[$NAME] $M: eval failed (see $LOG)" >&2
      fi
    else
      echo "[$NAME] $M: run failed with exit $RC (see $LOG): $(tail -1 "$LOG")" >&2
      rm -f "$DIR/metrics.json"
    fi
    ROWS+=("$M=$DIR=$WALL")
  done
  if [[ $GT_TWIN -eq 1 && -f "$CASE/gt/twin/scene.json" ]]; then
    # A mirror of the case whose gt/twin is a copy (its scene.json refers to ../../ files), so
    # that metrics.json is written outside the case folder.
    MIRROR="$OUT/$NAME/_case"
    rm -rf "$MIRROR"
    mkdir -p "$MIRROR/gt"
    for e in "$CASE"/*; do [[ "$(basename "$e")" != gt ]] && ln -s "$e" "$MIRROR/"; done
    for e in "$CASE"/gt/*; do [[ "$(basename "$e")" != twin ]] && ln -s "$e" "$MIRROR/gt/"; done
    cp -rL "$CASE/gt/twin" "$MIRROR/gt/twin"
    rm -f "$MIRROR/gt/twin/metrics.json"
    echo "[$NAME] gt-twin: photoscene eval" >&2
    "$PS" -q eval "$MIRROR/gt/twin" --scene "$MIRROR/scene.json" --spp "$EVAL_SPP" "${EVAL_THREADS[@]}" \
      >"$OUT/$NAME/gt-twin.log" 2>&1 || echo "[$NAME] gt-twin: eval failed (see $OUT/$NAME/gt-twin.log)" >&2
    ROWS+=("gt-twin=$MIRROR/gt/twin=0")
  fi
  "$TABLE" --case "$NAME" --plot "$OUT/error_vs_time_$NAME.png" "${ROWS[@]}" | tee -a "$REPORT"
  echo | tee -a "$REPORT"
done
echo "written: $REPORT" >&2
