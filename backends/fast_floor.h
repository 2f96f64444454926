// floor for texel addressing, the one place where host and device code
// differ on purpose (backend-specific, so it lives in backends/): the device
// has a rounding instruction; the baseline x86-64 host build does not, and a
// libm call per coordinate was a good part of a textured span's cost.
#pragma once

#include <Kokkos_Core.hpp>

#include <cmath>
#include <cstdint>

namespace rast {

// floorf on the device; on the host the same value without a call into libm
// (the baseline x86-64 build has no rounding instruction, and four calls per
// bilinear sample were a good part of a textured span's cost). Integral
// magnitudes (from 2^23 up), infinities and NaN are their own floor; zero's
// sign may differ from floorf's, which no use below can see.
KOKKOS_INLINE_FUNCTION float floorTexel(float x) {
#if defined(__CUDA_ARCH__) || defined(__HIP_DEVICE_COMPILE__)
  return ::floorf(x);
#else
  if (!(x > -8388608.0f && x < 8388608.0f)) return x;
  const float t = float(int32_t(x));  // towards zero
  return t > x ? t - 1.0f : t;
#endif
}

// floor as a texel index, for arguments the callers have already bounded
// (|x| < 2^31, not NaN: reduced texture coordinates times the side, clamped
// cube map coordinates, the split-sum table's): on the host a truncation and
// one correction, without floorTexel's range test; the same value as
// int32_t(floorTexel(x)) there, and float() of it is floorTexel(x) (exact,
// the index being an integer that a float holds). On the device int32_t(floorf(x)).
KOKKOS_INLINE_FUNCTION int32_t floorIndex(float x) {
#if defined(__CUDA_ARCH__) || defined(__HIP_DEVICE_COMPILE__)
  return int32_t(::floorf(x));
#else
  const int32_t i = int32_t(x);  // towards zero
  return float(i) > x ? i - 1 : i;
#endif
}

}  // namespace rast
