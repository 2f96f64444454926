#!/usr/bin/env bash
# A mutation campaign of the rast command line under AddressSanitizer and
# UndefinedBehaviorSanitizer: builds rast with -fsanitize=address,undefined
# (build/asan), then runs `rast render` on mutated scene files (the fuzz seed
# corpus and assimp's glTF test models) with random flags, for a bounded time.
#
#   bash scripts/fuzz/fuzz_cli.sh [--seconds N] [--seed S] [--out DIR]
#
# Every run must end in exit 0 with an image, or in exit 1/2 with one
# 'rast: error:' line; a sanitizer report, a signal, a hang (> 60 s) or a
# multi-line error is a finding, kept as DIR/finding-*/ (input, command, output).
# Defaults: 600 s, seed 1, build/fuzz-cli. Exits 1 when anything was found.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."

seconds=600 seed=1 out=build/fuzz-cli
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) seconds="$2"; shift 2 ;;
    --seed) seed="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    *) echo "usage: $0 [--seconds N] [--seed S] [--out DIR]" >&2; exit 2 ;;
  esac
done

if [ -z "${Kokkos_ROOT:-}" ] && [ -d .deps/kokkos/install ]; then export Kokkos_ROOT=$PWD/.deps/kokkos/install; fi
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S . -B build/asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRAST_EXEC_SPACE=OpenMP \
  -DRAST_BUILD_TESTS=OFF -DRAST_SERIAL_TWIN=OFF "${launcher[@]}" \
  -DCMAKE_CXX_FLAGS="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
cmake --build build/asan --target rast
mkdir -p "$out"
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export OMP_PROC_BIND=${OMP_PROC_BIND:-false} OMP_NUM_THREADS=${OMP_NUM_THREADS:-2}
python3 scripts/fuzz/fuzz_cli.py --rast build/asan/rast --seconds "$seconds" --seed "$seed" --out "$out" \
  --seeds tests/fuzz/corpus /usr/share/assimp/models/glTF2
