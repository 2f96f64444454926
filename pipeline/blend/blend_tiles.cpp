// The exact and sorted BLEND methods (docs/transparency.md, "exact and sorted:
// tile lists, peeled in registers"): no fragment is stored. Before shading (the opaque
// depth is still in the visibility buffer):
//   tiles_count, tiles_layout, tiles_fill: a counted two-pass layout of the
//     BLEND work items (raster triangle, 8x8 block): per block the list of
//     the triangles that cover a sample of it, 4 bytes an entry; an item whose
//     triangle covers no sample of its block is left out (exact test on the
//     block's corner samples). The order inside a list depends on the thread
//     schedule; nothing below depends on it.
//   opaque_depth: the opaque depth of every sample, which shading clears.
// After shading, resolve: per sample, its block's list walked with the raster
// methods' edge and depth arithmetic, LESS against the opaque depth; the K
// smallest keys (visKey or sortedKey: unique) above the last pass's largest
// are kept in a small sorted array and composited front to back ("over", as
// kbuffer and the old fragment store did: the same bits); a sample with more
// than K fragments, still not opaque, walks the list again from there (depth
// peeling, in registers). A pass costs a walk of the list; a sample of L
// layers takes ceil(L / K) passes until its transmittance reaches 0.
#include "pipeline/blend/frag_shade.h"
#include "pipeline/cpu/span_math.h"
#include "pipeline/data/test_hooks.h"

