// The listed methods' resolve on CPUs, a block a thread (docs/transparency.md,
// "On a CPU: a block's triangles in order"). Where the triangles of a
// block's list keep one order at every sample of the block
//   sorted:   always (a triangle's key is its draw's);
//   exact:    where their depth ranges do not overlap: the whole
//             triangles' (depthBounds), else over the block
//             (blockDepthRange), both widened past the depth's rounding;
//   weighted: the list's raster-index order, in which its sums add,
// each triangle in turn is walked over the block's 64 pixels and its
// fragments in front of the opaque depth are shaded together (Lambert under
// the headlight: the span shader's vector loop over them all, one set-up a
// triangle and sample; where they are half the block or more, over all 64
// pixels, masked, with no gathering into lanes) and composited as found: no keys, no insertion, no
// second walk, and a triangle's set-up once for the block instead of once a
// row and pass. Under the glTF shading, where every triangle of the list
// covers the block in front of the opaque depth with one colour (unlit
// layers; weighted: parallel to the image, one weight), the block's pixels
// composite the same colours: once for all 64 (uniform). Other blocks
// (overlapping ranges, lists longer than kBlockOrderMax) take peel.h's rows.
// The same fragments are composited in the same order with the same
// arithmetic as there: the same bits
// (tests/pipeline/test_transparency.cpp, TestHooks::peelRows). GPUs take
// peel_team.h's team form, which walks in order the same way a pixel a thread.
#pragma once

#include "pipeline/blend/peel.h"

