// One drawn triangle's setup, shared by the setup's passes
// (primitive_setup.cpp): its corners fetched, clipped in homogeneous space
// where it crosses a plane, culled, snapped and counted into raster
// triangles, with their work items (the visbuffer's, the BLEND class's).
// Here and not in primitive_setup.cpp because that file holds the passes
// (the GPU's count and write passes, the host's one pass) and their scans.
#pragma once

#include "pipeline/data/device_scene.h"
#include "pipeline/data/frame_buffers.h"
#include "pipeline/rules/alpha_items.h"
#include "pipeline/rules/clip.h"
#include "pipeline/rules/depth_plane.h"
#include "pipeline/rules/raster_rules.h"
#include "pipeline/rules/visbuffer_blocks.h"

namespace rast {
namespace triangle_setup {

struct SetupCommon {
  DView<DrawGPU> draws;
  DView<uint32_t> drawTriStart;
  DView<DrawIndex> triDraw;  // DeviceScene::triDraw (empty: search drawTriStart)
  DView<uint32_t> indices;
  DView<float4> clip;
  DView<SnapVert> snap;
  uint32_t numDraws;
  Viewport vp;
  float gx, gy;
  int32_t cullBack;  // CullFaces: 0 none, 1 every back face, 2 those of single-sided materials
  // Scenes with MASK or BLEND materials: each draw's AlphaDraw (DeviceScene::alphaDraws),
  // whose triangles the setup marks (markAlphaClass); unread otherwise.
  DView<AlphaDraw> alphaDraws;
  int32_t alphaScene = 0;

  // Drawn-vertex indices of drawn triangle t's corners, its front winding,
  // whether its back faces are culled, and its alpha class.
  KOKKOS_INLINE_FUNCTION void corners(uint32_t t, uint32_t (&vi)[3], bool& frontCCW, bool& cull, int32_t& cls) const {
    const uint32_t d = drawOf(triDraw, drawTriStart, numDraws, t);
    const DrawGPU& dr = draws(d);
    const uint32_t base = 3 * (dr.srcTri + (t - dr.dstTri));
    for (int k = 0; k < 3; ++k) vi[k] = dr.dstVertex + indices(base + k);
    frontCCW = dr.mirrored == 0;
    cull = cullBack == 1 || (cullBack == 2 && dr.singleSided);
    cls = alphaScene ? alphaDraws(d).cls : int32_t(kAlphaOpaque);
  }

