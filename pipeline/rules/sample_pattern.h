// Where a pixel's coverage samples lie under MSAA: the standard D3D/Vulkan
// positions, in the 1/256-pixel units of the snapping rules, so that coverage
// of every sample follows the same exact edge functions as single sampling.
#pragma once

#include "pipeline/data/gpu_types.h"

namespace rast {

// The standard D3D/Vulkan sample positions for 1, 2, 4 or 8 samples (y up).
SamplePattern samplePattern(int count);

}  // namespace rast