namespace rast {
namespace blending {

// Longest list walked in order (its set-up lives on the thread's stack).
constexpr uint32_t kBlockOrderMax = 64;
static_assert(kItemShift == 3, "the block loops below take 8x8 blocks: q = 8 y + x");

// One triangle's edges and depth terms at one sample over a block: the edge
// values at the sample of the block's corner pixel and their steps a pixel
// along x and y, in double (integers below 2^50, as SpanConsts: exact), the
// top-left rule's biases; DepthTerms' fields.
struct BlockEdges {
  double e[3], a[3], b[3], bias[3];
  float z0, d1, d2, ia;
};
// Its fragments over the block's 64 pixels (q = 8 y + x from the corner):
// Edges::inside, DepthTerms::at (float(double(e)) rounds as float(e) does:
// the same depth) and LESS against the opaque depth's bits opq (0 for a
// pixel outside the frame: never passed); pass[q] 1 for a fragment, its
// pixel's count cnt[q] raised, z[q] its depth. Plain loops, also built for
// AVX-512 and AVX2 (cpu_clones.h): the same results, 8 or 16 pixels at once.
RAST_CPU_CLONES void blockFragmentsWide(const BlockEdges& k, const uint32_t* __restrict__ opq,
                                        uint32_t* __restrict__ cnt, int32_t* __restrict__ pass,
                                        float* __restrict__ z) {
  for (int q = 0; q < 64; ++q) {
    const double x = double(q & 7), y = double(q >> 3);
    const double s0 = k.e[0] + k.a[0] * x + k.b[0] * y, s1 = k.e[1] + k.a[1] * x + k.b[1] * y,
                 s2 = k.e[2] + k.a[2] * x + k.b[2] * y;
    const float l1 = float(s2) * k.ia, l2 = float(s0) * k.ia;
    const float zz = clamp01(k.z0 + (l1 * k.d1 + l2 * k.d2));
    const int32_t in = (s0 + k.bias[0] > 0.0) & (s1 + k.bias[1] > 0.0) & (s2 + k.bias[2] > 0.0);
    const int32_t p = in & (floatBits(zz) < opq[q] ? 1 : 0);
    z[q] = zz;
    pass[q] = p;
    cnt[q] += uint32_t(p);
  }
}

// One pixel q of a block composited with colour (r, g, b) and alpha above
// 0 where f (a fragment): exact's and sorted's "over" (frag_shade.h's over()
// a channel at a time: acc + rgb * (T * alpha), T * (1 - alpha)), weighted's
// sums (weightedTerms', with weight w). Forced inline into the block loops
// below, which vectorize over them.
KOKKOS_FORCEINLINE_FUNCTION void overPixel(const int q, const bool f, const float r, const float g, const float b,
                                           const float alpha, float* __restrict__ aR, float* __restrict__ aG,
                                           float* __restrict__ aB, float* __restrict__ T) {
  const float t = T[q], tw = t * alpha;
  aR[q] = f ? aR[q] + r * tw : aR[q];
  aG[q] = f ? aG[q] + g * tw : aG[q];
  aB[q] = f ? aB[q] + b * tw : aB[q];
  T[q] = f ? t * (1.0f - alpha) : t;
}
KOKKOS_FORCEINLINE_FUNCTION void weightedPixel(const int q, const bool f, const float r, const float g, const float b,
                                               const float alpha, const float w, float* __restrict__ wR,
                                               float* __restrict__ wG, float* __restrict__ wB, float* __restrict__ wA,
                                               float* __restrict__ reveal) {
  wR[q] = f ? wR[q] + r * alpha * w : wR[q];
  wG[q] = f ? wG[q] + g * alpha * w : wG[q];
  wB[q] = f ? wB[q] + b * alpha * w : wB[q];
  wA[q] = f ? wA[q] + alpha * w : wA[q];
  reveal[q] = f ? reveal[q] * (1.0f - alpha) : reveal[q];
}

// weightedFront for a block's pixels: what lies in front (aR, aG, aB) and
// the transmittance T from weighted's sums and revealage.
RAST_CPU_CLONES void weightedFrontBlockWide(const float* __restrict__ wR, const float* __restrict__ wG,
                                            const float* __restrict__ wB, const float* __restrict__ wA,
                                            const float* __restrict__ reveal, float* __restrict__ aR,
                                            float* __restrict__ aG, float* __restrict__ aB, float* __restrict__ T) {
  for (int q = 0; q < 64; ++q) {
    const bool some = wA[q] > 0.0f;
    const float t = some ? reveal[q] : 1.0f, k = (1.0f - t) / wA[q];
    aR[q] = some ? wR[q] * k : 0.0f;
    aG[q] = some ? wG[q] * k : 0.0f;
    aB[q] = some ? wB[q] * k : 0.0f;
    T[q] = t;
  }
}
// Peel::filmValue for a block's pixels at a sample of S: what lies in front
// (aR, aG, aB; transmittance T) over the film's opaque colour (hR..hA:
// overOpaque), with several samples added to their sum (sR..sA) and
// averaged; the value (fR..fA) is the film's at the last sample.
RAST_CPU_CLONES void filmBlockWide(const float* __restrict__ aR, const float* __restrict__ aG,
                                   const float* __restrict__ aB, const float* __restrict__ T,
                                   const float* __restrict__ hR, const float* __restrict__ hG,
                                   const float* __restrict__ hB, const float* __restrict__ hA, float* __restrict__ sR,
                                   float* __restrict__ sG, float* __restrict__ sB, float* __restrict__ sA, const int S,
                                   float* __restrict__ fR, float* __restrict__ fG, float* __restrict__ fB,
                                   float* __restrict__ fA) {
  if (S == 1) {
    for (int q = 0; q < 64; ++q) {
      fR[q] = aR[q] + T[q] * hR[q];
      fG[q] = aG[q] + T[q] * hG[q];
      fB[q] = aB[q] + T[q] * hB[q];
      fA[q] = 1.0f - T[q] * (1.0f - hA[q]);
    }
    return;
  }
  const float inv = 1.0f / float(S);
  for (int q = 0; q < 64; ++q) {
    sR[q] = sR[q] + (aR[q] + T[q] * hR[q]);
    sG[q] = sG[q] + (aG[q] + T[q] * hG[q]);
    sB[q] = sB[q] + (aB[q] + T[q] * hB[q]);
    sA[q] = sA[q] + (1.0f - T[q] * (1.0f - hA[q]));
    fR[q] = sR[q] * inv;
    fG[q] = sG[q] * inv;
    fB[q] = sB[q] * inv;
    fA[q] = sA[q] * inv;
  }
}

// Whether the triangle of edges k takes in the sample of all 64 pixels: an
// edge function is linear, so its least value over them is at a corner pixel
// (the same sums as blockFragmentsWide's, exact integers in double).
KOKKOS_INLINE_FUNCTION bool blockCovered(const BlockEdges& k) {
  bool in = true;
  for (int i = 0; i < 3; ++i)
    for (int c = 0; c < 4; ++c) {
      const double x = (c & 1) ? 7.0 : 0.0, y = (c & 2) ? 7.0 : 0.0;
      in = in & (k.e[i] + k.a[i] * x + k.b[i] * y + k.bias[i] > 0.0);
    }
  return in;
}

// "over" for a block's pixels at once, a pixel whose colour's alpha cA[q] is
// above 0 composited (the others, alpha 0 or NaN or not a fragment,
// unchanged). Plain loops, also built for AVX-512 and AVX2.
RAST_CPU_CLONES void overBlockWide(float* __restrict__ aR, float* __restrict__ aG, float* __restrict__ aB,
                                   float* __restrict__ T, const float* __restrict__ cR, const float* __restrict__ cG,
                                   const float* __restrict__ cB, const float* __restrict__ cA) {
  for (int q = 0; q < 64; ++q) overPixel(q, cA[q] > 0.0f, cR[q], cG[q], cB[q], cA[q], aR, aG, aB, T);
}

// A triangle of constant colour under Lambert's headlight (Peel::litSetup:
// span constants k, base colour, alpha above 0) lit at the block's 64 pixels
// at once (X, Y: theirs) by the span shader's lane loop, and composited
// where pass[q]: exact and sorted "over" where the pixel is not yet opaque;
// weighted's sums (the weights FragShade::weightOf of depth z[q], near and
// far planes zn, zf, one array a sum). A block that a layer covers has 64
// fragments: this leaves out the gathering of the fragments into lanes and
// the scatter of their colours back (peel_block.h's walk takes it when half
// the block's pixels or more have one). Each pixel's lighting is its own
// lane's: the same bits.
RAST_CPU_CLONES void litOverBlockWide(const shading::SpanConsts& k, const int32_t* __restrict__ X,
                                      const int32_t* __restrict__ Y, const int32_t* __restrict__ pass,
                                      const float4 base, const float alpha, float* __restrict__ aR,
                                      float* __restrict__ aG, float* __restrict__ aB, float* __restrict__ T) {
  alignas(64) float b0[64], b1[64], b2[64], nx[64], ny[64], nz[64], diffuse[64];
  shading::spanLightingLanes(k, 64, X, Y, b0, b1, b2, nx, ny, nz, diffuse);
  for (int q = 0; q < 64; ++q) {
    const float d = diffuse[q];  // Peel::litLanesAt's colour
    overPixel(q, (pass[q] != 0) & (T[q] > 0.0f), base.x * d + 0.0f, base.y * d + 0.0f, base.z * d + 0.0f, alpha, aR,
              aG, aB, T);
  }
}
RAST_CPU_CLONES void litWeightedBlockWide(const shading::SpanConsts& k, const int32_t* __restrict__ X,
                                          const int32_t* __restrict__ Y, const int32_t* __restrict__ pass,
                                          const float* __restrict__ z, const float zn, const float zf,
                                          const float4 base, const float alpha, float* __restrict__ wR,
                                          float* __restrict__ wG, float* __restrict__ wB, float* __restrict__ wA,
                                          float* __restrict__ reveal) {
  alignas(64) float b0[64], b1[64], b2[64], nx[64], ny[64], nz[64], diffuse[64];
  shading::spanLightingLanes(k, 64, X, Y, b0, b1, b2, nx, ny, nz, diffuse);
  for (int q = 0; q < 64; ++q) {
    const float d = diffuse[q];
    weightedPixel(q, pass[q] != 0, base.x * d + 0.0f, base.y * d + 0.0f, base.z * d + 0.0f, alpha,
                  FragShade::weightOf(z[q], zn, zf), wR, wG, wB, wA, reveal);
  }
}
// A triangle whose every fragment has colour c (FragShade::constantColour;
// alpha c.w above 0) composited where pass[q], as above: no shading at all.
RAST_CPU_CLONES void constOverBlockWide(const int32_t* __restrict__ pass, const float4 c, float* __restrict__ aR,
                                        float* __restrict__ aG, float* __restrict__ aB, float* __restrict__ T) {
  for (int q = 0; q < 64; ++q) overPixel(q, (pass[q] != 0) & (T[q] > 0.0f), c.x, c.y, c.z, c.w, aR, aG, aB, T);
}
RAST_CPU_CLONES void constWeightedBlockWide(const int32_t* __restrict__ pass, const float* __restrict__ z,
                                            const float zn, const float zf, const float4 c, float* __restrict__ wR,
                                            float* __restrict__ wG, float* __restrict__ wB, float* __restrict__ wA,
                                            float* __restrict__ reveal) {
  for (int q = 0; q < 64; ++q)
    weightedPixel(q, pass[q] != 0, c.x, c.y, c.z, c.w, FragShade::weightOf(z[q], zn, zf), wR, wG, wB, wA, reveal);
}

// A block's film pixels encoded as sRGB bytes with opaque alpha
// (encodeFilm's light, not straight: packSrgb8Packed's table lookups,
// encodeSrgb8Packed, a channel at a time), in a loop that AVX2's gathers
// vectorize (cpu_clones.h: no AVX-512 variant for table lookups).
RAST_CPU_CLONES_GATHER void encodeBlockWide(const float* __restrict__ r, const float* __restrict__ g,
                                            const float* __restrict__ b, const float* __restrict__ a,
                                            const uint32_t* __restrict__ table, uint32_t* __restrict__ out) {
  for (int q = 0; q < 64; ++q)
    out[q] = encodeSrgb8Packed(r[q], table) | encodeSrgb8Packed(g[q], table) << 8 |
             encodeSrgb8Packed(b[q], table) << 16 | unorm8(a[q]) << 24;
}

template <int kFam, int kFeat>
struct PeelBlocks {
  static constexpr int32_t kSide = 1 << kItemShift, kPixels = kSide * kSide;
  using P = Peel<kFam, kFeat>;
  P peel;
  bool rowsOnly;  // TestHooks::peelRows