namespace rast {
namespace blending {
namespace {

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

// A listed triangle's set-up for its items: edges, box, and per edge the
// largest step from a pixel centre to one of its samples, with the bias.
struct ItemTri {
  uint32_t index = ~0u;
  Edges e{};
  ItemBox b{};
  int64_t reach[3] = {0, 0, 0};
};

// Whether the triangle covers no sample of the pixels [x0, x1] x [y0, y1]:
// some edge is not positive (with its bias) at any of their samples. An edge
// function is linear: its largest value over the pixel centres is at the
// corner its signs point to, and a sample adds the same offset in every
// pixel, so the largest over the samples is that corner's value plus the
// edge's largest offset (reach): exact, no fragment is lost.
KOKKOS_INLINE_FUNCTION bool blockMissed(const ItemTri& it, int32_t x0, int32_t x1, int32_t y0, int32_t y1) {
  for (int i = 0; i < 3; ++i)
    if (it.e.eval(i, it.e.A[i] > 0 ? x1 : x0, it.e.B[i] > 0 ? y1 : y0) + it.reach[i] <= 0) return true;
  return false;
}

// tiles_count (pass 0) and tiles_fill (pass 1): each BLEND work item whose
// triangle covers a sample of its block, counted into the block's count, then
// written at its block's cursor (tileEnd, the scan's start before the fill).
// A GPU thread takes every threads-th item (neighbouring threads, neighbouring
// items); a CPU thread a contiguous share, so that its items' owner is found
// by stepping and set up once per triangle.
struct TileItems {
  DView<RasterTri> tris;
  DView<uint64_t> start, totals;
  DView<uint32_t> counters, tileCount, tileEnd, tileTris;
  Viewport vp;
  uint32_t capacity, threads, blocksX;
  uint64_t tileCapacity;
  int32_t fill;
  KOKKOS_INLINE_FUNCTION void prepare(uint32_t i, ItemTri& it) const {
    const RasterTri& t = tris(i);
    it.index = i;
    it.e = Edges(t);
    it.b = itemBox(t, vp);
    const SamplePattern& sp = vp.samples;
    for (int k = 0; k < 3; ++k) {
      int64_t m = it.e.atSample(k, 0, sp.ox[0], sp.oy[0]);
      for (int s = 1; s < sp.count; ++s) {
        const int64_t v = it.e.atSample(k, 0, sp.ox[s], sp.oy[s]);
        m = v > m ? v : m;
      }
      it.reach[k] = m + it.e.bias[k];
    }
  }
  KOKKOS_INLINE_FUNCTION void item(uint64_t w, const ItemTri& it) const {
    const ItemBox& b = it.b;
    const uint32_t local = uint32_t(w - start(it.index));
    const int32_t bx = b.bx0 + int32_t(local % uint32_t(b.bw)), by = b.by0 + int32_t(local / uint32_t(b.bw));
    const int32_t x0 = b.minX > (bx << kItemShift) ? b.minX : (bx << kItemShift);
    const int32_t x1 = b.maxX < ((bx + 1) << kItemShift) - 1 ? b.maxX : ((bx + 1) << kItemShift) - 1;
    const int32_t y0 = b.minY > (by << kItemShift) ? b.minY : (by << kItemShift);
    const int32_t y1 = b.maxY < ((by + 1) << kItemShift) - 1 ? b.maxY : ((by + 1) << kItemShift) - 1;
    if (blockMissed(it, x0, x1, y0, y1)) return;
    const uint32_t block = uint32_t(by) * blocksX + uint32_t(bx);
    if (!fill) {
      Kokkos::atomic_fetch_add(&tileCount(block), 1u);
      return;
    }
    const uint32_t slot = Kokkos::atomic_fetch_add(&tileEnd(block), 1u);
    if (slot < tileCapacity) tileTris(slot) = it.index;  // else the frame is drawn again with more room (lastFrameFit)
  }
  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t th) const {
    const uint64_t total = totals(kBlendItems);
    const uint32_t n = counters(kRasterTris) < capacity ? counters(kRasterTris) : capacity;
    ItemTri it;
    if (kOnDevice) {
      for (uint64_t w = th; w < total; w += threads) {
        const uint32_t i = itemOwner(start, n, w);
        if (i != it.index) prepare(i, it);
        item(w, it);
      }
      return;
    }
    const uint64_t share = (total + threads - 1) / threads, w0 = share * th;
    const uint64_t w1 = w0 + share < total ? w0 + share : total;
    uint32_t i = w0 < w1 ? itemOwner(start, n, w0) : 0;
    for (uint64_t w = w0; w < w1; ++w) {
      while (i + 1 < n && start(i + 1) <= w) ++i;  // itemOwner's answer, stepping
      if (i != it.index) prepare(i, it);
      item(w, it);
    }
  }
};

// tiles_layout: exclusive scan of the block counts into tileEnd (the fill's
// cursors), the 64-bit total into totals(kBlendListed): a total beyond any
// capacity is seen as such and never wraps.
struct TileScan {
  DView<uint32_t> tileCount, tileEnd;
  DView<uint64_t> totals;
  uint32_t n;
  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t i, uint64_t& upd, const bool final) const {
    const uint32_t v = tileCount(i);
    if (final) {
      if (v > totals(kBlendLongest)) Kokkos::atomic_fetch_max(&totals(kBlendLongest), uint64_t(v));
      tileEnd(i) = uint32_t(upd);
      if (i + 1 == n) totals(kBlendListed) = upd + v;
    }
    upd += v;
  }
};

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
    const uint32_t end = listed ? tileEnd(block) : 0u, begin = listed ? end - tileCount(block) : 0u;
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
  KOKKOS_INLINE_FUNCTION void compositeLanes(const int32_t x0, const int32_t Y, const int s, const int32_t run,
                                             const uint64_t (&best)[kPeelRun][kPeelK], const uint32_t (&cnt)[kPeelRun],
                                             const bool (&more)[kPeelRun], float3 (&acc)[kPeelRun],
                                             float (&T)[kPeelRun], PeelCache& cache) const {
    using shading::SpanConsts;
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
        const int e = cache.slot(tri);
        if (cache.a[e].index != tri) fs.sc.prepare(tri, cache.a[e]);
        fs.template use<kFam>(tri, cache.tf[e], cache.pt[e]);
        cache.evS[e] = -1;  // its stepped edge values are not this row's
        const AlphaTri& a = cache.a[e];
        const TriFrag& f = cache.tf[e];
        if (!a.textured && !fs.sc.hasColor && !f.textured) {
          const float alpha = cleanAlpha(a.alpha);  // AlphaScene::alphaFrom of a constant alpha
          if (!(alpha > 0.0f)) continue;           // no fragment
          // The edge values at the sample of pixel (X, Y) (Edges::atSample),
          // exact integers in double; the headlight's lighting.
          SpanConsts c;
          fillSpanConsts(c, f, fs.sp.ox[s], fs.sp.oy[s], fs.sh.p.perspective != 0, f.eye, fs.sh.p.ambient,
                         1.0f - fs.sh.p.ambient);
          alignas(32) int32_t X[kPeelRun], Ys[kPeelRun];
          alignas(32) float b0[kPeelRun], b1[kPeelRun], b2[kPeelRun], nx[kPeelRun], ny[kPeelRun], nz[kPeelRun],
              diffuse[kPeelRun];
          for (int j = 0; j < m; ++j) {
            X[j] = x0 + lane[j];
            Ys[j] = Y;
          }
          shading::spanLightingLanesWide(c, m, X, Ys, b0, b1, b2, nx, ny, nz, diffuse);
          const float4 base = f.baseColor;
          for (int j = 0; j < m; ++j) {  // Shade::litLight's colour (spec is 0 in Lambert)
            const float3 rgb = float3{base.x, base.y, base.z} * diffuse[j] + float3{0.0f, 0.0f, 0.0f};
            over(acc[lane[j]], T[lane[j]], float4{rgb.x, rgb.y, rgb.z, alpha});
          }
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
          int64_t s0 = e.atSample(0, e.eval(0, x0, Y), ox, oy), s1 = e.atSample(1, e.eval(1, x0, Y), ox, oy),
                  s2 = e.atSample(2, e.eval(2, x0, Y), ox, oy);
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
          if (first) {  // the statistics: every fragment in front of the opaque depth
            frags += cnt[r];
            if (cnt[r] > totals(kBlendMaxDepth)) Kokkos::atomic_fetch_max(&totals(kBlendMaxDepth), uint64_t(cnt[r]));
          }
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
      for (int r = 0; r < kPeelRun && r < run; ++r) {
        const int64_t i = int64_t(Y) * width + x0 + r;
        const float4 out = overOpaque(acc[r], T[r], hdr(i));
        if (S == 1) {
          hdr(i) = out;
        } else {
          sum[r] = sum[r] + out;
          if (s + 1 == S) hdr(i) = sum[r] * (1.0f / float(S));
        }
      }
    }
  }
};

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

