// Screen-space ambient occlusion's sample kernel and interleave pattern,
// exposed for the reference comparison and the tests.
#pragma once

#include "base/vec.h"
#include "host/settings/post_settings.h"

#include <vector>

namespace rast {

// n fixed hemisphere directions around +z (xyz unit, w = 1): cosine-weighted,
// from a Hammersley set, as the ray-traced reference distributes its rays.
std::vector<float4> ssaoKernel(int n);

// The world-space radius a frame uses: the requested one, or 5% of the
// camera's distance to its target.
float ssaoRadiusFor(const PostSettings& s, double eyeTargetDistance);

// The 4x4 ordered (Bayer) pattern, 0..15, that rotates each pixel's tangent
// frame (ssaoBayer(x, y) sixteenths of a turn) and jitters its first step
// (ssaoBayer(y, x)). Its quarter turn, value / 4, follows the pixel's parity
// (x & 1, y & 1).
KOKKOS_INLINE_FUNCTION int ssaoBayer(int x, int y) {
  const int b[16] = {0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5};
  return b[(x & 3) + 4 * (y & 3)];
}

// Interleaved directions: the pixel in slot c marches directions c, c + G,
// c + 2G, ... of the n (G = ssaoInterleave(n) = min(n, 4)), ceil(n/4) or
// floor(n/4) of them (n < 4: one each, the slots repeat). The slot is the
// pixel's 2x2 cell in its 4x4 tile, so any 3x3 window, and the blur's 5x5,
// holds every slot: the blur gathers all n directions. Why cells and not
// the pixel's parity: parity fixes the Bayer rotation's quarter turn, and
// the directions c, c + 4, ... of the Hammersley kernel lie within a quarter
// turn of each other (their azimuth's first two bits are c's), so each slot
// would lean one way (on the duck: RMSE 0.049 instead of 0.026 against the
// reference). With cells, every slot meets every quarter turn.
KOKKOS_INLINE_FUNCTION int ssaoInterleave(int n) { return n < 4 ? n : 4; }
KOKKOS_INLINE_FUNCTION int ssaoSlot(int x, int y, int n) {
  return (((x >> 1) & 1) + 2 * ((y >> 1) & 1)) % ssaoInterleave(n);
}

}  // namespace rast