  int64_t blocks;
  // Blocks a work item takes: neighbours, which mostly list the same
  // triangles, whose shading lookups (the cache) it then sets up once.
  static constexpr int64_t kRun = 4;
  static int64_t itemsFor(int64_t blocks) { return (blocks + kRun - 1) / kRun; }

  // Work item: blocks run * kRun onwards (kPeelRun == kSide: a CPU's).
  void operator()(const int64_t run, uint64_t& frags) const {
    // Dependent on the template: never instantiated for a GPU, whose kPeelRun is 1.
    static_assert(kFam >= 0 && kPeelRun == kSide, "a CPU thread takes blocks");
    typename P::PeelCache cache;
    for (int64_t block = run * kRun; block < (run + 1) * kRun && block < blocks; ++block) {
      uint32_t ord[kBlockOrderMax], idx[kBlockOrderMax];
      float lo[kBlockOrderMax], hi[kBlockOrderMax];  // exact's depth ranges
      uint32_t n = 0;
      if (rowsOnly || !order(block, idx, ord, n, lo, hi))
        peel(block, frags);
      else
        walk(block, idx, ord, n, lo, hi, cache, frags);
    }
  }

  // The block's list (idx) and the order its triangles keep at every
  // sample (ord: places in idx, first composited first); false where there
  // is none, or the list is empty, too long or not read (the frame is drawn
  // again with more room).
  bool order(const int64_t block, uint32_t (&idx)[kBlockOrderMax], uint32_t (&ord)[kBlockOrderMax], uint32_t& n,
             float (&lo)[kBlockOrderMax], float (&hi)[kBlockOrderMax]) const {
    const P& p = peel;
    if (!(p.totals(kBlendListed) <= p.tileCapacity)) return false;
    n = p.tileCount(block);
    if (n == 0 || n > kBlockOrderMax) return false;
    const uint32_t begin = p.listBegin(block, n);
    const int32_t x0 = int32_t(block % p.blocksX) << kItemShift, y0 = int32_t(block / p.blocksX) << kItemShift;
    uint64_t key[kBlockOrderMax];
    for (uint32_t j = 0; j < n; ++j) {
      const uint32_t i = p.tileTris(begin + j);
      idx[j] = i;
      if (p.weighted) {
        key[j] = j;  // tiles_sort put the list in raster-index order
      } else if (p.sorted) {
        key[j] = p.sortedKeyOf(i);  // unique: it ends in the raster index
      } else {
        // exact: first the triangles' whole depth ranges (depthBounds),
        // which cost three comparisons; where they do not order the list,
        // their ranges over the block (below).
        const DepthBounds z = depthBounds(p.fs.sc.tris(i));
        lo[j] = z.lo;
        hi[j] = z.hi;
        key[j] = uint64_t(orderBits(lo[j])) << 32 | j;
      }
    }
    sortKeys(key, n, ord);
    if (p.weighted || p.sorted || inOrder(idx, ord, n, lo, hi)) return true;
    for (uint32_t j = 0; j < n; ++j) {
      const RasterTri& t = p.fs.sc.tris(idx[j]);
      blockDepthRange(Edges(t), DepthTerms(t), x0, y0, lo[j], hi[j]);
      key[j] = uint64_t(orderBits(lo[j])) << 32 | j;
    }
    sortKeys(key, n, ord);
    return inOrder(idx, ord, n, lo, hi);
  }
  // ord: the places of n keys in ascending order (insertion sort: lists are
  // short and mostly in order).
  KOKKOS_INLINE_FUNCTION static void sortKeys(const uint64_t (&key)[kBlockOrderMax], const uint32_t n,
                                              uint32_t (&ord)[kBlockOrderMax]) {
    for (uint32_t j = 0; j < n; ++j) {
      uint32_t k = j;
      for (; k > 0 && key[ord[k - 1]] > key[j]; --k) ord[k] = ord[k - 1];
      ord[k] = j;
    }
  }
  // exact: whether the depth ranges [lo, hi] in the order ord keep one
  // order at every sample: each triangle's range before the next's, but for
  // a quad's two halves (edgeNeighbours: never both at one sample), whose
  // ranges overlap and which then take their union's place. The ranges are
  // the whole triangles' or the block's: either bounds every depth the
  // block's samples take, so an order they give is the same.
  bool inOrder(const uint32_t (&idx)[kBlockOrderMax], const uint32_t (&ord)[kBlockOrderMax], const uint32_t n,
               const float (&lo)[kBlockOrderMax], const float (&hi)[kBlockOrderMax]) const {
    const P& p = peel;
    float before = 0.0f;
    for (uint32_t t = 0; t < n;) {
      float last = hi[ord[t]];
      uint32_t u = t + 1;
      if (u < n && !(last < lo[ord[u]]) &&
          edgeNeighbours(p.fs.sc.tris(idx[ord[t]]), p.fs.sc.tris(idx[ord[u]]))) {
        last = hi[ord[u]] > last || hi[ord[u]] != hi[ord[u]] ? hi[ord[u]] : last;  // (NaN kept: fails below)
        ++u;
      }
      if (t > 0 && !(before < lo[ord[t]])) return false;  // ranges overlap (or NaN): peeled
      before = last;
      t = u;
    }
    return true;
  }