// The resolve's team form, for the specialised fragment shading on GPUs (and
// on host backends under TestHooks::teamResolve, so that tests compare it
// with the plain form): a team per 8x8 block. The block's list is copied into
// team scratch in raster-index order and each of its triangles set up there
// once for the block's 64 pixels: edges and depth terms, the shading lookups
// (AlphaTri, TriFrag, PbrTri), and the triangle's depth range over the block.
// The plain resolve set a triangle up again for every fragment it shaded
// (one cached lookup a thread: a pixel's layers are different triangles).
// The triangles' order is then the same at every sample of the block when
//   sorted: always (a triangle's key is its draw's, whatever the sample);
//   exact:  the depth ranges do not overlap (separate layers: most blocks),
// and each pixel walks the list once in that order, compositing what it
// covers as it finds it: no keys, no insertion, no second walk. Otherwise a
// pixel keeps the K nearest keys and peels as row() does, with keys that end
// in the triangle's place in the list instead of its raster index (the list
// is in raster-index order: the same order). Either way the same fragments
// are composited in the same order as by the plain form: the same bits. A
// list longer than the scratch holds is resolved the plain way.
template <int kFam, int kFeat>
struct PeelTeam {
  struct Entry {
    AlphaTri a;
    TriFrag tf;
    FragPbrTri<kFam> pt;
    DepthTerms dz;    // no default: entries live in scratch, never constructed
    uint64_t triKey;  // sorted: its draw's key with the low half cleared
    uint64_t order;   // its key in the block's order (sorted's key; exact: the depth range's start)
    float lo, hi;     // exact: its depth range over the block
  };
  static constexpr int32_t kPixels = 1 << (2 * kItemShift);
  // Entries that fit n bytes of scratch; the scratch for n entries.
  static constexpr uint32_t entriesIn(size_t n) { return uint32_t((n - 64) / (sizeof(Entry) + 2 * sizeof(uint32_t))); }
  static constexpr size_t scratchFor(uint32_t n) { return n * (sizeof(Entry) + 2 * sizeof(uint32_t)) + 64; }
  static_assert(entriesIn(kBlendTeamScratchBytes) >= 16,
                "a block's list under 8 full-screen layers (16 triangles on its diagonal) fits");
  // The entries of a frame whose last frame's longest list was `longest`.
  static uint32_t entriesFor(uint64_t longest) {
    const uint32_t lo = entriesIn(kBlendTeamScratchBytes), hi = entriesIn(kBlendTeamScratchMaxBytes);
    return longest <= lo ? lo : (longest < hi ? uint32_t(longest) : hi);
  }

