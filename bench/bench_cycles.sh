#!/usr/bin/env bash
# Our path tracer against Blender Cycles (CPU) on the same twin, resolution and spp (issue 3, "Benchmark").
#
#   bench/bench_cycles.sh [--build DIR] [--out DIR] [--twin DIR]... [--width W --height H]
#                         [--spps "4 16 64"] [--ref-spp 512 | --ref REF.exr] [--threads 2]
#
# Needs ./build/bin/photoscene and ./build/bin/ps_bench_compare (cmake --build build --target photoscene
# ps_bench_compare). Cycles runs only when `blender` is on PATH (bench/cycles/twin_to_blender.py);
# otherwise its columns say "skipped". BLENDER=/path/to/blender picks another binary (BLENDER=none: skip).
#
# Per twin: a high-spp reference with our path tracer (seed 0); then at each spp two renders of
# each renderer with seeds 1 and 2. Reported:
#   t        process wall seconds and CPU seconds (user + sys; includes loading, BVH, Blender start-up)
#   rmse_ref RMSE (linear radiance) of the seed-1 render against OUR reference: noise + each renderer's
#            bias against our model (Cycles' Principled BSDF differs from ours by a few %, see README)
#   noise    pure noise, no reference needed: RMSE(seed 1, seed 2) / sqrt(2); "top-1%": the share of
#            its square in the 1 % of pixels with the largest difference (fireflies)
#   eq-noise ratio = (noise_ours^2 cpu_ours) / (noise_cycles^2 cpu_cycles): the ratio of CPU times the two
#            need for equal noise (variance ~ 1 / spp); < 0.5 meets the issue's target
set -euo pipefail

source "$(dirname "${BASH_SOURCE[0]}")/bench_common.sh"
OUT="${TMPDIR:-/tmp}/ps_bench_cycles"
W=320
H=240
SPPS="4 16 64"
REF_SPP=512
REF_FILE=""
THREADS=2
TWINS=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --twin) TWINS+=("$2"); shift 2 ;;
    --width) W="$2"; shift 2 ;;
    --height) H="$2"; shift 2 ;;
    --spps) SPPS="$2"; shift 2 ;;
    --ref-spp) REF_SPP="$2"; shift 2 ;;
    --ref) REF_FILE="$(cd "$(dirname "$2")" && pwd)/$(basename "$2")"; shift 2 ;;  # reuse a reference (one twin)
    --threads) THREADS="$2"; shift 2 ;;
    *) common_option "$@"; shift "$SHIFT" ;;
  esac
