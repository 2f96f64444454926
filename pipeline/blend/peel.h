// The listed methods' resolve, a pixel (GPU) or a block's row (CPU) a thread
// (docs/transparency.md, "exact and sorted: tile lists, peeled in
// registers"): per sample its block's list walked with the raster methods'
// edge and depth arithmetic, LESS against the opaque depth; the K smallest
// keys above the last pass's largest kept in a small sorted array and
// composited front to back; a sample with more than K fragments, still not
// opaque, walks the list again (depth peeling, in registers). weighted walks
// the list once, summing (rowWeighted). Apart from blend_tiles.cpp, which
// builds the lists and launches this, and peel_team.h, the GPU's team form,
// which falls back on it for long lists.
#pragma once

#include "pipeline/blend/frag_shade.h"
#include "base/color.h"
#include "pipeline/cpu/span_math.h"

namespace rast {
namespace blending {

// Keys kept per pass and sample. On a GPU the array must stay in registers:
// the insertion below indexes it only with compile-time indices (an unrolled
// chain of compare-and-swap), 8 keys = 16 registers a thread on top of the
// fragment shader's; 16 would halve the passes over deep lists at the cost
// of occupancy (to be measured on the H100). A CPU lane holds 16.
constexpr int kPeelK = kOnDevice ? 8 : 16;
// Pixels a CPU thread resolves together along a row (one block's row: they
// share the list, and each triangle's edges and depth terms are set up once
// for all of them); a GPU thread resolves one pixel, a warp half a block (one
// list: the same loop and loads for its 32 threads). A CPU thread takes a
// whole block, one lookup cache of kPeelK triangles for its 8 rows: the
// pixels of a row composite the same K triangles one after the other.
constexpr int32_t kPeelRun = kOnDevice ? 1 : (1 << kItemShift);
constexpr int kPeelCache = kOnDevice ? 1 : kPeelK;
constexpr uint64_t kNoKey = ~uint64_t(0);

// A triangle's depth over the samples of the 8x8 block at (x0, y0), bounded:
// the depth plane (DepthTerms::plane) at the corners of the block's pixels
// (every sample lies within them), in double from the exact edge values,
// widened past the float evaluation's rounding (each of its terms rounds
// within 2^-21 of the sum of their magnitudes), clamped as DepthTerms::at
// clamps. NaN terms give NaN bounds, which order nothing.
KOKKOS_INLINE_FUNCTION void blockDepthRange(const Edges& e, const DepthTerms& dz, int32_t x0, int32_t y0, float& lo,
                                            float& hi) {
  const double c0 = double(e.eval(0, x0, y0)), c2 = double(e.eval(2, x0, y0));
  double mn = 0.0, mx = 0.0, mag = 0.0;
  for (int c = 0; c < 4; ++c) {
    const double fx = (c & 1) ? 7.5 : -0.5, fy = (c & 2) ? 7.5 : -0.5;  // pixels from (x0, y0)
    const double e0 = c0 + double(e.A[0]) * fx + double(e.B[0]) * fy, e2 = c2 + double(e.A[2]) * fx + double(e.B[2]) * fy;
    const double t1 = e2 * double(dz.ia) * double(dz.d1), t2 = e0 * double(dz.ia) * double(dz.d2);
    const double z = double(dz.z0) + (t1 + t2);
    const double m = ::fabs(double(dz.z0)) + ::fabs(t1) + ::fabs(t2);
    mn = c == 0 || z < mn ? z : mn;
    mx = c == 0 || z > mx ? z : mx;
    mag = m > mag ? m : mag;
  }
  const double w = mag * 0x1p-20;
  const double l = mn - w, h = mx + w;
  lo = l == l ? float(l < 0.0 ? 0.0 : (l > 1.0 ? 1.0 : l)) : l;
  hi = h == h ? float(h < 0.0 ? 0.0 : (h > 1.0 ? 1.0 : h)) : h;
}

// Whether a triangle's depth at every sample of a block, within a range
// [lo, hi] that bounds it (blockDepthRange, depthBounds) and above 0 (not
// -0, whose bits fail LESS), lies in front of the nearest opaque depth
// (bits) nearest: then every covered sample passes LESS.
KOKKOS_INLINE_FUNCTION bool blockInFront(float lo, float hi, uint32_t nearest) {
  return lo > 0.0f && hi == hi && floatBits(hi) < nearest;
}

// Whether raster triangles s and t (counter-clockwise, finishTriangle) share
// an edge, a to b in one and b to a in the other: their interiors then lie
// on either side of it, and on it the top-left rule gives a sample to one of
// them (the two edge functions are each other's negation, and their biases
// differ), so no sample has a fragment of both: a quad's two halves.
// sharedEdge: 3 i + k for s's edge i (vertex i to i + 1, Edges' numbering)
// and t's edge k, else -1.
KOKKOS_INLINE_FUNCTION int32_t sharedEdge(const RasterTri& s, const RasterTri& t) {
  for (int i = 0; i < 3; ++i) {
    const int i1 = i == 2 ? 0 : i + 1;
    for (int k = 0; k < 3; ++k) {
      const int k1 = k == 2 ? 0 : k + 1;
      if (s.x[i] == t.x[k1] && s.y[i] == t.y[k1] && s.x[i1] == t.x[k] && s.y[i1] == t.y[k]) return 3 * i + k;
    }
  }
  return -1;
}
KOKKOS_INLINE_FUNCTION bool edgeNeighbours(const RasterTri& s, const RasterTri& t) { return sharedEdge(s, t) >= 0; }

// Where the list of `block`, n entries long, starts in the lists' buffer:
// at block x stride in the strided layout, else n before its end
// (BlendBuffers::listStride).
KOKKOS_INLINE_FUNCTION uint64_t listBegin(const DView<uint32_t>& tileEnd, const uint32_t stride, const int64_t block,
                                          const uint32_t n) {
  return stride ? uint64_t(block) * stride : tileEnd(block) - n;
}

// The resolve for the frame's fragment family and features (frag_shade.h).
template <int kFam, int kFeat>
struct Peel {
  using PeelCache = FragCacheOf<kPeelCache, kFam>;
  FragShade fs;
  DView<float4> hdr;
  DView<uint32_t> tileCount, tileEnd, tileTris, opaque;
  DView<uint64_t> totals;
  uint64_t tileCapacity;
  int32_t width, height, blocksX, sorted;
  int32_t lambertLanes = 0;  // Lambert under the headlight (compositeLanes)
  int32_t weighted = 0;      // weighted: rowWeighted's sums instead of the peel
  // The frame's RGBA8 colour and the sRGB encoder's table, written where the
  // resolve folds the film's encoding in (BlendPlan::encode, raw, straight).
  DView<uint32_t> color, packed;
  int32_t encode = 0, raw = 0, straight = 0;
  // The team form under the glTF shading: per block the composite of a
  // uniform block and its fragments a sample, and the blocks the team walks
  // (uniform_blocks.h).
  DView<float4> blockComposite;
  DView<uint32_t> blockFrags, walkedBlocks;
  uint32_t stride = 0;  // the lists' layout (BlendBuffers::listStride)
  static constexpr bool kEncodes = familyEncodes(kFam);

