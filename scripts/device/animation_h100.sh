#!/usr/bin/env bash
# Issue #40 on the GPU machine (after scripts/device/pack.sh, from the repository
# root): what skinning costs a 1080p frame on the GPU, and that skinned,
# morphed and animated frames are the CPU build's bits.
#
#   bash scripts/device/animation_h100.sh [OUTDIR]     (default: $OUT, else ./device-out)
#
# 1. scripts/measure/skin_bench.py with the CUDA build: a 1000x1000 grid (1M vertices,
#    4 weights each) plain and skinned, `rast bench` at 1920x1080, 200 frames: the vertex
#    stage and frame medians (the issue's budget: skinning adds at most 0.1 ms).
# 2. Parity: the animated fuzz seed and simple_skin at several times, CUDA against the
#    OpenMP build: primitive ids and depth byte-identical (docs/determinism.md).
# 3. tests/cli/cli_animation.py against the CUDA build.
set -uo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"
out=${1:-${OUT:-$root/device-out}}
mkdir -p "$out"
dev=$root/.device
[ -d "$dev/lib" ] && export LD_LIBRARY_PATH="$dev/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export OMP_PROC_BIND=false
cuda=$dev/cuda/rast cpu=$dev/openmp/rast
status=0

echo "=== skin bench (CUDA)"
python3 scripts/measure/skin_bench.py --rast "$cuda" --n 1000 --size 1920x1080 --frames 200 --out "$out/skin_bench_cuda.csv" || status=1

echo "=== parity CUDA vs OpenMP"
cam="--eye 0.5,0.5,4 --target 0.5,0.5,0 --up 0,1,0 --near 0.1 --far 50"
for spec in "tests/fuzz/corpus/anim_skin_morph.gltf:0 0.25 0.5 0.8" "$dev/assimp/simple_skin/simple_skin.gltf:0.3 1 2.5 4"; do
  scene=${spec%%:*}
  for t in ${spec#*:}; do
    for b in cuda cpu; do
      exe=$cuda; [ "$b" = cpu ] && exe=$cpu
      # shellcheck disable=SC2086
      "$exe" render "$scene" --time "$t" --size 640x480 $cam -o "$out/p_${b}.png" \
        --aov "primid=$out/p_${b}.bin,depth=$out/p_${b}.pfm" > /dev/null || status=1
    done
    if cmp -s "$out/p_cuda.bin" "$out/p_cpu.bin" && cmp -s "$out/p_cuda.pfm" "$out/p_cpu.pfm"; then
      echo "ok   $(basename "$scene") t=$t: ids and depth identical"
    else
      echo "FAIL $(basename "$scene") t=$t: ids or depth differ"; status=1
    fi
  done
done

echo "=== cli_animation (CUDA)"
python3 tests/cli/cli_animation.py --rast "$cuda" --workdir "$out/cli_animation" || status=1
exit $status
