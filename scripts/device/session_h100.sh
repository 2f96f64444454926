#!/usr/bin/env bash
# One GPU-machine session's measurements for the open issues, in as few device
# calls as possible (each call starts a machine, so steps that belong together
# run together). From the repository root, after scripts/device/pack.sh
# (with --python for the module), with .nvdr/src (a copy of NVlabs/nvdiffrast,
# never part of the project) for the nvdiffrast step:
#
#   bash scripts/device/session_h100.sh OUTDIR STEP...
#
# Steps (each logs to OUTDIR/STEP.log and its own files; a failing step does
# not stop the others; the exit status is non-zero when any failed):
#   suite      run_suite.sh's Catch2 tests and CLI parity (CUDA against OpenMP)
#   pbr        pbr_h100.sh: glTF shading frame times and parity (#37)
#   animation  animation_h100.sh: skinning cost and parity (#40)
#   blend      bench_transparency.py: the transparency methods' error and time (#39)
#   python     the Python module's tests on the CUDA build (#42)
#   nvdiffrast rasterize_vs_nvdiffrast.py: rast.rasterize against dr.rasterize (#42)
#   distributed distributed_scale.sh: sort-last and many views over the machine's GPUs (#41)
# At the end OUTDIR/results.tar.gz holds every file written (the device tool
# brings back few files).
set -uo pipefail
out=${1:?usage: session_h100.sh OUTDIR STEP...}
shift
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"
mkdir -p "$out/files"
dev=$root/.device
source scripts/device/device_env.sh
status=0
step() {  # step NAME CMD...
  local name=$1; shift
  local t0=$SECONDS
  echo "=== $name: $*"
  "$@" > "$out/files/$name.log" 2>&1
  local rc=$?
  echo "=== $name: exit $rc ($((SECONDS - t0)) s)"
  tail -25 "$out/files/$name.log"
  [ "$rc" -eq 0 ] || status=1
}
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader
[ -f "$dev/build.env" ] && cat "$dev/build.env"
ldd "$dev/cuda/rast" | grep -E "not found|mpi" || true

for s in "$@"; do
  case $s in
    suite) RAST_SUITE_SKIP=bench,post,count step suite bash scripts/device/run_suite.sh "$out/files/suite" ;;
    pbr) step pbr bash scripts/device/pbr_h100.sh "$dev/cuda/rast" "$dev/openmp/rast" "$dev/shared/models" "$out/files/pbr" ;;
    animation) step animation bash scripts/device/animation_h100.sh "$out/files/animation" ;;
    blend) step blend python3 scripts/measure/bench_transparency.py --rast "$dev/cuda/rast" \
             --out "$out/files/transparency_cuda.csv" --size 1920x1080 --frames 50 --reference-grid 16 ;;
    python) step python env PYTHONPATH="$dev/python" python3 tests/python/test_module.py --rast "$dev/cuda/rast" \
              --workdir /tmp/pymod ;;
    nvdiffrast)
      if ! python3 -c "import nvdiffrast.torch" 2>/dev/null; then
        TORCH_CUDA_ARCH_LIST=9.0 MAX_JOBS=16 python3 -m pip install -q --no-build-isolation --no-deps --no-index \
          .nvdr/src > "$out/files/nvdiffrast_build.log" 2>&1 || echo "nvdiffrast did not build (log in files)"
      fi
      mkdir -p /tmp/stress
      [ -f "$dev/glref_src/gen_scenes.py" ] && python3 "$dev/glref_src/gen_scenes.py" /tmp/stress > /dev/null
      step nvdiffrast env PYTHONPATH="$dev/python" python3 scripts/device/rasterize_vs_nvdiffrast.py \
        --rast "$dev/cuda/rast" --models "$dev/shared/models" --stress /tmp/stress \
        --out "$out/files/rasterize_vs_nvdiffrast.csv" ;;
    distributed) step distributed bash scripts/device/distributed_scale.sh "$dev/cuda/rast" "$out/files/distributed" ;;
    *) echo "unknown step $s"; status=1 ;;
  esac
done
tar -czf "$out/results.tar.gz" -C "$out" files && rm -rf "$out/files"
exit $status