  // Sample s of S of pixel px: what lies in front (acc, transmittance T)
  // over the opaque colour in the film; with several samples their running
  // sum, averaged into the film at the last. Where the resolve encodes, the
  // pixel's bytes too (encodeFilm: postEncode's; kEncodes). Every form of the resolve ends a sample here
  // (the block walk with filmValue's arithmetic).
  RAST_GPU_INLINE void filmSample(const int64_t px, const int s, const int S, const float3 acc, const float T,
                                  float4& sum) const {
    float4 c;
    if (filmValue(px, s, S, acc, T, sum, c) && kEncodes && encode)
      color(px) = encodeFilm(c, raw != 0, straight != 0, packed);
  }
  // The same but for the bytes: true and the pixel's colour c where it is
  // final (the last sample), which the caller encodes. (peel_block.h's walk
  // takes a block's pixels at once with this arithmetic: filmBlockWide.)
  RAST_GPU_INLINE bool filmValue(const int64_t px, const int s, const int S, const float3 acc, const float T,
                                 float4& sum, float4& c) const {
    const float4 out = overOpaque(acc, T, hdr(px));
    if (S == 1) {
      c = out;
    } else {
      sum = sum + out;
      if (s + 1 < S) return false;
      c = sum * (1.0f / float(S));
    }
    hdr(px) = c;
    return true;
  }

