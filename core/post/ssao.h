// Screen-space ambient occlusion's sample kernel, exposed for the reference
// comparison and the tests.
#pragma once

#include "../vec.h"
#include "post_settings.h"

#include <vector>

namespace rast {

// n fixed hemisphere samples around +z (xyz, unit length times a scale in
// (0, 1] that puts more samples near the point): cosine-weighted directions
// from a Hammersley set, scales from the base-3 radical inverse.
std::vector<float4> ssaoKernel(int n);

// The world-space radius a frame uses: the requested one, or 5% of the
// camera's distance to its target.
float ssaoRadiusFor(const PostSettings& s, double eyeTargetDistance);

}  // namespace rast