  Peel<kFam, kFeat> peel;
  int64_t blocks;
  uint32_t entries;  // entries the scratch holds (entriesFor)

  // The team's scratch: the entries, the raw and ordered lists, flags and
  // the team's fragment count.
  struct Scratch {
    Entry* ent;
    uint32_t *raw, *ord;
    int32_t *ordered, *same;
    uint64_t* frags;
  };

  // A team takes a run of neighbouring blocks (along a row: mostly the same
  // list, whose entries it then keeps), and counts its fragments into
  // totals(kBlendFrags) with one atomic (a team reduction per block cost
  // more than the resolve's own work on the H100).
  RAST_FLATTEN void operator()(const TeamMember& m) const {
    Scratch sc;
    sc.ent = static_cast<Entry*>(m.team_scratch(0).get_shmem_aligned(size_t(entries) * sizeof(Entry), 16));
    sc.raw = static_cast<uint32_t*>(m.team_scratch(0).get_shmem(entries * sizeof(uint32_t)));
    sc.ord = static_cast<uint32_t*>(m.team_scratch(0).get_shmem(entries * sizeof(uint32_t)));
    sc.frags = static_cast<uint64_t*>(m.team_scratch(0).get_shmem_aligned(sizeof(uint64_t), 8));
    sc.ordered = static_cast<int32_t*>(m.team_scratch(0).get_shmem(sizeof(int32_t)));
    sc.same = static_cast<int32_t*>(m.team_scratch(0).get_shmem(sizeof(int32_t)));
    const int64_t per = (blocks + m.league_size() - 1) / m.league_size();
    const int64_t b0 = per * m.league_rank(), b1 = b0 + per < blocks ? b0 + per : blocks;
    uint64_t frags = 0;
    uint32_t held = ~0u;  // the length of the list whose entries the scratch holds (~0u: none)
    if (m.team_rank() == 0) *sc.frags = 0;
    for (int64_t block = b0; block < b1; ++block) resolveBlock(m, sc, block, held, frags);
    if (frags) Kokkos::atomic_add(sc.frags, frags);
    m.team_barrier();
    if (m.team_rank() == 0 && *sc.frags) Kokkos::atomic_add(&peel.totals(kBlendFrags), *sc.frags);
  }

  // The place of raster index i in the list in raster-index order (its
  // entries are unique).
  KOKKOS_INLINE_FUNCTION static uint32_t rankOf(const uint32_t* raw, const uint32_t n, const uint32_t i) {
    uint32_t r = 0;
    for (uint32_t k = 0; k < n; ++k) r += raw[k] < i ? 1u : 0u;
    return r;
  }

