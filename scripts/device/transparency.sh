#!/usr/bin/env bash
# The transparency methods on the GPU machine (docs/transparency.md): the
# Catch2 and CLI transparency tests of a CUDA build, then the methods' error
# against exact and against the supersampled exact reference versus frame time
# at 1920x1080 (scripts/measure/bench_transparency.py) and its chart, then the
# same glTF files drawn by the GPU's own OpenGL with sorted blending
# (scripts/measure/glblend, through scripts/measure/blend_vs_gl.py) against
# rast exact and sorted, when .device/glblend is there (scripts/device/pack.sh).
#
#   bash scripts/device/transparency.sh BUILD_DIR OUTDIR [--gl-only]
#
# BUILD_DIR: a configured and built CUDA tree (cmake --preset cuda; its rast,
# rast_tests), or with --gl-only any folder holding a CUDA rast (.device/cuda).
# Writes OUTDIR/transparency_cuda.csv, OUTDIR/transparency_cuda.png,
# OUTDIR/tests.log and OUTDIR/blend_vs_gl_cuda.csv (+ blend_vs_gl.txt, blend_vs_gl_env.txt).
# glblend needs EGL and epoxy there: .xdeb/ from scripts/device/fetch_x_debs.sh,
# as scripts/device/three_way.sh uses them.
set -uo pipefail
build=${1:?usage: transparency.sh BUILD_DIR OUTDIR [--gl-only]}
out=${2:?usage: transparency.sh BUILD_DIR OUTDIR [--gl-only]}
gl_only=${3:-}
root=$(cd "$(dirname "$0")/../.." && pwd)
mkdir -p "$out"
if [ "$gl_only" != "--gl-only" ]; then
  # The Catch2 cases are named "MASK: ...", "BLEND: ..." (tests/pipeline/test_transparency.cpp).
  ctest --test-dir "$build" -R "BLEND|MASK|transparency" --output-on-failure > "$out/tests.log" 2>&1
  echo "tests: rc $? (log in $out/tests.log)"
  python3 "$root/scripts/measure/bench_transparency.py" --rast "$build/rast" --out "$out/transparency_cuda.csv" \
    --size 1920x1080 --frames 50 --reference-grid 16
  python3 "$root/scripts/plot/plot_transparency.py" "$out/transparency_cuda.csv" --out "$out/transparency_cuda.png" ||
    echo "no chart (matplotlib missing): the CSV is the result"
fi

glblend=${GLBLEND:-$root/.device/glblend}
if [ ! -x "$glblend" ]; then
  echo "no $glblend: no comparison with the hardware rasterizer's blending (scripts/device/pack.sh --glblend)"
  exit 0
fi
# glref's set-up (three_way.sh): libglvnd's EGL and libepoxy from .xdeb, NVIDIA's EGL only.
x=/tmp/x
mkdir -p "$x"
for f in "$root"/.xdeb/*.deb; do [ -f "$f" ] && dpkg -x "$f" "$x"; done
export LD_LIBRARY_PATH=$x/usr/lib/x86_64-linux-gnu:$x/lib/x86_64-linux-gnu:/usr/local/nvidia/lib64:$root/.device/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
for j in /usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json /usr/share/glvnd/egl_vendor.d/10_nvidia.json; do
  [ -f "$j" ] && { export __EGL_VENDOR_LIBRARY_FILENAMES=$j; break; }
done
export OMP_PROC_BIND=false
{
  echo "date: $(date -u +%Y-%m-%dT%H:%M:%SZ)"
  nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
  [ -f "$root/.device/build.env" ] && cat "$root/.device/build.env"
} > "$out/blend_vs_gl_env.txt" 2>&1
# glblend's RGBA16F framebuffer (what engines blend into) timed; its RGBA32F one compared too.
python3 "$root/scripts/measure/blend_vs_gl.py" --rast "$build/rast" --glblend "$glblend" \
  --out "$out/blend_vs_gl_cuda.csv" --size 1920x1080 --frames 50 --warmup 5 --gl-frames 200 --gl-warmup 20 \
  --film rgba16f,rgba32f --workdir "$out/blend_vs_gl_files" 2>&1 | tee "$out/blend_vs_gl.txt"