  // Where the list of `block`, n entries long, starts in tileTris (< 2^32: its capacity).
  RAST_GPU_INLINE uint32_t listBegin(const int64_t block, const uint32_t n) const {
    return uint32_t(blending::listBegin(tileEnd, stride, block, n));
  }

  // sorted's key: its triangle's, whatever the sample.
  RAST_GPU_INLINE uint64_t sortedKeyOf(uint32_t i) const {
    const AlphaScene& sc = fs.sc;
    return fs.sortedKey(drawOf(sc.triDraw, sc.drawTriStart, sc.numDraws, sc.tris(i).prim), i);
  }

  // Keeps the kPeelK smallest keys seen, sorted, `held` of them so far
  // (key is below best[kPeelK - 1]). On a GPU each step keeps the smaller of
  // the two and carries the larger on (compile-time indices: registers); a
  // CPU shifts the larger ones up from the end, as far as the key goes.
  RAST_GPU_INLINE static void insert(uint64_t (&best)[kPeelK], uint64_t key, uint32_t held) {
    if (kOnDevice) {
#if defined(__CUDA_ARCH__) || defined(__HIP_DEVICE_COMPILE__)
#pragma unroll
#endif
      for (int k = 0; k < kPeelK; ++k) {
        const uint64_t lo = key < best[k] ? key : best[k];
        key = key < best[k] ? best[k] : key;
        best[k] = lo;
      }
      return;
    }
    int k = held < uint32_t(kPeelK) ? int(held) : kPeelK - 1;
    for (; k > 0 && best[k - 1] > key; --k) best[k] = best[k - 1];
    best[k] = key;
  }

  // Work items: on a GPU one pixel, numbered 64 a block (block-major); on a
  // CPU one block.
  RAST_FLATTEN void operator()(const int64_t item, uint64_t& frags) const {
    const int64_t block = kPeelRun == 1 ? item >> (2 * kItemShift) : item;
    const int32_t bx = int32_t(block % blocksX), by = int32_t(block / blocksX);
    // A list that overflowed its capacity is not read: the frame is drawn again.
    const bool listed = totals(kBlendListed) <= tileCapacity;
    const uint32_t n = listed ? tileCount(block) : 0u, begin = listed ? listBegin(block, n) : 0u, end = begin + n;
    PeelCache cache;
    if (kPeelRun == 1) {
      const int32_t p = int32_t(item & ((1 << (2 * kItemShift)) - 1));
      const int32_t X = (bx << kItemShift) + (p & ((1 << kItemShift) - 1)), Y = (by << kItemShift) + (p >> kItemShift);
      if (X < width && Y < height) row(X, Y, 1, begin, end, cache, frags);
      return;
    }
    const int32_t x0 = bx << kItemShift, run = x0 + kPeelRun < width ? kPeelRun : width - x0;
    for (int32_t Y = by << kItemShift; Y < ((by + 1) << kItemShift) && Y < height; ++Y)
      row(x0, Y, run, begin, end, cache, frags);
  }