  RAST_GPU_INLINE void resolveBlock(const TeamMember& m, const Scratch& sc, const int64_t block, uint32_t& held,
                                    uint64_t& frags) const {
    const Peel<kFam, kFeat>& P = peel;
    const int32_t bx = int32_t(block % P.blocksX), by = int32_t(block / P.blocksX);
    const int32_t x0 = bx << kItemShift, y0 = by << kItemShift;
    const bool listed = P.totals(kBlendListed) <= P.tileCapacity;  // else the frame is drawn again
    const uint32_t end = listed ? P.tileEnd(block) : 0u, begin = listed ? end - P.tileCount(block) : 0u;
    const uint32_t n = end - begin;
    const int nThreads = m.team_size(), me = m.team_rank();
    if (n > entries) {  // the plain resolve's walk of the global list
      typename Peel<kFam, kFeat>::PeelCache cache;
      for (int p = me; p < kPixels; p += nThreads) {
        const int32_t X = x0 + (p & ((1 << kItemShift) - 1)), Y = y0 + (p >> kItemShift);
        if (X < P.width && Y < P.height) P.row(X, Y, 1, begin, end, cache, frags);
      }
      return;
    }
    Entry* ent = sc.ent;
    uint32_t *raw = sc.raw, *ord = sc.ord;
    for (uint32_t j = uint32_t(me); j < n; j += uint32_t(nThreads)) raw[j] = P.tileTris(begin + j);
    if (me == 0) {
      *sc.ordered = 1;
      *sc.same = n == held ? 1 : 0;
    }
    m.team_barrier();
    // Entry r of the list in raster-index order: its rank among the (unique)
    // raster indices. The last block's entries serve when they are the same.
    for (uint32_t j = uint32_t(me); j < n; j += uint32_t(nThreads))
      if (ent[rankOf(raw, n, raw[j])].a.index != raw[j]) *sc.same = 0;
    m.team_barrier();
    if (!*sc.same) {
      for (uint32_t j = uint32_t(me); j < n; j += uint32_t(nThreads)) {
        const uint32_t i = raw[j], r = rankOf(raw, n, i);
        Entry& en = ent[r];
        en.a.index = ~0u;
        P.fs.sc.prepare(i, en.a);
        en.tf.index = ~0u;
        P.fs.template use<kFam>(i, en.tf, en.pt);
        en.dz = DepthTerms(P.fs.sc.tris(i));
        en.triKey = P.sorted ? P.sortedKeyOf(i) & ~uint64_t(0xffffffffu) : 0;
      }
    }
    held = n;
    // Each entry's depth range over this block, and its key in the block's
    // order: sorted's key (as the keys below); exact: the range's start, ties
    // by raster index.
    for (uint32_t r = uint32_t(me); r < n; r += uint32_t(nThreads)) {
      Entry& en = ent[r];
      blockDepthRange(en.tf.e, en.dz, x0, y0, en.lo, en.hi);
      en.order = P.sorted ? en.triKey | uint64_t(0xffffffffu - r) : uint64_t(orderBits(en.lo)) << 32 | r;
    }
    m.team_barrier();
    for (uint32_t r = uint32_t(me); r < n; r += uint32_t(nThreads)) {
      uint32_t d = 0;
      for (uint32_t k = 0; k < n; ++k) d += ent[k].order < ent[r].order ? 1u : 0u;
      ord[d] = r;
    }
    m.team_barrier();
    if (!P.sorted)
      for (uint32_t t = uint32_t(me); t + 1 < n; t += uint32_t(nThreads))
        if (!(ent[ord[t]].hi < ent[ord[t + 1]].lo)) *sc.ordered = 0;  // ranges overlap (or NaN)
    m.team_barrier();
    const bool inOrder = *sc.ordered != 0;
    for (int p = me; p < kPixels; p += nThreads) {
      const int32_t X = x0 + (p & ((1 << kItemShift) - 1)), Y = y0 + (p >> kItemShift);
      if (X < P.width && Y < P.height) {
        if (inOrder)
          pixelInOrder(ent, ord, n, X, Y, frags);
        else
          pixel(ent, n, X, Y, frags);
      }
    }
    m.team_barrier();  // the scratch is the next block's
  }