  // blockInFront for the triangle of list place j: exact's range from
  // order() (the whole triangle's or the block's), else, and for sorted,
  // its range over the block.
  bool inFront(const Edges& e, const DepthTerms& dz, const int32_t x0, const int32_t y0,
               const float (&lo)[kBlockOrderMax], const float (&hi)[kBlockOrderMax], const uint32_t j,
               const uint32_t nearestOpaque) const {
    if (!peel.sorted && blockInFront(lo[j], hi[j], nearestOpaque)) return true;
    float l, h;
    blockDepthRange(e, dz, x0, y0, l, h);
    return blockInFront(l, h, nearestOpaque);
  }

  // One triangle's BlockEdges at sample (ox, oy) over the block at (x0, y0).
  KOKKOS_INLINE_FUNCTION static BlockEdges blockEdges(const Edges& e, const DepthTerms& dz, const int32_t x0,
                                                      const int32_t y0, const int32_t ox, const int32_t oy) {
    BlockEdges be;
    for (int k = 0; k < 3; ++k) {
      be.e[k] = double(e.sample(k, x0, y0, ox, oy));
      be.a[k] = double(e.A[k]);
      be.b[k] = double(e.B[k]);
      be.bias[k] = double(e.bias[k]);
    }
    be.z0 = dz.z0;
    be.d1 = dz.d1;
    be.d2 = dz.d2;
    be.ia = dz.ia;
    return be;
  }

