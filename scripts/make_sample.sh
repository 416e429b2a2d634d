#!/usr/bin/env bash
# Regenerates the bundled sample scene samples/data/living-room with the project's own tools
# (graph library materials, the path tracer): see samples/tools/make_sample_scene.cpp.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh >/dev/null
OUT=samples/data/living-room
tmp=$(mktemp -d)
./"${BUILD_DIR:-build}"/bin/ps_make_sample_scene "$tmp" --spp "${SPP:-256}" "$@"
cp samples/data/README.living-room.txt "$tmp/README.txt"
rm -rf "$OUT"
mkdir -p "$(dirname "$OUT")"
mv "$tmp" "$OUT"
echo "sample written to $OUT ($(du -sh "$OUT" | cut -f1))"
