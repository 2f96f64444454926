// A frame's visibility keys handed to a caller that writes its own outputs
// from them (RenderSettings::keysOnly: rast::lib::rasterize's nvdiffrast-style
// outputs). Why here and not in the caller: the keys carry the pipeline's
// bookkeeping for the next frame. The shade stage clears each key it reads
// and resets the visbuffer raster's block depth bounds (raster_visbuffer.cpp)
// so that the next frame needs no clearing pass (FrameBuffers::visClear), and
// it reads no key of a block the raster left alone this frame (the block
// tags). FrameKeys::take does the same for the caller's pass, one pixel at a
// time, so a keys-only frame costs what a shaded one costs minus the shading.
//
// The same pass hands the frame's counters to the host (publish): its first
// thread copies them into the renderer's page-locked host copy, which the
// device writes directly, so Renderer::lastFrameFit only waits for the pass
// and no copy follows it (on the H100 the copy's own launch and the wait for
// the copy engine cost a call about 5-8 us of a 100 us fixed cost).
#pragma once

#include "pipeline/data/frame_buffers.h"
#include "pipeline/rules/raster_rules.h"
#include "pipeline/rules/visbuffer_blocks.h"

namespace rast {

struct FrameKeys {
  DView<uint64_t> vis;
  DView<RasterTri> tris;
  DView<uint32_t> blockFrame, blockDepth;
  DView<FrameUniforms> frame;
  int32_t blocksPerRow = 0;
  int32_t tagged = 0;       // the raster tagged the blocks it wrote (ShadeParams::blockFrames)
  int32_t resetBlocks = 0;  // the block depth bounds exist and are reset with the keys
  DView<uint32_t> counters;    // the frame's counters (frame_buffers.h), final once the pass runs
  uint32_t* countersOut = nullptr;  // the renderer's host copy, device-writable (null: the renderer copies)

  // Called by exactly one thread of the pass (the caller's choice, e.g. the
  // one that takes pixel 0).
  KOKKOS_INLINE_FUNCTION void publish() const {
    if (countersOut)
      for (size_t i = 0; i < counters.extent(0); ++i) countersOut[i] = counters(i);
  }

  // The drawn triangle (primitive id - 1) covering pixel (x, y), index i
  // (bottom row first), or -1 where none does. Every pixel of the frame must
  // be taken once, in one pass queued right after the frame: the key is left
  // clear for the next frame, and a block's first pixel resets its bound.
  KOKKOS_INLINE_FUNCTION int64_t take(int64_t i, int32_t x, int32_t y) const {
    constexpr int32_t kMask = (1 << kVisBlockShift) - 1;
    const uint32_t b = uint32_t(y >> kVisBlockShift) * uint32_t(blocksPerRow) + uint32_t(x >> kVisBlockShift);
    if (resetBlocks && ((x | y) & kMask) == 0) blockDepth(b) = kFarDepthBits;
    if (tagged && blockFrame(b) != frame(0).frame) return -1;  // no key written here this frame: clear
    const uint64_t key = vis(i);
    if (key == kClearKey) return -1;
    vis(i) = kClearKey;
    const uint32_t idx = uint32_t(key & 0xffffffffu);
    return idx == 0 ? -1 : int64_t(tris(idx - 1).prim);
  }
};

}  // namespace rast
