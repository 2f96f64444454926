#!/usr/bin/env bash
# rast (CUDA) against the GPU's hardware OpenGL rasterizer (glref through EGL)
# and nvdiffrast's CUDA rasterizer (cudaraster), same scenes, sizes and
# cameras, in one run on the GPU machine (docs/performance.md, issue #11).
#
#   bash scripts/device/three_way.sh OUTDIR [SIZES]     (default 1920x1080)
#
# Needs, next to the working tree: .device/ from scripts/device/pack.sh (with
# .device/glref, see --glref there), .xdeb/ from scripts/device/fetch_x_debs.sh
# (libglvnd's EGL and libepoxy for glref) and .nvdr/src, a copy of
# NVlabs/nvdiffrast that never enters the project: it is installed here with
# the machine's own torch (pip install --no-build-isolation).
set -uo pipefail
out=${1:?usage: three_way.sh OUTDIR [SIZES]}
sizes=${2:-1920x1080}
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"
mkdir -p "$out"
dev=$root/.device
x=/tmp/x
mkdir -p "$x"
for f in .xdeb/*.deb; do dpkg -x "$f" "$x"; done
export LD_LIBRARY_PATH=$x/usr/lib/x86_64-linux-gnu:$x/lib/x86_64-linux-gnu:/usr/local/nvidia/lib64${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
# NVIDIA's EGL only: the hardware rasterizer, not Mesa.
for j in /usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json /usr/share/glvnd/egl_vendor.d/10_nvidia.json; do
  [ -f "$j" ] && { export __EGL_VENDOR_LIBRARY_FILENAMES=$j; break; }
done
export OMP_PROC_BIND=false

# nvdiffrast, built for this GPU only (about a minute).
t0=$SECONDS
if ! python3 -c "import nvdiffrast.torch" 2>/dev/null; then
  TORCH_CUDA_ARCH_LIST=9.0 MAX_JOBS=16 python3 -m pip install -q --no-build-isolation --no-deps --no-index .nvdr/src \
    > "$out/nvdiffrast_build.log" 2>&1 || { echo "three_way: nvdiffrast did not build"; tail -30 "$out/nvdiffrast_build.log"; }
fi
echo "three_way: nvdiffrast ready after $((SECONDS - t0)) s: $(python3 -c 'import nvdiffrast, torch; print(nvdiffrast.__version__, torch.__version__)' 2>&1)"

# glref's stress scenes (standard library only).
mkdir -p /tmp/stress
python3 "$dev/glref_src/gen_scenes.py" /tmp/stress > /dev/null
m=$dev/shared/models
{
  echo "date: $(date -u +%Y-%m-%dT%H:%M:%SZ)"
  nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
  cat "$dev/build.env"
} > "$out/three_way_env.txt"
python3 scripts/device/perf_vs_gl.py --rast "$dev/cuda/rast" --glref "$dev/glref" --models "$m" --stress /tmp/stress \
  --sizes "$sizes" --nvdiffrast --out "$out/three_way.csv" \
  --extra-camera "engine_inside=$m/engine.glb:--eye,0,-44.46,-6,--target,300,-44.46,-6,--up,0,1,0,--fovy,60,--near,1,--far,5000" \
  --extra-camera "milktruck_cab=$m/milktruck.glb:--eye,0.5,1.3,0.2,--target,3,1.0,0.5,--up,0,1,0,--fovy,45,--near,0.5,--far,807.250969" \
  2>&1 | tee "$out/three_way.txt"