  // Clips drawn triangle t (corners vi) into a convex polygon and sets up its
  // fan; calls emit(rt) for each raster triangle that survives, in order, and
  // returns how many did. kDepth: the pieces' depths are wanted (not when
  // only counting), from the drawn triangle's plane (depth_plane.h).
  template <bool kDepth, class Emit>
  KOKKOS_INLINE_FUNCTION uint32_t clipAndSetUp(uint32_t t, const uint32_t (&vi)[3], bool frontCCW, bool cull, int32_t cls,
                                               Emit&& emit) const {
    ClipVert poly[kMaxClipVerts];
    for (int k = 0; k < 3; ++k) poly[k].p = clip(vi[k]);
    poly[0].b1 = 0.0f; poly[0].b2 = 0.0f;
    poly[1].b1 = 1.0f; poly[1].b2 = 0.0f;
    poly[2].b1 = 0.0f; poly[2].b2 = 1.0f;
    const DepthPlane plane = kDepth ? DepthPlane(poly[0].p, poly[1].p, poly[2].p, vp) : DepthPlane();
    const int n = clipTriangle(poly, gx, gy);
    uint32_t k = 0;
    for (int i = 0; i + 2 < n; ++i) {
      RasterTri rt;
      if (!setupTriangle(poly[0], poly[i + 1], poly[i + 2], vp, cull, frontCCW, t, rt)) continue;
      if (kDepth) depthFromPlane(rt, plane);
      if (cls != kAlphaOpaque) markAlphaClass(rt, cls);
      emit(rt);
      ++k;
    }
    return k;
  }
};

constexpr uint32_t kSetupChunk = 256;       // drawn triangles per team
constexpr uint32_t kClippedFlag = 0x80000000u;  // in a scratch count: pieces written later

// Raster triangles drawn triangle t yields, from the vertex stage's snapped
// corners; `clipped` says the triangle crosses a clipping plane, and then the
// count comes from clipping it. The corners' codes classify the triangle as
// clipTriangle would (non-finite or wholly outside one plane: nothing; inside
// every plane: untouched), and an untouched triangle gets the bits
// setupTriangle would give it, so the result equals clipping every triangle.
// `out` holds the raster triangle when the triangle is unclipped and yields one;
// kDepth: with its corner depths on the unsnapped plane (depth_plane.h), which
// only the write pass needs. clipCounts: the count pass's counts of clipped
// triangles, or null to clip and count here. blocks (unless null): the
// visbuffer's work items of the raster triangles (with clipCounts, a clipped
// triangle's come from clipBlocks, the count pass's).
// kCount: a clipped triangle is clipped here to be counted (false: it is
// flagged clipped and left to the caller, with 0). blendItems (unless null,
// and only without clipCounts): the BLEND class's work items of the raster
// triangles (alpha_items.h).
// Forced inline: with the GPU's setup also built for host backends (for
// TestHooks::gpuSetupOnHostTeam), GCC stopped inlining it into the host
// functors, and tiny's host setup took 40% longer (22 against 15.5 ms).
template <bool kDepth, bool kCount = true>
KOKKOS_FORCEINLINE_FUNCTION uint32_t setupOne(const SetupCommon& c, uint32_t t, RasterTri& out, bool& clipped,
                                         const uint8_t* clipCounts, uint32_t* blocks = nullptr,
                                         const uint32_t* clipBlocks = nullptr, uint32_t* blendItems = nullptr) {
  uint32_t vi[3];
  bool frontCCW, cull;
  int32_t cls;
  c.corners(t, vi, frontCCW, cull, cls);
  SnapVert s[3];
  uint32_t any = 0, all = ~0u;
  for (int k = 0; k < 3; ++k) {
    s[k] = c.snap(vi[k]);
    const uint32_t code = snapCode(s[k]);
    any |= code;
    all &= code;
  }
  clipped = false;
  if (blocks) *blocks = 0;
  if (blendItems) *blendItems = 0;
  if (any == 0) {  // the common case: inside every plane, w > 0
    putCorner(out, 0, s[0], 0.0f, 0.0f);
    putCorner(out, 1, s[1], 1.0f, 0.0f);
    putCorner(out, 2, s[2], 0.0f, 1.0f);
    if (kDepth) {
      const int32_t rx[3] = {fineResidual(s[0].x), fineResidual(s[1].x), fineResidual(s[2].x)};
      const int32_t ry[3] = {fineResidual(s[0].y), fineResidual(s[1].y), fineResidual(s[2].y)};
      depthAtSnappedCorners(out, rx, ry);
    }
    if (!finishTriangle(c.vp, cull, frontCCW, t, out)) return 0;
    if (cls != kAlphaOpaque) markAlphaClass(out, cls);
    uint32_t bw;
    if (blocks) *blocks = visBlocksOf(out, bw);
    if (blendItems) *blendItems = classItems(out, c.vp, kAlphaBlend);
    return 1;
  }
  if ((any & kCodeNonFinite) || (all & 0x3fu)) return 0;  // not drawable, or wholly outside one plane
  if (!(any & 0x3fu)) return 0;                           // inside every plane, but some w <= 0
  // Beyond a side of the viewport: nothing to clip. Seen from inside a model,
  // most triangles that cross the near plane are (engine_inside: 990 of 1,000
  // left no piece), and clipping each, twice, by one thread while its team
  // waits was most of that view's setup.
  if (outsideViewportSide(c.clip(vi[0]), c.clip(vi[1]), c.clip(vi[2]))) return 0;
  clipped = true;
  if (!kCount) return 0;
  if (clipCounts) {
    if (blocks && clipBlocks) *blocks = clipBlocks[t];
    return clipCounts[t];
  }
  return c.clipAndSetUp<false>(t, vi, frontCCW, cull, cls, [&](const RasterTri& piece) {
    uint32_t bw;
    if (blocks) *blocks += visBlocksOf(piece, bw);
    if (blendItems) *blendItems += classItems(piece, c.vp, kAlphaBlend);
  });
}

KOKKOS_INLINE_FUNCTION uint32_t chunkLength(uint32_t chunk, uint32_t n) {
  const uint32_t first = chunk * kSetupChunk;
  return n - first < kSetupChunk ? n - first : kSetupChunk;
}

}  // namespace triangle_setup
}  // namespace rast
