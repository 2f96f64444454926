// The transparency stage's front (docs/transparency.md): the passes that draw
// the raster triangles of glTF MASK and BLEND materials, which the setup marks
// and the raster methods skip (markAlphaClass, raster_rules.h).
//   * alphaWorkLists: each class's work items (8x8 blocks of its triangles' boxes).
//   * rasterMask: MASK triangles alpha-tested per sample and depth-tested into
//     the visibility buffer with the same keys and atomic minimum as the
//     raster methods: a discarded fragment never wins, whatever the method.
//   * blendCollect (before shading: it reads the opaque depth) and blendResolve
//     (after it: composites over the shaded opaque colour in the float film);
//     exact, sorted and weighted: tile lists walked per sample (blend_tiles.cpp).
#pragma once

#include "pipeline/shade/shade.h"

namespace rast {

// What a frame's transparency does, decided by the frame plan.
struct BlendPlan {
  bool mask = false, blend = false;          // the scene draws MASK / BLEND triangles
  Transparency method = Transparency::Exact;  // never Auto
  int k = 8;                                  // kbuffer
  // The method walks tile lists (exact and sorted always; weighted unless
  // its lists would exceed the memory budget, then its fixed-memory sums).
  bool lists = true;
  // The resolve also writes the frame's RGBA8 colour (encodeFilm: raw, the
  // diagnostic modes' bytes; straight, straight alpha), and the post chain,
  // which would only encode the film, does not run: the tile lists' resolve
  // writes every pixel, and the film then has no other pass to wait for.
  bool encode = false, raw = false, straight = false;
  // The shade stage writes the opaque depth that the lists' resolve reads
  // (shadeWritesOpaqueDepth): the lists' stage copies none.
  bool shadeDepth = false;
  // GPUs' glTF shading (and the team form under TestHooks::teamResolve):
  // the uniform blocks are classified before shading, and the shade stage
  // composites their pixels as it shades them (ShadeBlend): no pass of its
  // own reads and writes the film for them. Implies shadeDepth.
  bool shadeComposite = false;
  // With shadeComposite and encode: the pixels that the shade stage
  // composites get their bytes and no film value, which nothing reads after
  // them (the film is not an output of such a frame; Renderer::filmBottomUp).
  // Not under TestHooks::keepFilm, for tests that compare films.
  bool filmless = false;
};

// Whether `method` walks tile lists, `fallback` telling that they would
// exceed the budget (exact and sorted then become kbuffer: chooseTransparency).
inline bool walksTileLists(Transparency method, bool fallback) {
  return method == Transparency::Exact || method == Transparency::Sorted ||
         (method == Transparency::Weighted && !fallback);
}

void alphaWorkLists(const DeviceScene& s, FrameBuffers& f, const BlendPlan& b);
void rasterMask(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p);
// opaqueKeys: every sample's opaque key (f.vis; under a sort-last split the
// composited keys, whose depth is the whole scene's).
void blendCollect(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights,
                  const BlendPlan& b, const DView<uint64_t>& opaqueKeys);
void blendResolve(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights,
                  const BlendPlan& b);

// Whether every pass of a frame's BLEND method launches lightweight (the
// listed methods with a specialised fragment shading: blend_tiles.cpp), so
// that the frame can be recorded and replayed (backends/frame_graphs.h);
// kbuffer, the fixed-memory sums and the general fragment maths launch
// heavyweight (pipeline/data/device.h). What else the passes' launches
// depend on besides device memory and the plan's key: the resolve's scratch
// size, from the last frame's longest list.
bool blendLaunchesLightweight(const BlendPlan& b, const ShadeParams& p);
// Whether the tile lists' resolve under shading p can write the colour's
// bytes itself (BlendPlan::encode): on CPUs always (kBlendResolveEncodes);
// on GPUs under the glTF shading, whose uniform blocks' pixels a light
// kernel writes (pipeline/blend/uniform_blocks.h), where the team form's
// encoding under Lambert cost it what the encoder's pass did.
bool blendResolveEncodes(const ShadeParams& p);
// Whether the uniform blocks of a frame under shading p can be composited by
// the shade stage (BlendPlan::shadeComposite; the frame plan adds its own
// conditions): the team form under the glTF shading.
bool blendShadeComposites(const ShadeParams& p);
uint64_t blendLaunchKey(const FrameBuffers& f);
// The layout of the frame's tile lists (blend_tiles.cpp): 0 counted, else
// strided with this stride, where the last frame's longest list fits it and
// the lists' buffer holds it (Renderer::lastFrameFit grows it).
uint32_t listStrideFor(const FrameBuffers& f);
// The entries the strided layout needs for f's frame where the last frame's
// lists allow it, else 0.
uint64_t stridedListRoom(const FrameBuffers& f);

// Device bytes per sample of a method's fixed buffers (opaque depth and
// block counts, k-buffer, weighted sums), and per entry of the listed
// methods' tile lists (grown to the frame's need): for the memory budget.
uint64_t blendBytesPerSample(const BlendPlan& b);
constexpr uint64_t kBytesPerListEntry = sizeof(uint32_t);

}  // namespace rast
