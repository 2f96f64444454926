// scanExclusive (scan.h): one Kokkos parallel_scan, named by its caller's stage.
#include "pipeline/data/scan.h"

namespace rast {
namespace {

// Exclusive prefix sum in place; the grand total goes to counters(slot).
struct ExclusiveScan {
  DView<uint32_t> data;
  DView<uint32_t> counters;
  uint32_t n;
  int slot;
  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t i, uint32_t& update, const bool final) const {
    const uint32_t v = data(i);
    if (final) {
      data(i) = update;
      if (i + 1 == n) counters(slot) = update + v;
    }
    update += v;
  }
};

}  // namespace

void scanExclusive(const char* label, const DView<uint32_t>& data, uint32_t n, const DView<uint32_t>& counters, int slot) {
  if (n == 0) {
    Kokkos::parallel_for(label, Range(0, 1), KOKKOS_LAMBDA(const int) { counters(slot) = 0; });
    return;
  }
  Kokkos::parallel_scan(label, Kokkos::RangePolicy<Exec, Kokkos::IndexType<uint32_t>>(0, n),
                        ExclusiveScan{data, counters, n, slot});
}

}  // namespace rast
