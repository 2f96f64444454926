#!/bin/bash
# SSAO error against rast's ray-traced AO and the SSAO pass's time, per sample
# count, on the built-in default scene and the shared models (docs/post.md).
# usage: scripts/measure/ssao_sweep.sh RAST OUT.csv [SHARED_DIR]
set -euo pipefail
rast=$1 out=$2 shared=${3:-../shared}
scenes=(builtin:default)
for m in duck cow engine; do
  [ -f "$shared/models/$m.glb" ] && scenes+=("$shared/models/$m.glb")
done
tmp=$(mktemp -d)
n=0
for s in "${scenes[@]}"; do
  n=$((n + 1))
  "$rast" ssao-error "$s" --size 1920x1080 --error-size 480x270 --rays 256 --samples 1,2,4,8,16,32 \
    --frames 5 --warmup 2 --csv "$tmp/$n.csv"
done
{ sed -n 1p "$tmp/1.csv"; for f in "$tmp"/*.csv; do sed -n '2,$p' "$f"; done; } > "$out"
rm -r "$tmp"
echo "wrote $out"
