// Bloom's building blocks, exposed for the tests: the bright pass (to half
// resolution), the separable Gaussian blur with team scratch, and its weights.
#pragma once

#include "pipeline/data/device.h"
#include "base/vec.h"

#include <vector>

namespace rast {

// Weights w[0..r] of a Gaussian with sigma = r / 3 (the radius covers three
// sigmas), normalised so that w[0] + 2 * sum(w[1..r]) = 1. r >= 1.
std::vector<float> gaussianWeights(int radius);

KOKKOS_INLINE_FUNCTION float luminance(float4 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

// What a pixel contributes to bloom: nothing at or under the threshold
// luminance; above it, the colour scaled by the excess fraction (so the bloom
// rises continuously from zero at the threshold).
KOKKOS_INLINE_FUNCTION float4 brightPart(float4 c, float threshold) {
  const float l = luminance(c);
  if (!(l > threshold)) return float4{0.0f, 0.0f, 0.0f, 0.0f};
  const float k = (l - threshold) / l;
  return float4{c.x * k, c.y * k, c.z * k, 0.0f};
}

// half(x, y) = mean of brightPart over the 2x2 full-resolution pixels it covers
// (edge pixels repeated); half is ((w + 1) / 2) x ((h + 1) / 2).
void bloomBrightPass(const DView<float4>& full, int w, int h, const DView<float4>& half, float threshold);

// In-place separable Gaussian blur of img (w x h, row-major), clamp-to-edge;
// tmp holds the intermediate (at least w * h). weights from gaussianWeights.
void blurSeparable(const DView<float4>& img, const DView<float4>& tmp, int w, int h, const DView<float>& weights,
                   int radius);

}  // namespace rast