  // The sample's result into the film (row()'s ending).
  RAST_GPU_INLINE void store(const int64_t px, const int s, const float3 acc, const float T, float4& sum) const {
    const Peel<kFam, kFeat>& P = peel;
    const int S = P.fs.sp.count;
    const float4 out = overOpaque(acc, T, P.hdr(px));
    if (S == 1) {
      P.hdr(px) = out;
    } else {
      sum = sum + out;
      if (s + 1 == S) P.hdr(px) = sum * (1.0f / float(S));
    }
  }
  RAST_GPU_INLINE void count(const uint32_t cnt, uint64_t& frags) const {
    // the statistics: every fragment in front of the opaque depth
    frags += cnt;
    if (cnt > peel.totals(kBlendMaxDepth)) Kokkos::atomic_fetch_max(&peel.totals(kBlendMaxDepth), uint64_t(cnt));
  }

  // Pixel (X, Y) of a block whose triangles keep one order at all its
  // samples: one walk in that order, each fragment composited as found.
  RAST_GPU_INLINE void pixelInOrder(const Entry* ent, const uint32_t* ord, const uint32_t n, const int32_t X,
                                    const int32_t Y, uint64_t& frags) const {
    const FragShade& fs = peel.fs;
    const int S = fs.sp.count;
    const int64_t px = int64_t(Y) * peel.width + X;
    float4 sum{0.0f, 0.0f, 0.0f, 0.0f};
    for (int s = 0; s < S; ++s) {
      const int32_t ox = fs.sp.ox[s], oy = fs.sp.oy[s];
      const uint32_t opq = peel.opaque(px * S + s);
      float3 acc{0.0f, 0.0f, 0.0f};
      float T = 1.0f;
      uint32_t cnt = 0;
      for (uint32_t t = 0; t < n; ++t) {
        const Entry& en = ent[ord[t]];
        const Edges& e = en.tf.e;
        const int64_t s0 = e.atSample(0, e.eval(0, X, Y), ox, oy), s1 = e.atSample(1, e.eval(1, X, Y), ox, oy),
                      s2 = e.atSample(2, e.eval(2, X, Y), ox, oy);
        if (!e.inside(s0, s1, s2)) continue;
        if (!(floatBits(en.dz.at(s0, s2)) < opq)) continue;  // LESS against the opaque depth
        ++cnt;
        if (!(T > 0.0f)) continue;  // opaque already: counted, not shaded
        const float4 c = fs.template shadeAt<kFam, kFeat>(X, Y, s, s0, s1, s2, en.a, en.tf, en.pt);
        if (c.w > 0.0f) over(acc, T, c);  // alpha 0 (or NaN): no fragment
      }
      count(cnt, frags);
      store(px, s, acc, T, sum);
    }
  }

