#!/usr/bin/env bash
# Scale measurements of distributed runs (docs/distributed.md, #41), on a GPU
# machine with several GPUs and mpirun, from the repository root, with a CUDA
# build of rast that has MPI (RAST_MPI=ON; scripts/device/pack.sh puts it in
# .device/cuda/rast):
#
#   bash scripts/device/distributed_scale.sh [RAST] [OUTDIR]   (default .device/cuda/rast, $OUT or ./device-out)
#
# 0. identity: image, depth and ids of 2 and 4 ranks (NCCL and MPI) against one process,
#    BLEND scenes (exact, sorted, kbuffer) included;
# 1. composite: `rast bench --distribute` at 1920x1080 on 1, 2 and 4 ranks of a
#    small scene: the `composite` and `merge` stages are the exchange per frame,
#    over NCCL (found in the PyTorch environment) and over MPI (RAST_COMPOSITE=mpi);
# 2. strong scaling: builtin:tiny?n=100000000 (100 M triangles) on 1, 2, 4 ranks;
# 3. weak scaling: 100 M triangles per rank (n = 100 M x ranks; builtin:tiny is
#    generated in part per rank under --distribute, up to 1.8 G triangles);
# 4. many views: 1,000 views (a turntable) of builtin:default at 640x480 on 1,
#    2 and 4 ranks, wall time of the whole run.
# Each bench writes JSON rows (rank 0's stages: vertex, setup, raster,
# composite, shade, merge, frame) to OUTDIR/dist_*.json; summary.txt collects
# the tables. Environment: NCCL_NVLS_ENABLE=0 is kept for the shared hosts.
set -uo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"
rast=${1:-$root/.device/cuda/rast}
out=${2:-${OUT:-$root/device-out}}
mkdir -p "$out"
[ -x "$rast" ] || { echo "distributed_scale.sh: no rast at $rast" >&2; exit 1; }
[ -d "$root/.device/lib" ] && export LD_LIBRARY_PATH="$root/.device/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export OMP_PROC_BIND=false NCCL_NVLS_ENABLE=0 OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
# NCCL from the image's PyTorch environment (loaded at run time by rast).
nccl=$(python3 -c 'import nvidia.nccl; print(list(nvidia.nccl.__path__)[0])' 2>/dev/null || true)
[ -n "$nccl" ] && [ -e "$nccl/lib/libnccl.so.2" ] && export LD_LIBRARY_PATH="$nccl/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
gpus=$(nvidia-smi -L 2>/dev/null | wc -l)
[ "$gpus" -ge 1 ] || gpus=1
frames=${RAST_BENCH_FRAMES:-50}
summary=$out/summary_distributed.txt
: > "$summary"
run() {  # ranks, label, rast args...
  local n=$1 label=$2; shift 2
  [ "$n" -le "$gpus" ] || { echo "skip $label: $n ranks > $gpus GPUs" | tee -a "$summary"; return 0; }
  echo "== $label on $n ranks" | tee -a "$summary"
  mpirun --oversubscribe -np "$n" -x LD_LIBRARY_PATH -x NCCL_NVLS_ENABLE -x RAST_COMPOSITE "$rast" "$@" 2>&1 | tail -5 | tee -a "$summary"
}
export RAST_COMPOSITE=${RAST_COMPOSITE:-auto}
"$rast" info | head -8 | tee -a "$summary"
# 0. identity on the GPUs: sort-last over NCCL and over MPI against one process.
idir=$out/identity
mkdir -p "$idir"
# glTF BLEND (docs/distributed.md, "Transparency"): layers_occluded has an opaque quad through the
# layers that the last rank draws.
python3 "$root/scripts/measure/blend_scenes.py" "$idir/blend" > /dev/null
for spec in "builtin:default --aa none" "builtin:default --aa msaa4" "builtin:tiny?n=2000000 --raster visbuffer" "builtin:lines?n=100000" \
    "builtin:layers?n=8&mixed=1 --shading pbr --transparency exact" \
    "$idir/blend/layers_occluded.gltf --shading pbr --transparency sorted --aa msaa4" \
    "$idir/blend/layers_occluded.gltf --transparency kbuffer"; do
  set -- $spec
  scene=$1; shift
  "$rast" render "$scene" --size 1920x1080 "$@" -o "$idir/one.png" --aov "depth=$idir/one_d.npy,primid=$idir/one_i.npy" > /dev/null 2>&1
  for n in 2 4; do
    [ "$n" -le "$gpus" ] || continue
    for mode in nccl mpi; do
      rm -f "$idir"/many*
      RAST_COMPOSITE=$mode mpirun --oversubscribe -np "$n" -x LD_LIBRARY_PATH -x NCCL_NVLS_ENABLE -x RAST_COMPOSITE \
        "$rast" render "$scene" --size 1920x1080 "$@" -o "$idir/many.png" --aov "depth=$idir/many_d.npy,primid=$idir/many_i.npy" \
        --distribute > "$idir/log.txt" 2>&1
      if cmp -s "$idir/one.png" "$idir/many.png" && cmp -s "$idir/one_d.npy" "$idir/many_d.npy" && cmp -s "$idir/one_i.npy" "$idir/many_i.npy"; then
        echo "identity ok: $spec, $n ranks, $mode" | tee -a "$summary"
      else
        echo "identity FAILED: $spec, $n ranks, $mode ($(grep -m1 'rast:' "$idir/log.txt"))" | tee -a "$summary"
      fi
    done
  done
done
for n in 1 2 4; do
  run "$n" composite bench builtin:default --size 1920x1080 --frames "$frames" --distribute --json "$out/dist_composite_$n.json"
  RAST_COMPOSITE=mpi run "$n" composite-mpi bench builtin:default --size 1920x1080 --frames "$frames" --distribute \
    --json "$out/dist_composite_mpi_$n.json"
done
# BLEND: rank 0 composites every BLEND fragment (the others none): the blend stages do not scale.
for n in 1 2; do
  run "$n" blend bench 'builtin:layers?n=8&mixed=1' --size 1920x1080 --frames "$frames" --transparency exact --distribute \
    --json "$out/dist_blend_$n.json"
done
for n in 1 2 4; do
  run "$n" strong bench 'builtin:tiny?n=100000000' --size 1920x1080 --frames "$frames" --distribute --json "$out/dist_strong_$n.json"
done
for n in 1 2 4; do
  run "$n" weak bench "builtin:tiny?n=$((100000000 * n))" --size 1920x1080 --frames "$frames" --distribute --json "$out/dist_weak_$n.json"
done
python3 - "$out/cams1000.json" <<'PY'
import json, math, sys
json.dump([{"eye": [4 * math.sin(2 * math.pi * k / 1000), 1.5, 4 * math.cos(2 * math.pi * k / 1000)],
            "target": [0, 0.4, 0]} for k in range(1000)], open(sys.argv[1], "w"))
PY
mkdir -p "$out/views"
for n in 1 2 4; do
  [ "$n" -le "$gpus" ] || continue
  start=$(date +%s.%N)
  mpirun --oversubscribe -np "$n" "$rast" render builtin:default --size 640x480 --cameras "$out/cams1000.json" \
    -o "$out/views/v${n}_%04d.png" --distribute > /dev/null 2>&1
  end=$(date +%s.%N)
  echo "many views: 1000 views on $n ranks: $(python3 -c "print(f'{$end - $start:.2f}')") s, $(ls "$out/views" | wc -l) files" | tee -a "$summary"
  rm -f "$out"/views/v*_0[1-9]*.png  # keep the first 100 of each run, not 1000 (what comes back is limited)
done
echo "summary: $summary"
