#!/usr/bin/env bash
# Builds the libFuzzer harness of the glTF/GLB loader (tests/fuzz/fuzz_loader.cpp)
# with clang's -fsanitize=fuzzer,address,undefined and runs it on a copy of the
# seed corpus (tests/fuzz/corpus) for a bounded time.
#
#   bash scripts/fuzz/fuzz_loader.sh [--seconds N] [--jobs J] [--out DIR]
#
# Defaults: 600 s, 1 job, build/fuzz. CI runs it with --seconds 60. New
# interesting inputs stay in DIR/corpus (not in the repository); a crash leaves
# DIR/crash-* and makes the script fail. Needs clang-14 and libclang-rt-14-dev
# (scripts/setup/bootstrap.sh installs them) and the Kokkos headers the loader's
# headers include (Kokkos_ROOT, else the bootstrap's .deps/kokkos/install).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."

seconds=600 jobs=1 out=build/fuzz
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) seconds="$2"; shift 2 ;;
    --jobs) jobs="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    *) echo "usage: $0 [--seconds N] [--jobs J] [--out DIR]" >&2; exit 2 ;;
  esac
done

CXX=${FUZZ_CXX:-$(command -v clang++-14 || command -v clang++ || true)}
[ -n "$CXX" ] || { echo "fuzz_loader: clang++ not found (apt-get install clang-14 libclang-rt-14-dev)" >&2; exit 1; }
kokkos=${Kokkos_ROOT:-$PWD/.deps/kokkos/install}
for k in /usr/local /usr /opt/kokkos; do  # where bootstrap.sh may have found an installed Kokkos
  [ -f "$kokkos/include/Kokkos_Core.hpp" ] || kokkos=$k
done
[ -f "$kokkos/include/Kokkos_Core.hpp" ] || { echo "fuzz_loader: no Kokkos headers in $kokkos (run scripts/setup/bootstrap.sh or set Kokkos_ROOT)" >&2; exit 1; }

mkdir -p "$out/corpus"
bin="$out/fuzz_loader"
srcs=(tests/fuzz/fuzz_loader.cpp
      host/gltf/file_gate.cpp host/gltf/schema_check.cpp host/gltf/image_decode.cpp host/gltf/accessors.cpp
      host/gltf/model_walk.cpp host/gltf/materials.cpp host/gltf/uri_resolver.cpp
      host/gltf/animation_load.cpp host/gltf/instancing.cpp host/gltf/compression.cpp
      host/scene/scene.cpp host/scene/animation.cpp host/scene/host_workers.cpp host/scene/memory_budget.cpp host/scene/tangents.cpp
      host/third_party_impl.cpp)
# Rebuild only when a source is newer than the binary.
need=1
if [ -x "$bin" ]; then
  need=0
  for s in "${srcs[@]}" $(find host base -name '*.h'); do [ "$s" -nt "$bin" ] && need=1; done
fi
if [ "$need" = 1 ]; then
  echo "fuzz_loader: building $bin with $CXX"
  "$CXX" -std=c++17 -g -O1 -fno-omit-frame-pointer -fopenmp \
    -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined -Wno-macro-redefined \
    -DGLM_FORCE_CXX17 -DTINYGLTF_USE_CPP14 -I. -isystem "$kokkos/include" \
    "${srcs[@]}" -ldraco -lmeshoptimizer -o "$bin"  # the decoders of host/gltf/compression.cpp
fi

# Seeds from the repository, then what earlier runs found.
cp -n tests/fuzz/corpus/* "$out/corpus/" 2>/dev/null || true
echo "fuzz_loader: fuzzing for ${seconds} s with ${jobs} job(s); corpus $out/corpus"
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
log="$out/fuzz_loader.log"
status=0
"$bin" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
  -dict=tests/fuzz/gltf.dict -artifact_prefix="$out/" -print_final_stats=1 \
  $( [ "$jobs" -gt 1 ] && echo "-fork=$jobs" ) \
  "$out/corpus" >"$log" 2>&1 || status=$?
sed -n '/stat::number_of_executed_units\|stat::peak_rss_mb\|stat::new_units_added\|Done [0-9]* runs\|ERROR\|SUMMARY/p' "$log"
if [ "$status" != 0 ]; then
  echo "fuzz_loader: FAILED (exit $status); see $log and $out/crash-*" >&2
  tail -n 40 "$log" >&2
  exit 1
fi
echo "fuzz_loader: no crash in ${seconds} s"