  // A CPU, Lambert under the headlight without vertex colours: the k-th
  // fragments of a run's pixels, when they are one triangle's (layers over
  // a block: mostly), lit together by the span shader's vector loop
  // (pipeline/cpu/span_math.h, spanLightingLanesWide: Shade::shadeFragment's
  // expressions in its order, the same bits), each pixel still composited
  // front to back and stopped where it is opaque. Others one at a time.
  static constexpr bool kLanes = !kOnDevice && kFam == kFragLit && kFeat == 0;
  // The colours of triangle tri's fragments at sample s of pixels x0 +
  // lane[j] of row Y (j < m), lit together where the triangle is untextured
  // and the scene has no vertex colours (alpha 0 or NaN: all zero, no
  // fragment); false where it is not (the caller shades them one at a time).
  KOKKOS_INLINE_FUNCTION bool litLanes(const uint32_t tri, const int32_t x0, const int32_t Y, const int s,
                                       const int (&lane)[kPeelRun], const int m, PeelCache& cache,
                                       float4 (&out)[kPeelRun]) const {
    alignas(32) int32_t X[kPeelRun], Ys[kPeelRun];
    for (int j = 0; j < m; ++j) {
      X[j] = x0 + lane[j];
      Ys[j] = Y;
    }
    return litLanesAt(tri, s, X, Ys, m, cache, out);
  }
  // The same for pixels (X[j], Y[j]), j < m <= kCap (peel_block.h: a block's).
  template <int kCap>
  KOKKOS_INLINE_FUNCTION bool litLanesAt(const uint32_t tri, const int s, const int32_t (&X)[kCap],
                                         const int32_t (&Ys)[kCap], const int m, PeelCache& cache,
                                         float4 (&out)[kCap]) const {
    shading::SpanConsts c;
    float4 base;
    float alpha;
    if (!litSetup(tri, s, cache, c, base, alpha)) return false;
    if (!(alpha > 0.0f)) {
      for (int j = 0; j < m; ++j) out[j] = float4{0.0f, 0.0f, 0.0f, 0.0f};
      return true;
    }
    alignas(32) float b0[kCap], b1[kCap], b2[kCap], nx[kCap], ny[kCap], nz[kCap], diffuse[kCap];
    shading::spanLightingLanesWide(c, m, X, Ys, b0, b1, b2, nx, ny, nz, diffuse);
    for (int j = 0; j < m; ++j) {  // Shade::litLight's colour (spec is 0 in Lambert)
      const float3 rgb = float3{base.x, base.y, base.z} * diffuse[j] + float3{0.0f, 0.0f, 0.0f};
      out[j] = float4{rgb.x, rgb.y, rgb.z, alpha};
    }
    return true;
  }
  // litLanesAt's set-up of triangle tri at sample s: its span constants (the
  // edge values at the sample of pixel (X, Y), Edges::atSample, exact
  // integers in double; the headlight's lighting; set only for alpha above
  // 0), its base colour and its alpha (AlphaScene::alphaFrom of a constant
  // alpha); false where its colour varies (textures, vertex colours).
  KOKKOS_INLINE_FUNCTION bool litSetup(const uint32_t tri, const int s, PeelCache& cache, shading::SpanConsts& c,
                                       float4& base, float& alpha) const {
    const int e = prepared(tri, cache);
    const AlphaTri& a = cache.a[e];
    const TriFrag& f = cache.tf[e];
    if (a.textured || fs.sc.hasColor || f.textured) return false;
    alpha = cleanAlpha(a.alpha);
    base = f.baseColor;
    if (alpha > 0.0f)
      fillSpanConsts(c, f, fs.sp.ox[s], fs.sp.oy[s], fs.sh.p.perspective != 0, f.eye, fs.sh.p.ambient,
                     1.0f - fs.sh.p.ambient);
    return true;
  }
  // Triangle tri's cache entry with its lookups prepared, for a caller that
  // does not step its edge values (FragCacheOf::at's, which it forgets: they
  // may be another triangle's, whose entry this was).
  KOKKOS_INLINE_FUNCTION int prepared(const uint32_t tri, PeelCache& cache) const {
    const int e = cache.slot(tri);
    if (cache.a[e].index != tri) fs.sc.prepare(tri, cache.a[e]);
    fs.template use<kFam>(tri, cache.tf[e], cache.pt[e]);
    cache.evS[e] = -1;
    return e;
  }
  // A CPU, the glTF shading: triangles whose fragments all have one colour
  // (FragShade::constantColour) are composited without shading (peel_block.h).
  static constexpr bool kConstant = !kOnDevice && kFam == kFragPbr;
  // Triangle tri's constant colour and alpha (w), its lookups prepared in
  // the cache; false where they vary.
  KOKKOS_INLINE_FUNCTION bool constantOf(const uint32_t tri, PeelCache& cache, float4& c) const {
    const int e = prepared(tri, cache);
    return fs.template constantColour<kFam, kFeat>(cache.a[e], cache.pt[e], c);
  }
  KOKKOS_INLINE_FUNCTION void compositeLanes(const int32_t x0, const int32_t Y, const int s, const int32_t run,
                                             const uint64_t (&best)[kPeelRun][kPeelK], const uint32_t (&cnt)[kPeelRun],
                                             const bool (&more)[kPeelRun], float3 (&acc)[kPeelRun],
                                             float (&T)[kPeelRun], PeelCache& cache) const {
    for (int k = 0; k < kPeelK; ++k) {
      int32_t m = 0;
      int lane[kPeelRun];
      uint32_t tri = ~0u;
      bool same = true;
      for (int r = 0; r < kPeelRun && r < run; ++r) {
        if (!more[r] || !(k < int(cnt[r])) || !(T[r] > 0.0f)) continue;
        const uint32_t idx = keyIndex(best[r][k], sorted != 0);
        same = same && (m == 0 || idx == tri);
        tri = idx;
        lane[m++] = r;
      }
      if (m == 0) break;
      if (same && m > 1) {
        float4 col[kPeelRun];
        if (litLanes(tri, x0, Y, s, lane, m, cache, col)) {
          for (int j = 0; j < m; ++j)
            if (col[j].w > 0.0f) over(acc[lane[j]], T[lane[j]], col[j]);  // alpha 0 (or NaN): no fragment
          continue;
        }
      }
      for (int j = 0; j < m; ++j) {
        const int r = lane[j];
        const float4 c = cache.template at<kFeat>(fs, keyIndex(best[r][k], sorted != 0), x0 + r, Y, s);
        if (c.w > 0.0f) over(acc[r], T[r], c);  // alpha 0 (or NaN): no fragment
      }
    }
  }

