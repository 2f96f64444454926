#!/usr/bin/env bash
# rast.rasterize against nvdiffrast's dr.rasterize on the GPU machine (issue
# #42, docs/python.md): nvdiffrast built there for the GPU (about a minute,
# from .nvdr/src, a copy of NVlabs/nvdiffrast that never enters the project),
# then scripts/device/rasterize_vs_nvdiffrast.py on the shared models and
# glref's 1 M-triangle scene, and scripts/device/rasterize_profile.py's
# breakdown of one call.
#
#   bash scripts/device/rasterize_h100.sh OUTDIR [SCENES_TO_PROFILE]
#
# Needs .device/ from scripts/device/pack.sh (the CUDA build with its Python
# module) and .nvdr/src.
set -uo pipefail
out=${1:?usage: rasterize_h100.sh OUTDIR [SCENES]}
scenes=${2:-box,duck}
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"
mkdir -p "$out"
source scripts/device/device_env.sh
export PYTHONPATH=$root/.device/python${PYTHONPATH:+:$PYTHONPATH}
if ! python3 -c "import nvdiffrast.torch" 2>/dev/null; then
  TORCH_CUDA_ARCH_LIST=9.0 MAX_JOBS=16 python3 -m pip install -q --no-build-isolation --no-deps --no-index .nvdr/src \
    > "$out/nvdiffrast_build.log" 2>&1 || { echo "rasterize_h100: nvdiffrast did not build"; tail -30 "$out/nvdiffrast_build.log"; }
fi
mkdir -p /tmp/stress
python3 .device/glref_src/gen_scenes.py /tmp/stress > /dev/null 2>&1 || echo "rasterize_h100: no glref scenes (tiny skipped)"
{
  echo "date: $(date -u +%Y-%m-%dT%H:%M:%SZ)"
  nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
  cat .device/build.env 2>/dev/null
} > "$out/rasterize_env.txt"
python3 scripts/device/rasterize_vs_nvdiffrast.py --rast .device/cuda/rast --models .device/shared/models \
  --stress /tmp/stress --out "$out/rasterize_vs_nvdiffrast.csv" 2>&1 | tee "$out/rasterize_vs_nvdiffrast.txt"
python3 scripts/device/rasterize_profile.py --rast .device/cuda/rast --models .device/shared/models \
  --scenes "$scenes" --out "$out/profile" > "$out/rasterize_profile.txt" 2>&1
grep -E "wall median|  [a-z_(]" "$out/rasterize_profile.txt" | head -40
