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

// Khronos PBR Neutral (Khronos Group, 2024; the glTF Sample Renderer's
// default): colours below 0.76 keep their hue and value, brighter ones are
// compressed towards white, with a small offset that lifts near-black.
// On a whole colour, not per channel.
KOKKOS_INLINE_FUNCTION float3 tonePbrNeutral(float3 c) {
  constexpr float kStart = 0.8f - 0.04f, kDesaturation = 0.15f;
  const float x = c.x < c.y ? (c.x < c.z ? c.x : c.z) : (c.y < c.z ? c.y : c.z);
  const float offset = x < 0.08f ? x - 6.25f * x * x : 0.04f;
  c = c - float3{offset, offset, offset};
  const float peak = c.x > c.y ? (c.x > c.z ? c.x : c.z) : (c.y > c.z ? c.y : c.z);
  if (peak < kStart) return c;
  constexpr float d = 1.0f - kStart;
  const float newPeak = 1.0f - d * d / (peak + d - kStart);
  c = c * (newPeak / peak);
  const float g = 1.0f - 1.0f / (kDesaturation * (peak - newPeak) + 1.0f);
  return c * (1.0f - g) + float3{newPeak, newPeak, newPeak} * g;
}

}  // namespace rast
