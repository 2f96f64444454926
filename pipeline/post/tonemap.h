// Tone-mapping curves, per channel, from linear scene light [0, inf) to
// display light [0, 1]. Host and device (the tests check them directly).
#pragma once

#include "base/vec.h"

namespace rast {

// Reinhard: x / (1 + x); 1 -> 0.5, tends to 1.
KOKKOS_INLINE_FUNCTION float toneReinhard(float x) {
  x = x > 0.0f ? x : 0.0f;
  return x / (1.0f + x);
}

// ACES filmic, Narkowicz's fit of the RRT+ODT (2015):
// x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14), clamped to [0, 1].
KOKKOS_INLINE_FUNCTION float toneAces(float x) {
  x = x > 0.0f ? x : 0.0f;
  return clamp01(x * (2.51f * x + 0.03f) / (x * (2.43f * x + 0.59f) + 0.14f));
}

}  // namespace rast
