#!/usr/bin/env bash
# Gather what a run on a separate GPU machine needs into .device/ (git-ignored),
# so that the folder can travel next to a copy of the working tree:
#
#   .device/cuda/rast, .device/cuda/rast_tests   the CUDA build   (default build/cuda)
#   .device/openmp/rast                          a CPU build, the parity reference
#   .device/assimp/                              Debian's assimp glTF2 test models
#   .device/shared/models/                       ../shared/models, when present
#   .device/shared/envs/                         ../shared/envs (the .hdr environments), when present
#   .device/lib/                                 host runtime libraries the builds need
#                                                (libgomp, libdraco, libmeshoptimizer, OpenEXR), in case the target lacks them
#   .device/lib-mpi/                             Debian's OpenMPI libraries (RAST_MPI builds), used
#                                                where the target has no OpenMPI 4 (session_h100.sh)
#   .device/python/rast/                         the CUDA build's Python module, when built
#   .device/kokkos_count.so                      Kokkos Tools launch counter (scripts/device/kokkos_tools/kokkos_count.cpp)
#   .device/kokkos_ktime.so                      Kokkos Tools per-kernel timer (scripts/device/kokkos_tools/kokkos_ktime.cpp)
#   .device/kokkos_htime.so                      Kokkos Tools host timeline of a call (scripts/device/kokkos_tools/kokkos_htime.cpp)
#   .device/src/tests/                           golden images and CLI test scripts of the
#                                                sources the binaries were built from
#   .device/build.env                            where the binaries were built (test data
#                                                paths compiled into rast_tests)
#   .device/glref, .device/glref_src/            ../shared/tools/glref built here (the
#                                                OpenGL yardstick, scripts/device/three_way.sh)
#                                                and its gen_scenes.py, when found
#   .device/glblend                              scripts/measure/glblend built here (OpenGL with
#                                                sorted blending, scripts/device/transparency.sh), when found
#
# Usage: bash scripts/device/pack.sh [--cuda-build DIR] [--cpu-build DIR] [--glref PATH] [--glblend PATH]
# Build first, e.g.:
#   cmake --preset cuda && cmake --build build/cuda --target rast rast_tests
#   cmake --preset openmp -B build/h-cudaref && cmake --build build/h-cudaref --target rast
# Then run scripts/device/run_suite.sh on the GPU machine from the repository root.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
cuda_build=$root/build/cuda
cpu_build=$root/build/openmp
assimp=${RAST_ASSIMP_GLTF_DIR:-/usr/share/assimp/models/glTF2}
shared=${RAST_SHARED_DIR:-$root/../shared}
glref=$cpu_build/tests/cli_glref_agreement/glref-build/glref
glblend=$root/build/glblend/glblend
while [ $# -gt 0 ]; do
  case $1 in
    --glref) glref=$2; shift 2 ;;
    --glblend) glblend=$2; shift 2 ;;
    --cuda-build) cuda_build=$(cd "$2" && pwd); shift 2 ;;
    --cpu-build) cpu_build=$(cd "$2" && pwd); shift 2 ;;
    *) echo "pack.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done

for f in "$cuda_build/rast" "$cpu_build/rast"; do
  [ -x "$f" ] || { echo "pack.sh: $f is missing: build it first" >&2; exit 1; }
done
[ -x "$cuda_build/tests/rast_tests" ] ||
  echo "pack.sh: note: $cuda_build/tests/rast_tests is not built: run_suite.sh's tests step will fail" >&2

