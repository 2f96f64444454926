#!/usr/bin/env bash
# Builds the libFuzzer harness of the Radiance .hdr reader (tests/fuzz/fuzz_hdr.cpp)
# with ASan and UBSan and runs it from seeds made here (a flat and a run-length
# file; no binary seeds in the tree):
#
#   bash scripts/fuzz/fuzz_hdr.sh [--seconds N] [--out DIR]
#
# Needs clang++ with libFuzzer (apt-get install clang-14 libclang-rt-14-dev) and
# Kokkos' headers (the memory ledger's header pulls in the scene's).
# Exits non-zero on a finding (see DIR/fuzz_hdr.log and DIR/crash-*).
set -euo pipefail
cd "$(dirname "$0")/../.."
seconds=60
out=build/fuzz-hdr
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) seconds="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    *) echo "usage: $0 [--seconds N] [--out DIR]" >&2; exit 2 ;;
  esac
done
CXX=${FUZZ_CXX:-$(command -v clang++-14 || command -v clang++ || true)}
[ -n "$CXX" ] || { echo "fuzz_hdr: clang++ not found (apt-get install clang-14 libclang-rt-14-dev)" >&2; exit 1; }
kokkos=${Kokkos_ROOT:-$PWD/.deps/kokkos/install}
for k in /usr/local /usr /opt/kokkos; do  # where bootstrap.sh may have found an installed Kokkos
  [ -f "$kokkos/include/Kokkos_Core.hpp" ] || kokkos=$k
done
[ -f "$kokkos/include/Kokkos_Core.hpp" ] || { echo "fuzz_hdr: no Kokkos headers in $kokkos (run scripts/setup/bootstrap.sh or set Kokkos_ROOT)" >&2; exit 1; }
mkdir -p "$out/corpus"
bin="$out/fuzz_hdr"
"$CXX" -std=c++17 -g -O1 -fno-omit-frame-pointer -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined \
  -fopenmp -I. -isystem "$kokkos/include" tests/fuzz/fuzz_hdr.cpp host/image/hdr_image.cpp host/scene/memory_budget.cpp -o "$bin"
python3 - "$out/corpus" <<'PY'
import sys
d = sys.argv[1]
head = lambda w, h: b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\nEXPOSURE=1\n\n-Y %d +X %d\n" % (h, w)
open(d + "/flat.hdr", "wb").write(head(4, 2) + bytes([128, 64, 32, 129]) * 8)
row = bytes([2, 2, 0, 16]) + b"".join(bytes([128 + 16, c]) for c in (200, 100, 50, 130))
open(d + "/rle.hdr", "wb").write(head(16, 3) + row * 2 + bytes([2, 2, 0, 16]) + bytes([16]) + bytes(range(100, 116)) +
                                 bytes([128 + 16, 1, 128 + 16, 2, 128 + 16, 131]))
PY
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
log="$out/fuzz_hdr.log"
status=0
"$bin" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=1024 -max_len=4096 -artifact_prefix="$out/" \
  -print_final_stats=1 "$out/corpus" >"$log" 2>&1 || status=$?
sed -n '/stat::number_of_executed_units\|stat::peak_rss_mb\|stat::new_units_added\|Done [0-9]* runs\|ERROR\|SUMMARY/p' "$log"
if [ "$status" != 0 ]; then
  echo "fuzz_hdr: FAILED (exit $status); see $log and $out/crash-*" >&2
  tail -n 40 "$log" >&2
  exit 1
fi
