// Supersampling over whole frames (SSAA, the reference mode): each pass's float
// film summed in linear light, then the average put back in the film for the
// post chain to encode once.
#pragma once

#include "pipeline/data/frame_buffers.h"

namespace rast {

// Supersampling by accumulation in float: add the pass's film (f.post.hdr)
// into f.accum, then put the average back in the film (encoded by the post
// chain's encoder).
void accumulateColor(FrameBuffers& f, bool first);
void resolveAccumulated(FrameBuffers& f, int passes);

}  // namespace rast