  // Under the glTF shading, sample s of a block in order: where each
  // triangle of the list covers the block (blockCovered; the tile lists
  // leave out the triangles that miss it) with one colour (Peel::constantOf:
  // unlit, untextured)
  //   exact and sorted: in front of its nearest opaque depth (inFront);
  //   weighted: parallel to the image (one depth at every sample: the
  //             weight's) in front of that depth,
  // every pixel composites the same fragments in the same order from
  // acc = 0, T = 1 (weighted: from zero sums). Their "over" (weighted's
  // sums) is then computed once, with walk()'s arithmetic (constOverBlockWide's
  // and constWeightedBlockWide's, a pixel), and written to the block's pixels
  // (aR, aG, aB, T; wR, wG, wB, wA, reveal; the counts cnt); false, nothing
  // written, where the block is not so. zn, zf: the camera's near and far
  // planes (weighted's weights).
  struct Sums {
    float *aR, *aG, *aB, *T, *wR, *wG, *wB, *wA, *reveal;
  };
  bool uniform(const int32_t x0, const int32_t y0, const uint32_t (&idx)[kBlockOrderMax],
               const uint32_t (&ord)[kBlockOrderMax], const uint32_t n, const float (&lo)[kBlockOrderMax],
               const float (&hi)[kBlockOrderMax], const int s, const uint32_t nearestOpaque, const float zn,
               const float zf, typename P::PeelCache& cache, const Sums& out, uint32_t* cnt) const {
    const P& p = peel;
    const FragShade& fs = p.fs;
    const bool weighted = p.weighted != 0;
    float4 col[kBlockOrderMax];
    float z[kBlockOrderMax];  // weighted: the triangle's one depth
    for (uint32_t t = 0; t < n; ++t) {
      const uint32_t i = idx[ord[t]];
      // The colour first: a lit or textured layer leaves before its edges
      // are set up (the walk sets them up again).
      if (!p.constantOf(i, cache, col[t])) return false;
      const RasterTri& tri = fs.sc.tris(i);
      const Edges e(tri);
      const DepthTerms dz(tri);
      const BlockEdges be = blockEdges(e, dz, x0, y0, fs.sp.ox[s], fs.sp.oy[s]);
      if (!blockCovered(be)) return false;
      if (weighted) {
        // DepthTerms::at with d1 = d2 = 0 is z0 + (+-0): z0 itself where z0 > 0.
        if (!(dz.d1 == 0.0f && dz.d2 == 0.0f && dz.z0 > 0.0f)) return false;
        z[t] = clamp01(dz.z0);
        if (!(floatBits(z[t]) < nearestOpaque)) return false;
      } else if (!inFront(e, dz, x0, y0, lo, hi, ord[t], nearestOpaque)) {
        return false;
      }
    }
    alignas(64) float r[1] = {0.0f}, g[1] = {0.0f}, b[1] = {0.0f}, a[1] = {0.0f}, tr[1] = {1.0f};
    uint32_t c = 0;
    for (uint32_t t = 0; t < n; ++t) {
      ++c;
      const float4 k = col[t];
      if (weighted)
        weightedPixel(0, k.w > 0.0f, k.x, k.y, k.z, k.w, FragShade::weightOf(z[t], zn, zf), r, g, b, a, tr);
      else
        overPixel(0, (tr[0] > 0.0f) & (k.w > 0.0f), k.x, k.y, k.z, k.w, r, g, b, tr);
    }
    for (int q = 0; q < kPixels; ++q) cnt[q] = c;
    if (weighted)
      for (int q = 0; q < kPixels; ++q) {
        out.wR[q] = r[0];
        out.wG[q] = g[0];
        out.wB[q] = b[0];
        out.wA[q] = a[0];
        out.reveal[q] = tr[0];
      }
    else
      for (int q = 0; q < kPixels; ++q) {
        out.aR[q] = r[0];
        out.aG[q] = g[0];
        out.aB[q] = b[0];
        out.T[q] = tr[0];
      }
    return true;
  }

