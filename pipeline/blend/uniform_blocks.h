// The listed methods' uniform blocks on GPUs (docs/transparency.md, "On a
// GPU: a team a block"). Under the glTF shading a block whose every listed
// triangle covers all its samples, in front of its nearest opaque depth,
// with one colour (unlit, untextured layers: FragShade::constantColour)
// composites the same fragments in the same order at every sample: the
// team form's walk would repeat one "over" 64 times a sample. Before the
// resolve a thread a block decides that and computes the composite once
// (rast::blend::uniform_blocks); the team then writes it over the opaque
// colour and leaves the list alone (PeelTeam::resolveBlock). Its own kernel
// and not a step of the team: classifying inside the team (a team reduction
// of the opaque depth and a barrier a block) made the H200's resolve slower
// (docs/journal/transparency-2026-11.md). The CPU's block walk decides the
// same a sample at a time (peel_block.h, PeelBlocks::uniform).
#pragma once

#include "pipeline/blend/peel.h"

namespace rast {
namespace blending {

// Longest list composited once (its keys and colours on the thread's stack).
constexpr uint32_t kUniformMax = 16;
// blockFrags' value for a block the team walks.
constexpr uint32_t kUniformWalk = ~0u;

// The resolves that read the uniform blocks: the glTF shading's instances
// that can have a constant colour.
template <int kFam, int kFeat>
constexpr bool uniformBlocksFor() {
  return kFam == kFragPbr && kFeat != shading::kPbrAny;
}

template <int kFam, int kFeat>
struct UniformBlocks {
  using P = Peel<kFam, kFeat>;
  P peel;  // writes its blockComposite (acc, T: weighted's after weightedFront) and
           // blockFrags (the fragments a sample; kUniformWalk where the team walks the list)

  // Whether the triangle of edges e takes in sample (ox, oy) of every pixel
  // of the block at (x0, y0): an edge function is linear, so its least value
  // over the pixels is at a corner pixel (exact integers, Edges::inside).
  KOKKOS_INLINE_FUNCTION static bool covers(const Edges& e, const int32_t x0, const int32_t y0, const int32_t ox,
                                            const int32_t oy) {
    bool in = true;
    for (int c = 0; c < 4; ++c) {
      const int32_t X = x0 + ((c & 1) ? 7 : 0), Y = y0 + ((c & 2) ? 7 : 0);
      in = in && e.inside(e.sample(0, X, Y, ox, oy), e.sample(1, X, Y, ox, oy), e.sample(2, X, Y, ox, oy));
    }
    return in;
  }

  KOKKOS_INLINE_FUNCTION void operator()(const int64_t block) const {
    peel.blockFrags(block) = kUniformWalk;
    const P& p = peel;
    const FragShade& fs = p.fs;
    const bool listed = p.totals(kBlendListed) <= p.tileCapacity;  // else the frame is drawn again
    if (!listed) return;
    const uint32_t end = p.tileEnd(block), n = p.tileCount(block), begin = end - n;
    if (n > kUniformMax) return;
    const int32_t x0 = int32_t(block % p.blocksX) << kItemShift, y0 = int32_t(block / p.blocksX) << kItemShift;
    const int S = fs.sp.count;
    // The nearest opaque depth of the block's samples in the frame.
    uint32_t nearest = ~0u;
    for (int32_t Y = y0; Y < y0 + (1 << kItemShift) && Y < p.height; ++Y)
      for (int32_t X = x0; X < x0 + (1 << kItemShift) && X < p.width; ++X)
        for (int s = 0; s < S; ++s) {
          const uint32_t o = p.opaque((int64_t(Y) * p.width + X) * S + s);
          nearest = o < nearest ? o : nearest;
        }
    // Each triangle: one colour, every sample covered and in front (exact
    // and sorted: its whole depth range, depthBounds; weighted: parallel to
    // the image, one depth and so one weight); its key in the walk's order.
    uint64_t key[kUniformMax];
    float4 col[kUniformMax];
    float lo[kUniformMax], hi[kUniformMax], z[kUniformMax];
    typename P::PeelCache cache;
    for (uint32_t j = 0; j < n; ++j) {
      const uint32_t i = p.tileTris(begin + j);
      if (!p.constantOf(i, cache, col[j])) return;
      const RasterTri& tri = fs.sc.tris(i);
      const Edges e(tri);
      for (int s = 0; s < S; ++s)
        if (!covers(e, x0, y0, fs.sp.ox[s], fs.sp.oy[s])) return;
      if (p.weighted) {
        const DepthTerms dz(tri);
        // DepthTerms::at with d1 = d2 = 0 is z0 + (+-0): z0 itself where z0 > 0.
        if (!(dz.d1 == 0.0f && dz.d2 == 0.0f && dz.z0 > 0.0f)) return;
        z[j] = clamp01(dz.z0);
        if (!(floatBits(z[j]) < nearest)) return;
        key[j] = i;  // raster-index order, in which the sums add
        continue;
      }
      const DepthBounds b = depthBounds(tri);
      if (!blockInFront(b.lo, b.hi, nearest)) return;
      lo[j] = b.lo;
      hi[j] = b.hi;
      // The team's keys (PeelTeam::resolveBlock), the list's place r in
      // raster-index order replaced by the raster index: the same order.
      key[j] = p.sorted ? (p.sortedKeyOf(i) & ~uint64_t(0xffffffffu)) | uint64_t(0xffffffffu - i)
                        : uint64_t(orderBits(b.lo)) << 32 | i;
    }
    uint32_t ord[kUniformMax];
    for (uint32_t j = 0; j < n; ++j) {
      uint32_t k = j;
      for (; k > 0 && key[ord[k - 1]] > key[j]; --k) ord[k] = ord[k - 1];
      ord[k] = j;
    }
    // exact: one order at every sample only where each range ends before
    // the next begins (the team's orderEntries); a quad's two halves never
    // both cover a sample, so never both the whole block.
    if (!p.weighted && !p.sorted)
      for (uint32_t t = 0; t + 1 < n; ++t)
        if (!(hi[ord[t]] < lo[ord[t + 1]])) return;
    // The team's walk of one sample (pixelInOrder, pixelWeighted), once.
    float3 acc{0.0f, 0.0f, 0.0f};
    float T = 1.0f;
    if (p.weighted) {
      float4 w{0.0f, 0.0f, 0.0f, 0.0f};
      float reveal = 1.0f;
      for (uint32_t t = 0; t < n; ++t)
        if (col[ord[t]].w > 0.0f) weightedTerms(w, reveal, col[ord[t]], fs.weight(z[ord[t]]));
      weightedFront(w, reveal, acc, T);
    } else {
      for (uint32_t t = 0; t < n; ++t)
        if (T > 0.0f && col[ord[t]].w > 0.0f) over(acc, T, col[ord[t]]);
    }
    p.blockComposite(block) = float4{acc.x, acc.y, acc.z, T};
    p.blockFrags(block) = n;
  }
};

}  // namespace blending
}  // namespace rast