# Keep .device/ out of git without touching the shared .gitignore.
exclude=$(git -C "$root" rev-parse --git-path info/exclude 2>/dev/null || true)
if [ -n "$exclude" ]; then
  case $exclude in /*) ;; *) exclude=$root/$exclude ;; esac
  mkdir -p "$(dirname "$exclude")"
  grep -qxF '/.device/' "$exclude" 2>/dev/null || echo '/.device/' >> "$exclude"
fi

dev=$root/.device
rm -rf "$dev"
mkdir -p "$dev/cuda" "$dev/openmp" "$dev/lib"
cp "$cuda_build/rast" "$dev/cuda/rast"
[ -x "$cuda_build/tests/rast_tests" ] && cp "$cuda_build/tests/rast_tests" "$dev/cuda/rast_tests"
[ -x "$cuda_build/rast-serial" ] && cp "$cuda_build/rast-serial" "$dev/cuda/rast-serial"
cp "$cpu_build/rast" "$dev/openmp/rast"
# Symbols are not needed there; the carry folder has a size limit.
strip "$dev"/cuda/* "$dev"/openmp/* 2>/dev/null || true

if [ -d "$assimp" ]; then
  cp -r "$assimp" "$dev/assimp"
else
  echo "pack.sh: note: $assimp absent; tests on Debian's models will skip" >&2
fi
if [ -d "$shared/models" ]; then
  mkdir -p "$dev/shared"
  cp -r "$shared/models" "$dev/shared/models"
else
  echo "pack.sh: note: $shared/models absent; tests on shared models will skip" >&2
fi
if [ -d "$shared/envs" ]; then  # rast_tests "[.bench]" filters ../shared/envs/chinese_garden_1k.hdr
  mkdir -p "$dev/shared"
  cp -r "$shared/envs" "$dev/shared/envs"
fi

if [ -x "$glref" ]; then
  cp "$glref" "$dev/glref"
  mkdir -p "$dev/glref_src"
  [ -f "$shared/tools/glref/gen_scenes.py" ] && cp "$shared/tools/glref/gen_scenes.py" "$dev/glref_src/"
else
  echo "pack.sh: note: no glref at $glref (ctest cli_glref_agreement builds one); no OpenGL comparison" >&2
fi
if [ -x "$glblend" ]; then
  cp "$glblend" "$dev/glblend"
  strip "$dev/glblend" 2>/dev/null || true
else
  echo "pack.sh: note: no glblend at $glblend (cmake -S scripts/measure/glblend -B build/glblend); no blending comparison" >&2
fi

# Kernel-launch counter (Kokkos Tools library; run_suite.sh uses it when present).
if command -v g++ >/dev/null; then
  g++ -O2 -shared -fPIC -o "$dev/kokkos_count.so" "$root/scripts/device/kokkos_tools/kokkos_count.cpp" ||
    echo "pack.sh: note: kokkos_count.so not built; no launch counts" >&2
  g++ -O2 -shared -fPIC -o "$dev/kokkos_ktime.so" "$root/scripts/device/kokkos_tools/kokkos_ktime.cpp" -ldl ||
    echo "pack.sh: note: kokkos_ktime.so not built; no per-kernel times" >&2
  g++ -O2 -shared -fPIC -o "$dev/kokkos_htime.so" "$root/scripts/device/kokkos_tools/kokkos_htime.cpp" ||
    echo "pack.sh: note: kokkos_htime.so not built; no host timelines" >&2
fi

# Non-system shared libraries the binaries use (libgomp for the OpenMP build;
# Debian's Draco and meshoptimizer for the glTF loader, docs/compression.md).
for f in "$dev"/cuda/* "$dev"/openmp/*; do
  ldd "$f" | awk '/=> \// {print $3}' | grep -E 'libgomp|libdraco|libmeshoptimizer|libOpenEXR|libIex|libIlmThread|libImath' || true
done | sort -u | while read -r lib; do cp -L "$lib" "$dev/lib/"; done

# Debian's OpenMPI, which RAST_MPI builds link (libmpi.so.40 and what it
# needs): loaded only where the GPU machine has no OpenMPI 4 of its own
# (session_h100.sh decides). Single-process runs never start MPI.
mkdir -p "$dev/lib-mpi"
for f in "$dev"/cuda/*; do
  ldd "$f" | awk '/=> \// {print $3}' | grep -E 'libmpi|libopen-(rte|pal)|libhwloc|libevent|libudev' || true
done | sort -u | while read -r lib; do cp -L "$lib" "$dev/lib-mpi/"; done

# The CUDA build's Python module (docs/python.md), when it was built: the
# machine's own python3 imports it with PYTHONPATH=.device/python.
if [ -d "$cuda_build/python/rast" ] && ls "$cuda_build"/python/rast/_rast*.so > /dev/null 2>&1; then
  mkdir -p "$dev/python"
  cp -r "$cuda_build/python/rast" "$dev/python/rast"
  strip "$dev"/python/rast/_rast*.so 2>/dev/null || true
fi

src_dir=$(sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$cuda_build/CMakeCache.txt")
shared_dir=$(sed -n 's/^RAST_SHARED_DIR:PATH=//p' "$cuda_build/CMakeCache.txt")
# The test files of the sources the binaries were built from (golden images, the
# parity script), so that a run elsewhere does not depend on the working tree
# there matching the build.
mkdir -p "$dev/src/tests"
cp -r "$src_dir/tests/golden" "$dev/src/tests/golden"
cp -r "$src_dir/tests/cli" "$src_dir/tests/support" "$dev/src/tests/"
{
  echo "RAST_BUILD_SOURCE_DIR=$src_dir"
  echo "RAST_BUILD_SHARED_DIR=$shared_dir"
  echo "RAST_BUILD_COMMIT=${RAST_BUILD_COMMIT:-$(git -C "$src_dir" rev-parse --short HEAD 2>/dev/null || echo unknown)$(git -C "$src_dir" diff --quiet 2>/dev/null || echo +dirty)}"
  echo "RAST_BUILD_DATE=$(date -u +%Y-%m-%dT%H:%M:%SZ)"
  echo "RAST_BUILD_COMPILER=$(sed -n 's/^CMAKE_CXX_COMPILER:[A-Z]*=//p' "$cuda_build/CMakeCache.txt")"
  echo "RAST_BUILD_KOKKOS=$(sed -n 's/^Kokkos_DIR:PATH=//p' "$cuda_build/CMakeCache.txt")"
} > "$dev/build.env"

echo "pack.sh: $(du -sh "$dev" | cut -f1) in $dev"
for f in "$dev"/cuda/* "$dev"/openmp/*; do
  if ldd "$f" | grep libcudart >/dev/null; then echo "pack.sh: warning: $f links libcudart dynamically" >&2; fi
done
