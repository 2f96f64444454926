// samplePattern (sample_pattern.h): the standard positions, snapped to 1/256 pixel.
#include "pipeline/rules/sample_pattern.h"

#include "base/error.h"

#include <algorithm>
#include <string>

namespace rast {

SamplePattern samplePattern(int count) {
  // D3D / Vulkan standard multisample positions in 1/16 pixel (y down there;
  // negated for our y-up window space), scaled to 1/256 pixel.
  static const int p2[2][2] = {{4, 4}, {-4, -4}};
  static const int p4[4][2] = {{-2, -6}, {6, -2}, {-6, 2}, {2, 6}};
  static const int p8[8][2] = {{1, -3}, {-1, 3}, {5, 1}, {-3, -5}, {-5, 5}, {-7, -1}, {3, 7}, {7, -7}};
  SamplePattern sp;
  const int(*src)[2] = nullptr;
  switch (count) {
    case 1: return sp;
    case 2: src = p2; break;
    case 4: src = p4; break;
    case 8: src = p8; break;
    default: throw Error("MSAA supports 1, 2, 4 or 8 samples, not " + std::to_string(count));
  }
  sp.count = count;
  for (int s = 0; s < count; ++s) {
    sp.ox[s] = src[s][0] * (kSubOne / 16);
    sp.oy[s] = -src[s][1] * (kSubOne / 16);
    sp.minX = s ? std::min(sp.minX, sp.ox[s]) : sp.ox[s];
    sp.maxX = s ? std::max(sp.maxX, sp.ox[s]) : sp.ox[s];
    sp.minY = s ? std::min(sp.minY, sp.oy[s]) : sp.oy[s];
    sp.maxY = s ? std::max(sp.maxY, sp.oy[s]) : sp.oy[s];
  }
  return sp;
}

}  // namespace rast
