// The index of a word's lowest set bit: a compiler builtin on the host, the
// device's own instruction under CUDA and HIP (backend-specific, so it lives
// in backends/). The CPU's fused shading finds a row's runs with it
// (pipeline/cpu/shade_spans.h).
#pragma once

#include <Kokkos_Core.hpp>

#include <cstdint>

namespace rast {

// x must be nonzero.
KOKKOS_FORCEINLINE_FUNCTION int32_t lowestBit(uint64_t x) {
#if defined(__CUDA_ARCH__) || defined(__HIP_DEVICE_COMPILE__)
  return __ffsll((long long)x) - 1;
#else
  return __builtin_ctzll(x);
#endif
}

}  // namespace rast