  // Pixels x0 .. x0 + run - 1 of row Y, whose block's list is [begin, end).
  RAST_GPU_INLINE void row(const int32_t x0, const int32_t Y, const int32_t run, const uint32_t begin,
                                  const uint32_t end, PeelCache& cache, uint64_t& frags) const {
    if (weighted) {
      rowWeighted(x0, Y, run, begin, end, cache, frags);
      return;
    }
    const int S = fs.sp.count;
    float4 sum[kPeelRun];
    for (int r = 0; r < kPeelRun; ++r) sum[r] = float4{0.0f, 0.0f, 0.0f, 0.0f};
    for (int s = 0; s < S; ++s) {
      uint64_t best[kPeelRun][kPeelK];
      uint64_t after[kPeelRun];
      uint32_t cnt[kPeelRun], opq[kPeelRun];
      float3 acc[kPeelRun];
      float T[kPeelRun];
      bool more[kPeelRun];
      for (int r = 0; r < kPeelRun && r < run; ++r) {
        after[r] = 0;  // every key is above 0
        acc[r] = float3{0.0f, 0.0f, 0.0f};
        T[r] = 1.0f;
        more[r] = end > begin;
        opq[r] = opaque((int64_t(Y) * width + x0 + r) * S + s);
      }
      for (bool first = true;; first = false) {
        bool any = false;
        for (int r = 0; r < kPeelRun && r < run; ++r) any = any || more[r];
        if (!any) break;
        for (int r = 0; r < kPeelRun && r < run; ++r) {
          cnt[r] = 0;
          for (int k = 0; k < kPeelK; ++k) best[r][k] = kNoKey;
        }
        // Last entry first: a list is roughly in submission order, and
        // transparent draws are mostly submitted back to front, so that the
        // nearest keys come first and a key rarely moves the ones held (on a
        // CPU, an insertion shifts the larger keys up).
        for (uint32_t j = end; j-- > begin;) {
          const uint32_t i = tileTris(j);
          const RasterTri& t = fs.sc.tris(i);
          const Edges e(t);
          const DepthTerms dz(t);
          const int32_t ox = fs.sp.ox[s], oy = fs.sp.oy[s];
          const uint64_t triKey = sorted ? sortedKeyOf(i) : 0;
          // The edge values at the run's first pixel's sample, then a step of
          // A_i a pixel: exact integers, the values forItemSamples takes.
          int64_t s0 = e.sample(0, x0, Y, ox, oy), s1 = e.sample(1, x0, Y, ox, oy), s2 = e.sample(2, x0, Y, ox, oy);
          for (int r = 0; r < kPeelRun && r < run; ++r, s0 += e.A[0], s1 += e.A[1], s2 += e.A[2]) {
            if (!more[r]) continue;
            if (!e.inside(s0, s1, s2)) continue;
            const float z = dz.at(s0, s2);
            if (!(floatBits(z) < opq[r])) continue;  // LESS against the opaque depth
            const uint64_t key = sorted ? triKey : visKey(z, i);
            if (key <= after[r]) continue;  // composited by an earlier pass
            if (key < best[r][kPeelK - 1]) insert(best[r], key, cnt[r]);
            ++cnt[r];
          }
        }
        const bool lanes = kLanes && lambertLanes && run > 1;
        for (int r = 0; r < kPeelRun && r < run; ++r) {
          if (!more[r]) continue;
          if (first) count(cnt[r], frags);  // the statistics: every fragment in front of the opaque depth
          if (lanes) continue;  // composited below, the run's pixels together
          // Front to back: on a GPU the nearest taken from the front of the
          // array and the rest shifted up (compile-time indices, one shading
          // call); a CPU indexes the array.
          const uint64_t lastKey = best[r][kPeelK - 1];
          const int kept = cnt[r] < uint32_t(kPeelK) ? int(cnt[r]) : kPeelK;
          for (int k = 0; k < kept && T[r] > 0.0f; ++k) {
            const uint64_t key = best[r][kOnDevice ? 0 : k];
            if (kOnDevice)
              for (int m = 0; m + 1 < kPeelK; ++m) best[r][m] = best[r][m + 1];
            const float4 c = cache.template at<kFeat>(fs, keyIndex(key, sorted != 0), x0 + r, Y, s);
            if (c.w > 0.0f) over(acc[r], T[r], c);  // alpha 0 (or NaN): no fragment
          }
          more[r] = cnt[r] > uint32_t(kPeelK) && T[r] > 0.0f;
          after[r] = lastKey;
        }
        if constexpr (kLanes) {
          if (lanes) {
            compositeLanes(x0, Y, s, run, best, cnt, more, acc, T, cache);
            for (int r = 0; r < kPeelRun && r < run; ++r) {
              if (!more[r]) continue;
              more[r] = cnt[r] > uint32_t(kPeelK) && T[r] > 0.0f;
              after[r] = best[r][kPeelK - 1];
            }
          }
        }
      }
      for (int r = 0; r < kPeelRun && r < run; ++r) filmSample(int64_t(Y) * width + x0 + r, s, S, acc[r], T[r], sum[r]);
    }
  }

