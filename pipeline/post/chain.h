// The post-processing chain the renderer runs after shading when
// RenderSettings::post asks for any pass: every pass reads and writes the float
// film in place, then the film's one encoder packs it to RGBA8.
//
// Adding a pass: a file here with its run function, one row in the table in
// chain.cpp, and its options in PostSettings (post_settings.h) and the
// command line (app/cli_options.cpp).
#pragma once

#include "pipeline/data/frame_buffers.h"
#include "host/settings/post_settings.h"

namespace rast {

class StageTimer;

// What the passes know of the frame beyond its buffers.
struct PostView {
  int width = 0, height = 0;
  float tanX = 1.0f, tanY = 1.0f;  // view-space x/-z and y/-z at the right and top edges
  float ssaoRadius = 1.0f;         // resolved world-space radius
};

using PostRun = void (*)(PostBuffers&, const PostView&, const PostSettings&);

struct PostPass {
  const char* name;  // stage name in `rast bench`; kernels are rast::post::<name>...
  bool (*enabled)(const PostSettings&);
  PostRun run;
};

// The passes in the order they run.
const PostPass* postPasses(int& count);

// Runs the enabled passes (marking each on the timer), then encodes the film
// into `color`: sRGB8 for light, raw bytes for the diagnostic modes (straight:
// the film's premultiplied alpha as straight alpha bytes).
void runPostChain(PostBuffers& b, const PostView& v, const PostSettings& s, const DView<uint32_t>& color,
                  const DView<uint32_t>& srgbEncodePacked, bool raw, StageTimer* timer, bool straight = false);

// The passes (one file each).
void postSsao(PostBuffers& b, const PostView& v, const PostSettings& s);
void postExposure(PostBuffers& b, const PostView& v, const PostSettings& s);
void postBloom(PostBuffers& b, const PostView& v, const PostSettings& s);
void postToneMap(PostBuffers& b, const PostView& v, const PostSettings& s);
void postEncode(const DView<float4>& hdr, int64_t n, const DView<uint32_t>& color, const DView<uint32_t>& packed, bool raw,
                bool straight = false);

}  // namespace rast