  // The block's samples, each triangle of the list in order over its pixels.
  void walk(const int64_t block, const uint32_t (&idx)[kBlockOrderMax], const uint32_t (&ord)[kBlockOrderMax],
            const uint32_t listed, const float (&lo)[kBlockOrderMax], const float (&hi)[kBlockOrderMax],
            typename P::PeelCache& cache, uint64_t& frags) const {
    const P& p = peel;
    const FragShade& fs = p.fs;
    const bool weighted = p.weighted != 0;
    const int32_t x0 = int32_t(block % p.blocksX) << kItemShift, y0 = int32_t(block / p.blocksX) << kItemShift;
    const int32_t cols = p.width - x0 < kSide ? p.width - x0 : kSide;
    const int32_t rows = p.height - y0 < kSide ? p.height - y0 : kSide;
    const int S = fs.sp.count;
    const float zn = fs.sh.p.frame(0).camera.znear, zf = fs.sh.p.frame(0).camera.zfar;  // weighted's weights
    alignas(64) float sR[kPixels], sG[kPixels], sB[kPixels], sA[kPixels];  // several samples' sum
    alignas(64) int32_t Xb[kPixels], Yb[kPixels];  // the block's pixels
    for (int q = 0; q < kPixels; ++q) {
      sR[q] = sG[q] = sB[q] = sA[q] = 0.0f;
      Xb[q] = x0 + (q & (kSide - 1));
      Yb[q] = y0 + (q >> kItemShift);
    }
    for (int s = 0; s < S; ++s) {
      const int32_t ox = fs.sp.ox[s], oy = fs.sp.oy[s];
      uint32_t n = listed;  // 0 where uniform() composited the block
      // What lies in front, a channel an array (overBlockWide), and the
      // transmittance; weighted's sums.
      alignas(64) float aR[kPixels], aG[kPixels], aB[kPixels], T[kPixels];
      alignas(64) float wR[kPixels], wG[kPixels], wB[kPixels], wA[kPixels], reveal[kPixels];
      alignas(64) uint32_t cnt[kPixels], opq[kPixels];
      for (int q = 0; q < kPixels; ++q) {
        cnt[q] = 0;
        opq[q] = 0;  // no pixel: no fragment
      }
      if (weighted)
        for (int q = 0; q < kPixels; ++q) {
          wR[q] = wG[q] = wB[q] = wA[q] = 0.0f;
          reveal[q] = 1.0f;
        }
      else
        for (int q = 0; q < kPixels; ++q) {
          aR[q] = aG[q] = aB[q] = 0.0f;
          T[q] = 1.0f;
        }
      for (int32_t yy = 0; yy < rows; ++yy)
        for (int32_t xx = 0; xx < cols; ++xx)
          opq[yy * kSide + xx] = p.opaque((int64_t(y0 + yy) * p.width + x0 + xx) * S + s);
      uint32_t nearestOpaque = opq[0];  // 0 where a pixel lies outside the frame
      for (int q = 1; q < kPixels; ++q) nearestOpaque = opq[q] < nearestOpaque ? opq[q] : nearestOpaque;
      if constexpr (P::kConstant)
        if (uniform(x0, y0, idx, ord, n, lo, hi, s, nearestOpaque, zn, zf, cache,
                    Sums{aR, aG, aB, T, wR, wG, wB, wA, reveal}, cnt))
          n = 0;
      for (uint32_t t = 0; t < n; ++t) {
        const uint32_t i = idx[ord[t]];
        const RasterTri& tri = fs.sc.tris(i);
        const Edges e(tri);
        const DepthTerms dz(tri);
        const BlockEdges be = blockEdges(e, dz, x0, y0, ox, oy);
        alignas(64) int32_t pass[kPixels];
        alignas(64) float z[kPixels];
        bool covered = !weighted && blockCovered(be);
        if (covered) covered = inFront(e, dz, x0, y0, lo, hi, ord[t], nearestOpaque);
        if (covered) {
          // Every pixel a fragment (exact and sorted read no fragment's depth).
          for (int q = 0; q < kPixels; ++q) {
            pass[q] = 1;
            cnt[q] += 1u;
          }
        } else {
          blockFragmentsWide(be, opq, cnt, pass, z);
        }
        // The fragments to shade: of pixels not yet opaque (weighted: all).
        int m = 0;
        for (int q = 0; q < kPixels; ++q) m += pass[q] & (weighted || T[q] > 0.0f ? 1 : 0);
        if (m == 0) continue;
        if constexpr (P::kLanes) {
          // Half the block or more: lit and composited at every pixel at once.
          shading::SpanConsts c;
          float4 base;
          float alpha;
          if (p.lambertLanes && 2 * m >= kPixels && p.litSetup(i, s, cache, c, base, alpha)) {
            if (!(alpha > 0.0f)) continue;  // no fragment
            if (weighted)
              litWeightedBlockWide(c, Xb, Yb, pass, z, zn, zf, base, alpha, wR, wG, wB, wA, reveal);
            else
              litOverBlockWide(c, Xb, Yb, pass, base, alpha, aR, aG, aB, T);
            continue;
          }
        }
        if constexpr (P::kConstant) {  // the glTF shading's unlit layers: one colour, nothing shaded
          float4 col;
          if (p.constantOf(i, cache, col)) {
            if (!(col.w > 0.0f)) continue;  // no fragment
            if (weighted)
              constWeightedBlockWide(pass, z, zn, zf, col, wR, wG, wB, wA, reveal);
            else
              constOverBlockWide(pass, col, aR, aG, aB, T);
            continue;
          }
        }
        int lane[kPixels];
        m = 0;
        for (int q = 0; q < kPixels; ++q) {
          lane[m] = q;
          m += pass[q] & (weighted || T[q] > 0.0f ? 1 : 0);
        }
        alignas(64) int32_t X[kPixels], Y[kPixels];
        for (int k = 0; k < m; ++k) {
          X[k] = x0 + (lane[k] & (kSide - 1));
          Y[k] = y0 + (lane[k] >> kItemShift);
        }
        float4 col[kPixels];
        bool lit = false;
        if constexpr (P::kLanes) lit = p.lambertLanes && m > 1 && p.litLanesAt(i, s, X, Y, m, cache, col);
        if (!lit) {
          const int c = p.prepared(i, cache);
          for (int k = 0; k < m; ++k)
            col[k] = fs.template shadeAt<kFam, kFeat>(X[k], Y[k], s, e.sample(0, X[k], Y[k], ox, oy),
                                                      e.sample(1, X[k], Y[k], ox, oy), e.sample(2, X[k], Y[k], ox, oy),
                                                      cache.a[c], cache.tf[c], cache.pt[c]);
        }
        if (weighted) {
          // The fragments' weights first, in a loop of their own (it vectorizes).
          float wt[kPixels];
          for (int k = 0; k < m; ++k) wt[k] = FragShade::weightOf(z[lane[k]], zn, zf);
          for (int k = 0; k < m; ++k) {
            if (!(col[k].w > 0.0f)) continue;  // alpha 0 (or NaN): no fragment
            const int q = lane[k];
            float4 wq{wR[q], wG[q], wB[q], wA[q]};
            weightedTerms(wq, reveal[q], col[k], wt[k]);
            wR[q] = wq.x;
            wG[q] = wq.y;
            wB[q] = wq.z;
            wA[q] = wq.w;
          }
          continue;
        }
        alignas(64) float cR[kPixels], cG[kPixels], cB[kPixels], cA[kPixels];
        if (m < kPixels)  // else lane[k] == k: every pixel has a fragment
          for (int q = 0; q < kPixels; ++q) cR[q] = cG[q] = cB[q] = cA[q] = 0.0f;  // no fragment
        for (int k = 0; k < m; ++k) {
          const int q = lane[k];
          cR[q] = col[k].x;
          cG[q] = col[k].y;
          cB[q] = col[k].z;
          cA[q] = col[k].w;
        }
        overBlockWide(aR, aG, aB, T, cR, cG, cB, cA);  // alpha 0 (or NaN): no fragment
      }
      // The statistics (Peel::count's, a block at once).
      uint64_t blockFrags = 0;
      uint32_t deepest = 0;
      for (int q = 0; q < kPixels; ++q) {  // (0 outside the frame)
        blockFrags += cnt[q];
        deepest = cnt[q] > deepest ? cnt[q] : deepest;
      }
      p.count(blockFrags, deepest, frags);
      // The film (Peel::filmValue's arithmetic: filmBlockWide); at the last
      // sample, where the resolve encodes, the block's bytes in one loop.
      if (weighted) weightedFrontBlockWide(wR, wG, wB, wA, reveal, aR, aG, aB, T);
      alignas(64) float hR[kPixels], hG[kPixels], hB[kPixels], hA[kPixels];
      alignas(64) float fR[kPixels], fG[kPixels], fB[kPixels], fA[kPixels];
      if (rows < kSide || cols < kSide)
        for (int q = 0; q < kPixels; ++q) hR[q] = hG[q] = hB[q] = hA[q] = 0.0f;  // pixels outside the frame
      for (int32_t yy = 0; yy < rows; ++yy) {
        const float4* h = &p.hdr(int64_t(y0 + yy) * p.width + x0);
        for (int32_t xx = 0; xx < cols; ++xx) {
          const int q = yy * kSide + xx;
          hR[q] = h[xx].x;
          hG[q] = h[xx].y;
          hB[q] = h[xx].z;
          hA[q] = h[xx].w;
        }
      }
      filmBlockWide(aR, aG, aB, T, hR, hG, hB, hA, sR, sG, sB, sA, S, fR, fG, fB, fA);
      if (s + 1 == S)  // (Peel::filmValue writes the film at the last sample)
        for (int32_t yy = 0; yy < rows; ++yy) {
          float4* h = &p.hdr(int64_t(y0 + yy) * p.width + x0);
          for (int32_t xx = 0; xx < cols; ++xx) {
            const int q = yy * kSide + xx;
            h[xx] = float4{fR[q], fG[q], fB[q], fA[q]};
          }
        }
      if (s + 1 == S && p.encode) {
        alignas(64) uint32_t bytes[kPixels];
        if (p.raw || p.straight)
          for (int q = 0; q < kPixels; ++q)
            bytes[q] = encodeFilm(float4{fR[q], fG[q], fB[q], fA[q]}, p.raw != 0, p.straight != 0, p.packed);
        else
          encodeBlockWide(fR, fG, fB, fA, p.packed.data(), bytes);
        for (int32_t yy = 0; yy < rows; ++yy)
          for (int32_t xx = 0; xx < cols; ++xx) p.color(int64_t(y0 + yy) * p.width + x0 + xx) = bytes[yy * kSide + xx];
      }
    }
  }
};

}  // namespace blending
}  // namespace rast