done
if [[ ${#TWINS[@]} -eq 0 ]]; then
  for t in "$ROOT/../shared/data/examples/blender-room/gt/twin" "$ROOT/samples/data/living-room/gt/twin"; do
    [[ -f "$t/scene.json" ]] && TWINS+=("$(cd "$t" && pwd)")
  done
fi
PS="$BUILD/bin/photoscene"
CMP="$BUILD/bin/ps_bench_compare"
need_programs "$PS" "$CMP"
if [[ ${#TWINS[@]} -eq 0 ]]; then echo "no twin folder found (pass --twin DIR)"; exit 0; fi
HAVE_BLENDER=0
BLENDER="${BLENDER:-blender}"
if command -v "$BLENDER" >/dev/null 2>&1; then HAVE_BLENDER=1; fi
mkdir -p "$OUT"

# run LOG CMD...: runs CMD with its output in LOG; sets T_WALL, T_CPU (user + sys of the process tree)
run() {
  local log="$1"; shift
  local u s
  ( TIMEFORMAT='%R %U %S'; time "$@" >"$log" 2>&1 ) 2>"$log.time" || { echo "FAILED: $* (see $log)" >&2; tail -5 "$log" >&2; exit 1; }
  read -r T_WALL u s < "$log.time"
  T_CPU=$(awk -v u="$u" -v s="$s" 'BEGIN{printf "%.2f", u + s}')
  T_WALL=$(awk -v w="$T_WALL" 'BEGIN{printf "%.2f", w}')
}
kv() { sed -n "s/.*\b$1=\([^ ]*\).*/\1/p"; }

ours() {  # ours SPP SEED OUTFILE
  run "$3.log" "$PS" render "$TWIN" --spp "$1" --seed "$2" --width "$W" --height "$H" --threads "$THREADS" -o "$3"
  # "render X: WxH at N spp in S s (R Mrays/s)": rays = S * R
  OUR_RAYS=$(sed -n 's/.* in \([0-9.]*\)s (\([0-9.]*\) Mrays\/s).*/\1 \2/p' "$3.log" | awk '{printf "%.3f", $1 * $2}')
  OUR_RENDER_S=$(sed -n 's/.* in \([0-9.]*\)s (.*/\1/p' "$3.log")
}
cycles() {  # cycles SPP SEED OUTFILE
  run "$3.log" "$BLENDER" --background --factory-startup --python "$ROOT/bench/cycles/twin_to_blender.py" -- \
      --twin "$TWIN" --out "$3" --spp "$1" --seed "$2" --width "$W" --height "$H" --threads "$THREADS"
  CY_RENDER_S=$(sed -n 's/^CYCLES_RENDER_SECONDS \(.*\)/\1/p' "$3.log")
}

echo "# photoscene path tracer vs Blender Cycles ($(date -u +%Y-%m-%dT%H:%MZ))"
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//'); load average at start: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "resolution ${W}x${H}, threads $THREADS, spp {$SPPS}, reference: ours at $REF_SPP spp"
[[ $HAVE_BLENDER -eq 1 ]] && echo "cycles: $("$BLENDER" --version 2>/dev/null | head -1)" || echo "cycles: skipped (blender not on PATH)"

for TWIN in "${TWINS[@]}"; do
  TWIN="$(cd "$TWIN" && pwd)"
  name=$(basename "$(dirname "$(dirname "$TWIN")")")_$(basename "$TWIN")
  D="$OUT/$name"; mkdir -p "$D"
  echo
  echo "## $TWIN"
  if [[ -n "$REF_FILE" ]]; then
    [[ "$REF_FILE" -ef "$D/ref_ours.exr" ]] || cp "$REF_FILE" "$D/ref_ours.exr"
    echo "reference: $REF_FILE (reused)"
  else
    ours "$REF_SPP" 0 "$D/ref_ours.exr"
    echo "reference: ours $REF_SPP spp: wall ${T_WALL}s, CPU ${T_CPU}s, $(awk -v r="$OUR_RAYS" -v c="$T_CPU" 'BEGIN{printf "%.2f", r / c}') Mrays per CPU-s"
  fi
  ROWS=()
  for N in $SPPS; do
    ours "$N" 1 "$D/ours_${N}_s1.exr"; ow=$T_WALL; oc=$T_CPU; orays=$OUR_RAYS; ors=$OUR_RENDER_S
    ours "$N" 2 "$D/ours_${N}_s2.exr"; oc2=$T_CPU
    o_ref=$("$CMP" "$D/ours_${N}_s1.exr" "$D/ref_ours.exr")
    o_pair=$("$CMP" "$D/ours_${N}_s1.exr" "$D/ours_${N}_s2.exr")
    o_rmse=$(kv rmse <<<"$o_ref"); o_noise=$(awk -v r="$(kv rmse <<<"$o_pair")" 'BEGIN{printf "%.5f", r / sqrt(2)}')
    o_noisec=$(awk -v r="$(kv rmse_clip1 <<<"$o_pair")" 'BEGIN{printf "%.5f", r / sqrt(2)}')
    o_top=$(kv top1_share <<<"$o_pair")
    o_mrays=$(awk -v r="$orays" -v c="$oc" 'BEGIN{printf "%.2f", r / c}')
    if [[ $HAVE_BLENDER -eq 1 ]]; then
      cycles "$N" 1 "$D/cycles_${N}_s1.exr"; cw=$T_WALL; cc=$T_CPU; crs=$CY_RENDER_S
      cycles "$N" 2 "$D/cycles_${N}_s2.exr"
      c_ref=$("$CMP" "$D/cycles_${N}_s1.exr" "$D/ref_ours.exr")
      c_pair=$("$CMP" "$D/cycles_${N}_s1.exr" "$D/cycles_${N}_s2.exr")
      c_rmse=$(kv rmse <<<"$c_ref"); c_noise=$(awk -v r="$(kv rmse <<<"$c_pair")" 'BEGIN{printf "%.5f", r / sqrt(2)}')
      c_noisec=$(awk -v r="$(kv rmse_clip1 <<<"$c_pair")" 'BEGIN{printf "%.5f", r / sqrt(2)}')
      c_ratio=$(kv mean_ratio <<<"$c_ref")
      c_top=$(kv top1_share <<<"$c_pair")
      ratio=$(awk -v a="$oc" -v b="$cc" 'BEGIN{printf "%.2f", a / b}')
      eq=$(awk -v no="$o_noise" -v to="$oc" -v nc="$c_noise" -v tc="$cc" 'BEGIN{printf "%.2f", no * no * to / (nc * nc * tc)}')
      eqc=$(awk -v no="$o_noisec" -v to="$oc" -v nc="$c_noisec" -v tc="$cc" 'BEGIN{printf "%.2f", no * no * to / (nc * nc * tc)}')
    else
      cw=skipped; cc=skipped; crs=-; c_rmse=-; c_noise=-; c_noisec=-; c_ratio=-; c_top=-; ratio=-; eq=-; eqc=-
    fi
    ROWS+=("| $N | $ow / $oc ($ors) | $cw / $cc ($crs) | $ratio | $o_rmse | $c_rmse | $o_noise | $c_noise | $o_top / $c_top | $eq | $eqc | $o_mrays | $c_ratio |")
    echo "spp $N done (ours CPU ${oc} s, cycles CPU ${cc} s)" >&2
  done
  echo
  echo "| spp | ours wall / CPU s (render wall) | Cycles wall / CPU s (render wall) | CPU ratio ours/Cycles | RMSE ours vs ref | RMSE Cycles vs ref | noise ours | noise Cycles | top-1% share of noise ours / Cycles | equal-noise CPU ratio | same, clipped to 1 | ours Mrays per CPU-s | Cycles mean / ref mean |"
  echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
  printf '%s\n' "${ROWS[@]}"
done
echo
echo "load average at end: $(cut -d' ' -f1-3 /proc/loadavg)"