  // Pixel (X, Y): row()'s passes over the scratch entries, key for key.
  RAST_GPU_INLINE void pixel(const Entry* ent, const uint32_t n, const int32_t X, const int32_t Y,
                             uint64_t& frags) const {
    const Peel<kFam, kFeat>& P = peel;
    const FragShade& fs = P.fs;
    const int S = fs.sp.count;
    const int64_t px = int64_t(Y) * P.width + X;
    float4 sum{0.0f, 0.0f, 0.0f, 0.0f};
    for (int s = 0; s < S; ++s) {
      const int32_t ox = fs.sp.ox[s], oy = fs.sp.oy[s];
      const uint32_t opq = P.opaque(px * S + s);
      uint64_t after = 0;  // every key is above 0
      float3 acc{0.0f, 0.0f, 0.0f};
      float T = 1.0f;
      for (bool more = n > 0, first = true; more; first = false) {
        uint64_t best[kPeelK];
        for (int k = 0; k < kPeelK; ++k) best[k] = kNoKey;
        uint32_t cnt = 0;
        for (uint32_t j = n; j-- > 0;) {  // last entry first, as row()
          const Entry& en = ent[j];
          const Edges& e = en.tf.e;
          const int64_t s0 = e.atSample(0, e.eval(0, X, Y), ox, oy), s1 = e.atSample(1, e.eval(1, X, Y), ox, oy),
                        s2 = e.atSample(2, e.eval(2, X, Y), ox, oy);
          if (!e.inside(s0, s1, s2)) continue;
          const float z = en.dz.at(s0, s2);
          if (!(floatBits(z) < opq)) continue;  // LESS against the opaque depth
          const uint64_t key = P.sorted ? (en.triKey | uint64_t(0xffffffffu - j)) : visKey(z, j);
          if (key <= after) continue;  // composited by an earlier pass
          if (key < best[kPeelK - 1]) Peel<kFam, kFeat>::insert(best, key, cnt);
          ++cnt;
        }
        if (first) count(cnt, frags);
        const uint64_t lastKey = best[kPeelK - 1];
        const int kept = cnt < uint32_t(kPeelK) ? int(cnt) : kPeelK;
        for (int k = 0; k < kept && T > 0.0f; ++k) {
          const uint64_t key = best[kOnDevice ? 0 : k];
          if (kOnDevice)
            for (int q = 0; q + 1 < kPeelK; ++q) best[q] = best[q + 1];
          const Entry& en = ent[keyIndex(key, P.sorted != 0)];
          const Edges& e = en.tf.e;
          const float4 c = fs.template shadeAt<kFam, kFeat>(X, Y, s, e.atSample(0, e.eval(0, X, Y), ox, oy),
                                                            e.atSample(1, e.eval(1, X, Y), ox, oy),
                                                            e.atSample(2, e.eval(2, X, Y), ox, oy), en.a, en.tf, en.pt);
          if (c.w > 0.0f) over(acc, T, c);  // alpha 0 (or NaN): no fragment
        }
        more = cnt > uint32_t(kPeelK) && T > 0.0f;
        after = lastKey;
      }
      store(px, s, acc, T, sum);
    }
  }
};

// peelResolve's launch of the frame's instance (withFragPath).
struct PeelLaunch {
  const FragShade& fs;
  const FrameBuffers& f;
  const Kokkos::Sum<uint64_t, Mem>& result;
  int64_t items;
  int32_t blocksX, sorted;
  template <int kFam, int kFeat>
  void run() const {
    const BlendBuffers& bb = f.blend;
    const Peel<kFam, kFeat> peel{fs, f.post.hdr, bb.tileCount, bb.tileEnd, bb.tileTris, bb.opaque, bb.totals,
                                 bb.tileCapacity, f.vp.width, f.vp.height, blocksX, sorted,
                                 fs.sh.p.mode == ShadingMode::Lambert && fs.sh.p.headlight ? 1 : 0};
    // The specialised resolves keep everything inline (nothing takes a
    // local's address) and launch lightweight, as the shade stage's lit and
    // glTF kernels; the general one calls the general fragment maths out
    // of line on a GPU and launches heavyweight (pipeline/data/device.h).
    static_assert(!kOnDevice || sizeof(peel) <= 4000, "a lightweight launch carries its functor in 4 KiB of parameters");
    if constexpr (kFam == kFragGeneral) {
      Kokkos::parallel_reduce("rast::blend::resolve", heavyweight(Range(0, items)), peel, result);
    } else if (kOnDevice || testHooks().teamResolve) {
      using Team = PeelTeam<kFam, kFeat>;
      using Policy = Kokkos::TeamPolicy<Exec, Kokkos::LaunchBounds<kBlendTeamLaunchBounds[0], kBlendTeamLaunchBounds[1]>>;
      const int64_t blocks = kPeelRun == 1 ? items >> (2 * kItemShift) : items;
      const int teamSize = kOnDevice ? Team::kPixels : 1;
      const int64_t teams = std::min<int64_t>(blocks, std::max<int64_t>(1, persistentThreads() / teamSize));
      const uint32_t entries = Team::entriesFor(bb.longestList);
      Kokkos::parallel_for(
          "rast::blend::resolve",
          lightweight(Policy(int(teams), teamSize).set_scratch_size(0, Kokkos::PerTeam(Team::scratchFor(entries)))),
          Team{peel, blocks, entries});
    } else {
      Kokkos::parallel_reduce(
          "rast::blend::resolve",
          lightweight(Kokkos::RangePolicy<Exec, Kokkos::LaunchBounds<kBlendResolveLaunchBounds[0],
                                                                     kBlendResolveLaunchBounds[1]>>(0, items)),
          peel, result);
    }
  }
};

}  // namespace