  // The statistics: a sample's fragments in front of the opaque depth.
  RAST_GPU_INLINE void count(const uint32_t cnt, uint64_t& frags) const { count(cnt, cnt, frags); }
  // The same for many samples: n fragments, at most deepest at one.
  RAST_GPU_INLINE void count(const uint64_t n, const uint32_t deepest, uint64_t& frags) const {
    frags += n;
    // uint64_t's maximum (a compare-and-swap loop behind a plain read), not
    // raiseTotal's hardware one: inlined into the team's resolve and the
    // uniform blocks' classification, that took 4 registers more and 8 to
    // 72 bytes more stack, and the H200's BLEND frame 3-7 us more.
    if (deepest > totals(kBlendMaxDepth)) Kokkos::atomic_fetch_max(&totals(kBlendMaxDepth), uint64_t(deepest));
  }

  // weighted: pixels x0 .. x0 + run - 1 of row Y, one walk of the list (in
  // raster-index order: tiles_sort), every fragment in front of the opaque
  // depth with an alpha above 0 added to its sample's sums (weightedTerms,
  // McGuire and Bavoil's weight at its depth), in registers: no atomics, the
  // same terms in the same order whatever the thread schedule. On a CPU
  // under the headlight's Lambert a triangle's fragments along the row are
  // lit together (litLanes).
  RAST_GPU_INLINE void rowWeighted(const int32_t x0, const int32_t Y, const int32_t run, const uint32_t begin,
                                   const uint32_t end, PeelCache& cache, uint64_t& frags) const {
    const int S = fs.sp.count;
    float4 sum[kPeelRun];
    for (int r = 0; r < kPeelRun; ++r) sum[r] = float4{0.0f, 0.0f, 0.0f, 0.0f};
    for (int s = 0; s < S; ++s) {
      float4 w[kPeelRun];
      float reveal[kPeelRun];
      uint32_t cnt[kPeelRun], opq[kPeelRun];
      for (int r = 0; r < kPeelRun && r < run; ++r) {
        w[r] = float4{0.0f, 0.0f, 0.0f, 0.0f};
        reveal[r] = 1.0f;
        cnt[r] = 0;
        opq[r] = opaque((int64_t(Y) * width + x0 + r) * S + s);
      }
      for (uint32_t j = begin; j < end; ++j) {
        const uint32_t i = tileTris(j);
        const RasterTri& t = fs.sc.tris(i);
        const Edges e(t);
        const DepthTerms dz(t);
        const int32_t ox = fs.sp.ox[s], oy = fs.sp.oy[s];
        int64_t s0 = e.sample(0, x0, Y, ox, oy), s1 = e.sample(1, x0, Y, ox, oy), s2 = e.sample(2, x0, Y, ox, oy);
        int lane[kPeelRun];
        float z[kPeelRun];
        int m = 0;
        for (int r = 0; r < kPeelRun && r < run; ++r, s0 += e.A[0], s1 += e.A[1], s2 += e.A[2]) {
          if (!e.inside(s0, s1, s2)) continue;
          z[m] = dz.at(s0, s2);
          if (!(floatBits(z[m]) < opq[r])) continue;  // LESS against the opaque depth
          ++cnt[r];
          lane[m++] = r;
        }
        float4 col[kPeelRun];
        bool lit = false;
        if constexpr (kLanes) lit = lambertLanes && m > 1 && litLanes(i, x0, Y, s, lane, m, cache, col);
        for (int k = 0; k < m; ++k) {
          const int r = lane[k];
          const float4 c = lit ? col[k] : cache.template at<kFeat>(fs, i, x0 + r, Y, s);
          if (c.w > 0.0f) weightedTerms(w[r], reveal[r], c, fs.weight(z[k]));  // alpha 0 (or NaN): no fragment
        }
      }
      for (int r = 0; r < kPeelRun && r < run; ++r) {
        count(cnt[r], frags);
        float3 acc;
        float T;
        weightedFront(w[r], reveal[r], acc, T);
        filmSample(int64_t(Y) * width + x0 + r, s, S, acc, T, sum[r]);
      }
    }
  }
};

}  // namespace blending
}  // namespace rast
