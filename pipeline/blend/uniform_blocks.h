// The listed methods' uniform blocks on GPUs (docs/transparency.md, "On a
// GPU: a team a block"). Under the glTF shading a block whose every listed
// triangle covers all its samples (or, with the other half of its quad, all
// but those across their shared edge), in front of its nearest opaque depth,
// with one colour (unlit, untextured layers: FragShade::constantColourOf)
// composites the same fragments in the same order at every sample: the
// team form's walk would repeat one "over" 64 times a sample. Before the
// resolve a thread a block decides that and computes the composite once
// (rast::blend::uniform_blocks); a thread a pixel then writes it over the
// opaque colour (rast::blend::uniform_pixels), and the team only counts the
// block's fragments (PeelTeam::resolveBlock). Kernels of their own and not
// steps of the team: classifying inside the team (a team reduction of the
// opaque depth and a barrier a block) made the H200's resolve slower, and
// the team kernel's occupancy (its scratch) is too low for a pass that only
// streams the film (docs/journal/transparency-2026-11.md). The CPU's block
// walk decides the same a sample at a time (peel_block.h, PeelBlocks::uniform).
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

  // The edges of e that leave out some sample of the pixels [x0, x1] x
  // [y0, y1] (the block's within the frame), bit k for edge k: an edge
  // function is linear, so its least value over them is at a corner pixel
  // (exact integers, Edges::inside's test).
  KOKKOS_INLINE_FUNCTION static uint32_t openEdges(const Edges& e, const int32_t x0, const int32_t y0,
                                                   const int32_t x1, const int32_t y1, const SamplePattern& sp) {
    uint32_t open = 0;
    for (int s = 0; s < sp.count; ++s)
      for (int c = 0; c < 4; ++c) {
        const int32_t X = (c & 1) ? x1 : x0, Y = (c & 2) ? y1 : y0;
        for (int k = 0; k < 3; ++k)
          if (!(e.sample(k, X, Y, sp.ox[s], sp.oy[s]) + e.bias[k] > 0)) open |= 1u << k;
      }
    return open;
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
    const int32_t x1 = x0 + (1 << kItemShift) <= p.width ? x0 + (1 << kItemShift) - 1 : p.width - 1;
    const int32_t y1 = y0 + (1 << kItemShift) <= p.height ? y0 + (1 << kItemShift) - 1 : p.height - 1;
    const int S = fs.sp.count;
    // The nearest opaque depth of the block's samples in the frame: a row's
    // eight loads at once (unrolled), a row after another.
    uint32_t nearest = ~0u;
    for (int32_t Y = y0; Y <= y1; ++Y)
      for (int s = 0; s < S; ++s) {
        const int64_t row = (int64_t(Y) * p.width + x0) * S + s;
#if defined(__CUDA_ARCH__) || defined(__HIP_DEVICE_COMPILE__)
#pragma unroll
#endif
        for (int32_t dx = 0; dx < (1 << kItemShift); ++dx) {
          const uint32_t o = x0 + dx <= x1 ? p.opaque(row + int64_t(dx) * S) : ~0u;
          nearest = o < nearest ? o : nearest;
        }
      }
    // Each triangle: one colour, in front (exact and sorted: its whole depth
    // range, depthBounds; weighted: parallel to the image, one depth and so
    // one weight, kept in lo), every sample taken in but across at most one
    // edge (2 bits of `open`: that edge + 1, else 0); its key in the walk's
    // order. The arrays are the thread's stack, which the loads of a
    // multiprocessor's threads share its L1 with: kept small.
    uint64_t key[kUniformMax];
    float4 col[kUniformMax];
    float lo[kUniformMax], hi[kUniformMax];
    uint32_t open = 0;
    // No early exit: without one the compiler overlaps several triangles'
    // loads (latency, not arithmetic, is this kernel's cost).
    bool ok = true;
#if defined(__CUDA_ARCH__) || defined(__HIP_DEVICE_COMPILE__)
#pragma unroll 4
#endif
    for (uint32_t j = 0; j < n; ++j) {
      const uint32_t i = p.tileTris(begin + j);
      const bool one = fs.template constantColourOf<kFam, kFeat>(i, col[j]);
      const RasterTri& t = fs.sc.tris(i);
      const uint32_t o = openEdges(Edges(t), x0, y0, x1, y1, fs.sp);
      ok = ok && one && !(o & (o - 1));  // two edges or three open: a corner of it in the block
      open |= (o ? (o == 1u ? 1u : o == 2u ? 2u : 3u) : 0u) << (2 * j);
      if (p.weighted) {
        const DepthTerms dz(t);
        // DepthTerms::at with d1 = d2 = 0 is z0 + (+-0): z0 itself where z0 > 0.
        lo[j] = clamp01(dz.z0);
        ok = ok && dz.d1 == 0.0f && dz.d2 == 0.0f && dz.z0 > 0.0f && floatBits(lo[j]) < nearest;
        key[j] = i;  // raster-index order, in which the sums add
      } else {
        const DepthBounds b = depthBounds(t);
        ok = ok && blockInFront(b.lo, b.hi, nearest);
        lo[j] = b.lo;
        hi[j] = b.hi;
        // The team's keys (PeelTeam::resolveBlock), the list's place r in
        // raster-index order replaced by the raster index: the same order.
        key[j] = p.sorted ? (p.sortedKeyOf(i) & ~uint64_t(0xffffffffu)) | uint64_t(0xffffffffu - i)
                          : uint64_t(orderBits(b.lo)) << 32 | i;
      }
    }
    if (!ok) return;
    uint8_t ord[kUniformMax];
    for (uint32_t j = 0; j < n; ++j) {
      uint32_t k = j;
      for (; k > 0 && key[ord[k - 1]] > key[j]; --k) ord[k] = ord[k - 1];
      ord[k] = uint8_t(j);
    }
    // The walk of one sample in that order (the team's pixelInOrder and
    // pixelWeighted), once, a unit at a time: a triangle, or a triangle
    // open across one edge and the next in the order, open across the same
    // edge reversed (sharedEdge), of the same colour (weighted: depth): a
    // quad's two halves. Each sample then lies inside the pair's four outer
    // edges and the shared one gives it to exactly one half: one fragment of
    // the pair's colour at every sample, in the pair's place. (Halves apart
    // in the order: another triangle's fragment would fall between them at
    // some samples.) exact: one order at every sample only where each
    // unit's range (a pair's: their union) ends before the next begins (the
    // team's orderEntries).
    float3 acc{0.0f, 0.0f, 0.0f};
    float T = 1.0f;
    float4 w{0.0f, 0.0f, 0.0f, 0.0f};
    float reveal = 1.0f, before = 0.0f;
    uint32_t units = 0;
    for (uint32_t t = 0; t < n; ++units) {
      const uint32_t j = ord[t], oj = (open >> (2 * j)) & 3u;
      float l = lo[j], h = p.weighted ? 0.0f : hi[j];
      if (oj) {
        if (t + 1 >= n) return;
        const uint32_t q = ord[t + 1], oq = (open >> (2 * q)) & 3u;
        const int32_t e = oq ? sharedEdge(fs.sc.tris(p.tileTris(begin + j)), fs.sc.tris(p.tileTris(begin + q))) : -1;
        if (e < 0 || uint32_t(e / 3) + 1 != oj || uint32_t(e % 3) + 1 != oq) return;
        if (floatBits(col[j].x) != floatBits(col[q].x) || floatBits(col[j].y) != floatBits(col[q].y) ||
            floatBits(col[j].z) != floatBits(col[q].z) || floatBits(col[j].w) != floatBits(col[q].w))
          return;
        if (p.weighted) {
          if (floatBits(lo[j]) != floatBits(lo[q])) return;
        } else {  // (no NaN: blockInFront)
          l = lo[q] < l ? lo[q] : l;
          h = hi[q] > h ? hi[q] : h;
        }
        t += 2;
      } else {
        t += 1;
      }
      if (p.weighted) {
        if (col[j].w > 0.0f) weightedTerms(w, reveal, col[j], fs.weight(l));
        continue;
      }
      if (!p.sorted && units > 0 && !(before < l)) return;  // ranges overlap (or NaN)
      before = h;
      if (T > 0.0f && col[j].w > 0.0f) over(acc, T, col[j]);
    }
    if (p.weighted) weightedFront(w, reveal, acc, T);
    p.blockComposite(block) = float4{acc.x, acc.y, acc.z, T};
    p.blockFrags(block) = units;
  }
};

// A uniform block's pixel: the block's composite over the opaque colour at
// every sample (the team's arithmetic: Peel::filmSample).
template <int kFam, int kFeat>
struct UniformPixels {
  Peel<kFam, kFeat> peel;
  KOKKOS_INLINE_FUNCTION void operator()(const int64_t px) const {
    const Peel<kFam, kFeat>& p = peel;
    const int32_t X = int32_t(px % p.width), Y = int32_t(px / p.width);
    const int64_t block = int64_t(Y >> kItemShift) * p.blocksX + (X >> kItemShift);
    if (p.blockFrags(block) == kUniformWalk) return;
    const float4 o = p.blockComposite(block);
    const int S = p.fs.sp.count;
    float4 sum{0.0f, 0.0f, 0.0f, 0.0f};
    for (int s = 0; s < S; ++s) p.filmSample(px, s, S, float3{o.x, o.y, o.z}, o.w, sum);
  }
};

}  // namespace blending
}  // namespace rast