void tileLists(FrameBuffers& f, const DView<uint64_t>& opaqueKeys) {
  BlendBuffers& bb = f.blend;
  const uint32_t blocksX = uint32_t(f.vp.width + (1 << kItemShift) - 1) >> kItemShift;
  const uint32_t blocks = blocksX * (uint32_t(f.vp.height + (1 << kItemShift) - 1) >> kItemShift);
  const size_t n = size_t(f.vp.width) * size_t(f.vp.height) * size_t(f.vp.samples.count);
  ensureCapacity(bb.tileCount, "blend.tileCount", blocks);
  ensureCapacity(bb.tileEnd, "blend.tileEnd", blocks);
  ensureCapacity(bb.opaque, "blend.opaque", n);
  if (!bb.tileTris.data()) {
    bb.tileCapacity = bb.tileCapacity ? bb.tileCapacity : blocks;  // one entry a block, then the frame's need
    bb.tileTris = allocUninit<uint32_t>("blend.tileTris", bb.tileCapacity);
  }
  Kokkos::deep_copy(Exec(), Kokkos::subview(bb.tileCount, std::make_pair(size_t(0), size_t(blocks))), 0u);
  const uint32_t threads = persistentThreads();
  TileItems c{f.tris, bb.blendStart, bb.totals, f.counters, bb.tileCount, bb.tileEnd, bb.tileTris, f.vp,
              f.triCapacity, threads, blocksX, bb.tileCapacity, 0};
  using Policy = Kokkos::RangePolicy<Exec, Kokkos::IndexType<uint32_t>>;
  Kokkos::parallel_for("rast::blend::tiles_count", Policy(0, threads), c);
  Kokkos::parallel_scan("rast::blend::tiles_layout", Policy(0, blocks), TileScan{bb.tileCount, bb.tileEnd, bb.totals, blocks});
  c.fill = 1;
  Kokkos::parallel_for("rast::blend::tiles_fill", Policy(0, threads), c);
  auto vis = opaqueKeys;
  auto opaque = bb.opaque;
  Kokkos::parallel_for("rast::blend::opaque_depth", Range(0, int64_t(n)),
                       KOKKOS_LAMBDA(const int64_t q) { opaque(q) = uint32_t(vis(q) >> 32); });
}

void peelResolve(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights,
                 bool sorted) {
  const BlendBuffers& bb = f.blend;
  const int32_t blocksX = (f.vp.width + (1 << kItemShift) - 1) >> kItemShift;
  const int64_t blocks = int64_t(blocksX) * ((f.vp.height + (1 << kItemShift) - 1) >> kItemShift);
  const int64_t items = kPeelRun == 1 ? blocks << (2 * kItemShift) : blocks;
  // The fragment count summed over threads into totals(kBlendFrags), not
  // one atomic a pixel; the depth's maximum (cleared with it by blendCollect)
  // rises a few times a frame.
  const Kokkos::Sum<uint64_t, Mem> result(Kokkos::View<uint64_t, Mem>(bb.totals.data() + kBlendFrags));
  const FragShade fs = makeFragShade(s, f, p, lights);
  withFragPath(fs, PeelLaunch{fs, f, result, items, blocksX, sorted ? 1 : 0});
}

}  // namespace blending
}  // namespace rast
