#!/usr/bin/env bash
# The glTF shading's cost on the CPU in instructions (issue #37's goal: a
# frame at most 1.3x Blinn-Phong's with punctual light, 1.5x with an
# environment), counted by callgrind on one thread because wall times on a
# shared 2-core VM are noisy. A frame's count is the second frame's of
# `rast bench --frames 2 --warmup 0` (callgrind dumps after each
# Renderer::enqueue): the steady frame, without the first frame's
# allocations and the environment's prefiltering.
#
#   bash scripts/measure/pbr_instructions.sh RAST MODELS_DIR OUT.csv [MODEL ...]
#
# Writes model,shading,instructions_per_frame rows (shading: blinn-phong,
# pbr-punctual = --shading pbr --env none, pbr-env = --shading pbr with the
# built-in environment; SHADINGS="..." picks some) and prints the ratios to
# Blinn-Phong.
set -euo pipefail
rast=$1 models=$2 out=$3
shift 3
list=("$@")
[ ${#list[@]} -gt 0 ] || list=(box checkerboard cow duck engine milktruck)
shadings=${SHADINGS:-blinn-phong pbr-punctual pbr-env}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
count() {  # instructions of the second Renderer::enqueue
  local file=$1
  shift
  rm -f "$tmp"/cg*
  OMP_NUM_THREADS=1 valgrind --tool=callgrind --callgrind-out-file="$tmp/cg" --dump-after='rast::Renderer::enqueue*' \
    "$rast" bench "$file" --size 1920x1080 --frames 2 --warmup 0 "$@" > "$tmp/log" 2>&1
  awk '/^summary:/ {print $2}' "$tmp/cg.2"
}
echo "model,shading,instructions_per_frame" > "$out"
for m in "${list[@]}"; do
  for v in "blinn-phong:--shading blinn-phong" "pbr-punctual:--shading pbr --env none" "pbr-env:--shading pbr"; do
    s=${v%%:*}
    [[ " $shadings " == *" $s "* ]] || continue
    read -r -a flags <<< "${v#*:}"
    echo "$m,$s,$(count "$models/$m.glb" "${flags[@]}")" >> "$out"
  done
done
python3 - "$out" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
by = {(r["model"], r["shading"]): int(r["instructions_per_frame"]) for r in rows}
for m in dict.fromkeys(r["model"] for r in rows):
    if any((m, s) not in by for s in ("blinn-phong", "pbr-punctual", "pbr-env")):
        continue
    bp = by[(m, "blinn-phong")]
    print(f"{m:12s} blinn-phong {bp / 1e6:8.1f} M  punctual {by[(m, 'pbr-punctual')] / 1e6:8.1f} M "
          f"({by[(m, 'pbr-punctual')] / bp:.2f}x)  env {by[(m, 'pbr-env')] / 1e6:8.1f} M ({by[(m, 'pbr-env')] / bp:.2f}x)")
PY
