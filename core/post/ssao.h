// Screen-space ambient occlusion's sample kernel, exposed for the reference
// comparison and the tests.
#pragma once

#include "../vec.h"
#include "post_settings.h"

#include <vector>

namespace rast {

// n fixed hemisphere directions around +z (xyz unit, w = 1): cosine-weighted,
// from a Hammersley set, as the ray-traced reference distributes its rays.
std::vector<float4> ssaoKernel(int n);

// The world-space radius a frame uses: the requested one, or 5% of the
// camera's distance to its target.
float ssaoRadiusFor(const PostSettings& s, double eyeTargetDistance);

}  // namespace rast
