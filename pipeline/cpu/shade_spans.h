// The CPU's shade kernel for Lambert shading with one sample per pixel: a work
// item takes a run of pixels along a row (kShadeRun), cuts it into spans of
// one triangle, and shades each span a stage at a time over small arrays
// (barycentrics, normals, positions, lighting for every pixel of the span,
// then texturing, then packing), so that the compiler turns the arithmetic
// stages into SIMD loops over pixels instead of one scalar fragment at a time.
//
// Every value is computed by the same operations in the same order as
// Shade::shadeFragment (edge values exactly in integers, then the same float
// expressions, no contraction), so the image is bit-identical to the per-pixel
// kernel's; only the order in which pixels are visited differs. Pixels of
// points and lines, and frames this kernel does not cover (other modes,
// trilinear filtering, MSAA, normals or SSAO outputs), use the per-pixel
// shader (see usable()).
//
// The kernel's parts are in the headers it includes: the span arithmetic
// (span_math.h), texturing (span_texture.h), runs and lane batches
// (lane_batch.h), and the members that shade a set of pixels as vector lanes
// (addLights, addLanes, shadeBatch, span, shadeLanes, texture: span_lanes.h,
// included at the end of this one). This header keeps the kernel itself: the
// triangle cache, the work items over rows and tiles, and how a row is cut
// into spans and batches.
#pragma once

#include "backends/bit_scan.h"
#include "backends/cpu_clones.h"
#include "pipeline/shade/shade_fragment.h"
#include "pipeline/cpu/span_math.h"
#include "pipeline/cpu/span_texture.h"
#include "pipeline/cpu/lane_batch.h"

namespace rast {
namespace shading {

// What a span needs of its triangle, looked up and computed once per
// triangle (Shade::prepare, then the triangle's constants of spanLighting and
// of the texture) and kept in a small cache while a tile or run is shaded:
// rows of a tile alternate between the same few triangles.
struct SpanTri {
  TriFrag f;
  SpanConsts k;  // all but the span's edge values s0, s1, s2
  SpanTex tex;
  int32_t spanReady;  // k and tex are set (prepareSpan)
};

struct SpanTriCache {
  static constexpr int kSlots = 8;
  uint32_t key[kSlots] = {~0u, ~0u, ~0u, ~0u, ~0u, ~0u, ~0u, ~0u};  // slot[s].f.index, together in one line
  SpanTri slot[kSlots];
  int next = 0;
};

struct ShadeSpans : Shade {
  // Whether this kernel covers a frame of these settings.
  static bool usable(const ShadeParams& p, int samples, int run) {
    return run > 1 && run <= kMaxSpanRun && samples == 1 && p.mode == ShadingMode::Lambert &&
           p.filter != TexFilter::Trilinear && !p.wantNormals && !p.wantGeom;
  }

  KOKKOS_INLINE_FUNCTION void put(int64_t i, float4 c) const {
    if (p.floatOut) hdr(i) = c;
    else color(i) = display(c);
  }

  KOKKOS_INLINE_FUNCTION void operator()(const int64_t item) const {
    const int32_t Y = int32_t(item / runsPerRow);
    const int32_t x0 = int32_t(item % runsPerRow) * run;
    const int32_t n = (x0 + run < width ? x0 + run : width) - x0;
    const int64_t row = int64_t(Y) * width + x0;
    uint32_t idx[kMaxSpanRun], depthBits[kMaxSpanRun];
    for (int32_t j = 0; j < n; ++j) {
      const uint64_t key = vis(row + j);
      idx[j] = uint32_t(key & 0xffffffffu);
      depthBits[j] = uint32_t(key >> 32);
    }
    SpanTriCache cache;
    shadeRow(x0, Y, n, idx, depthBits, cache);
  }

  // The rows of a finished tile of the fused binned raster (shade_stage.cpp):
  // w x h pixels from (tx0, ty0), ids (raster index + 1) and depth bits in
  // rows of `stride`.
  //
  // A triangle's runs on different rows of the tile are shaded together, up
  // to kMaxSpanRun pixels at a time (shadeLanes): the triangles of a dense
  // mesh cover a few pixels of each row, and shading them row by row paid a
  // span's fixed cost and a partly empty vector for each.
  static constexpr int32_t kMaxTileRuns = 1024;
  static constexpr int32_t kBatchRunMax = 16;     // runs from this long are shaded as row spans at once
  KOKKOS_INLINE_FUNCTION void shadeTile(int32_t tx0, int32_t ty0, int32_t w, int32_t h, int32_t stride,
                                        const uint32_t* ib, const uint32_t* zb) const {
    SpanTriCache cache;
    if (w * h > kMaxTileRuns || w > kMaxSpanRun) {
      for (int32_t r = 0; r < h; ++r) shadeRow(tx0, ty0 + r, w, ib + r * stride, zb + r * stride, cache);
      return;
    }
    // Rows: ids, depth, background and lines at once; triangles' runs listed.
    uint32_t runId[kMaxTileRuns];
    int32_t runAt[kMaxTileRuns];  // row in the tile << 16 | column
    int32_t runLen[kMaxTileRuns];
    int32_t nr = 0;
    for (int32_t r = 0; r < h; ++r) {
      const int32_t Y = ty0 + r;
      const int64_t row = int64_t(Y) * width + tx0;
      const uint32_t* idx = ib + r * stride;
      const uint32_t* depthBits = zb + r * stride;
      if (p.wantDepth)
        for (int32_t j = 0; j < w; ++j) depthOut(row + j) = bitsFloat(depthBits[j]);
      if (p.wantPrimId)
        for (int32_t j = 0; j < w; ++j) {
          const uint32_t id = idx[j];
          primOut(row + j) = id == 0 ? 0 : (id - 1) & kLineFlag ? lineShade.primId((id - 1) & ~kLineFlag) : tris(id - 1).prim + 1;
        }
      for (uint64_t starts = runStarts(idx, w); starts;) {
        const int32_t j = lowestBit(starts);
        starts &= starts - 1;
        const int32_t k = starts ? lowestBit(starts) : w;
        const uint32_t id = idx[j];
        if (id == 0) {
          if (p.floatOut) {
            for (int32_t m = j; m < k; ++m) hdr(row + m) = p.backgroundFilm;
          } else {
            uint32_t* const dst = color.data() + row;
            const uint32_t bg = p.backgroundPacked;
            for (int32_t m = j; m < k; ++m) dst[m] = bg;
          }
        } else if ((id - 1) & kLineFlag) {
          SpanTri& st = lookup(id - 1, cache);
          for (int32_t m = j; m < k; ++m) put(row + m, shadeFragment(st.f, tx0 + m, Y, 0, 0, 0.0f, nullptr));
        } else if (k - j >= kBatchRunMax) {  // a long run is a full vector by itself
          span(lookup(id - 1, cache), row + j, tx0 + j, Y, k - j);
        } else {
          runId[nr] = id;
          runAt[nr] = r << 16 | j;
          runLen[nr] = k - j;
          ++nr;
        }
      }
    }
    // Each run chained to the next run of its triangle (runNext, -1: none)
    // through a small open-addressing table from id to its latest run, so that
    // a batch follows its triangle's runs instead of searching for them.
    int32_t runNext[kMaxTileRuns];
    {
      uint32_t hKey[2 * kMaxTileRuns];  // 0: empty (background is never a run here)
      int32_t hLast[2 * kMaxTileRuns];
      int32_t bits = 6;  // at least twice as many slots as runs
      while ((1 << bits) < 2 * nr) ++bits;
      const uint32_t mask = (1u << bits) - 1u;
      for (uint32_t i = 0; i <= mask; ++i) hKey[i] = 0;
      for (int32_t t = 0; t < nr; ++t) {
        const uint32_t id = runId[t];
        uint32_t h = (id * 0x9E3779B1u) >> (32 - bits);  // Fibonacci hashing: the product's top bits
        while (hKey[h] != 0 && hKey[h] != id) h = (h + 1) & mask;
        if (hKey[h] == id) runNext[hLast[h]] = t;
        else hKey[h] = id;
        hLast[h] = t;
        runNext[t] = -1;
      }
    }
    // Batches of one triangle's runs, in the order their first runs appear:
    // a batch takes runs along the chain while they fit in kMaxSpanRun lanes;
    // the rest start a later batch when the scan reaches them.
    // Each lane is a pixel's coordinates: its edge values are evaluated in the
    // vector loop (spanLightingLanes), nothing per run but its pixels' places.
    int32_t laneX[kMaxSpanRun], laneY[kMaxSpanRun];
    for (int32_t q = 0; q < nr; ++q) {
      if (runLen[q] == 0) continue;  // already shaded in an earlier batch
      const uint32_t id = runId[q];
      SpanTri& st = lookup(id - 1, cache);
      int32_t m = 0;
      for (int32_t t = q; t >= 0; t = runNext[t]) {
        const int32_t len = runLen[t];
        if (m + len > kMaxSpanRun) break;
        const int32_t X = tx0 + (runAt[t] & 0xffff), Y = ty0 + (runAt[t] >> 16);
        for (int32_t i = 0; i < len; ++i) {
          laneX[m + i] = X + i;
          laneY[m + i] = Y;
        }
        m += len;
        runLen[t] = 0;
      }
      for (int32_t i = m; i < spanBlocks(m); ++i) {  // the last block's spare lanes: a pixel of the batch
        laneX[i] = laneX[0];
        laneY[i] = laneY[0];
      }
      shadeLanes(st, m, 0, laneX, laneY);
    }
  }

  // A tile no triangle touches: background, and the cleared depth and ids
  // (what shadeRow gives for ids 0 and depth bits of kClearKey).
  KOKKOS_INLINE_FUNCTION void shadeEmpty(int32_t tx0, int32_t ty0, int32_t w, int32_t h) const {
    for (int32_t r = 0; r < h; ++r) {
      const int64_t row = int64_t(ty0 + r) * width + tx0;
      if (p.wantDepth)
        for (int32_t j = 0; j < w; ++j) depthOut(row + j) = bitsFloat(uint32_t(kClearKey >> 32));
      if (p.wantPrimId)
        for (int32_t j = 0; j < w; ++j) primOut(row + j) = 0;
      if (p.floatOut) {
        for (int32_t j = 0; j < w; ++j) hdr(row + j) = p.backgroundFilm;
      } else {
        uint32_t* const dst = color.data() + row;
        const uint32_t bg = p.backgroundPacked;
        for (int32_t j = 0; j < w; ++j) dst[j] = bg;
      }
    }
  }

  // The cached SpanTri of raster triangle `index`, prepared on a miss.
  // spanConsts: with k and tex too (a batch's lanes need only f).
  // Forced inline: it runs once per span, and GCC outlined it (with a call
  // per span) once the span kernels had a file of their own (callgrind on
  // duck's fused tiles: 5% more instructions).
  KOKKOS_FORCEINLINE_FUNCTION SpanTri& lookup(uint32_t index, SpanTriCache& c, bool spanConsts = true) const {
    for (int s = 0; s < SpanTriCache::kSlots; ++s)
      if (c.key[s] == index) {
        SpanTri& st = c.slot[s];
        if (spanConsts && !st.spanReady && !(index & kLineFlag)) prepareSpan(st);
        return st;
      }
    c.key[c.next] = index;
    SpanTri& st = c.slot[c.next];
    c.next = c.next + 1 < SpanTriCache::kSlots ? c.next + 1 : 0;
    prepare(index, st.f);
    st.spanReady = 0;
    if (spanConsts && !(index & kLineFlag)) prepareSpan(st);
    return st;
  }

  // The per-triangle part of span(): spanLighting's constants and the texture's.
  KOKKOS_INLINE_FUNCTION void prepareSpan(SpanTri& st) const {
    st.spanReady = 1;
    const TriFrag& f = st.f;
    fillSpanConsts(st.k, f, 0, 0, p.perspective != 0, p.frame(0).camera.eye, p.ambient,
                   p.headlight ? 1.0f - p.ambient : 0.0f);
    if (f.textured) {
      SpanTex& x = st.tex;
      x.texels = texels.data() + f.tex.offset;
      x.lut = lut.data();
      x.width = f.tex.width;
      x.height = f.tex.height;
      x.wrapS = f.tex.wrapS;
      x.wrapT = f.tex.wrapT;
      x.indexable = int64_t(x.width) * int64_t(x.height) < (int64_t(1) << 31);
      x.u0 = f.uv[0].x; x.u1 = f.uv[1].x; x.u2 = f.uv[2].x;
      x.v0 = f.uv[0].y; x.v1 = f.uv[1].y; x.v2 = f.uv[2].y;
    }
  }

  // Pixels [x0, x0 + n) of row Y, given the visibility keys' halves: raster
  // index + 1 (0: none) and depth bits.
  KOKKOS_INLINE_FUNCTION void shadeRow(int32_t x0, int32_t Y, int32_t n, const uint32_t* idx,
                                       const uint32_t* depthBits, SpanTriCache& cache) const {
    const int64_t row = int64_t(Y) * width + x0;
    if (p.wantDepth)
      for (int32_t j = 0; j < n; ++j) depthOut(row + j) = bitsFloat(depthBits[j]);
    if (p.wantPrimId)
      for (int32_t j = 0; j < n; ++j) {
        const uint32_t id = idx[j];
        primOut(row + j) = id == 0 ? 0 : (id - 1) & kLineFlag ? lineShade.primId((id - 1) & ~kLineFlag) : tris(id - 1).prim + 1;
      }
    // Runs found kRunMaskBits pixels at a time (runStarts); a run across a
    // boundary becomes two spans, which shade the same pixels alike. Short
    // runs of untextured triangles go to a batch, shaded last (n <=
    // kMaxSpanRun: one batch holds them all).
    LaneBatch batch;
    for (int32_t base = 0; base < n; base += kRunMaskBits) {
      const int32_t end = n - base < kRunMaskBits ? n : base + kRunMaskBits;
      for (uint64_t starts = runStarts(idx + base, end - base); starts;) {
        const int32_t j = base + lowestBit(starts);
        starts &= starts - 1;
        const int32_t k = starts ? base + lowestBit(starts) : end;
        const uint32_t id = idx[j];
        if (id == 0) {
          if (p.floatOut) {
            for (int32_t m = j; m < k; ++m) hdr(row + m) = p.backgroundFilm;
          } else {
            uint32_t* const dst = color.data() + row;  // a plain fill the compiler vectorizes
            const uint32_t bg = p.backgroundPacked;
            for (int32_t m = j; m < k; ++m) dst[m] = bg;
          }
        } else if ((id - 1) & kLineFlag) {
          SpanTri& st = lookup(id - 1, cache);
          for (int32_t m = j; m < k; ++m) put(row + m, shadeFragment(st.f, x0 + m, Y, 0, 0, 0.0f, nullptr));
        } else if (k - j < kLaneRunMax) {
          SpanTri& st = lookup(id - 1, cache, false);
          if (st.f.textured) {
            span(lookup(id - 1, cache), row + j, x0 + j, Y, k - j);
          } else {
            if (batch.m + (k - j) > kMaxSpanRun) shadeBatch(batch, int64_t(Y) * width, Y);  // rows of a wide tile
            addLanes(batch, st.f, x0 + j, Y, k - j);
          }
        } else {
          span(lookup(id - 1, cache), row + j, x0 + j, Y, k - j);
        }
      }
    }
    if (batch.m) shadeBatch(batch, int64_t(Y) * width, Y);
  }

  // The scene's directional lights (without the headlight) added to the
  // diffuse terms of mb lanes, given their normals.
  KOKKOS_INLINE_FUNCTION void addLights(int32_t mb, const float* nx, const float* ny, const float* nz,
                                        float* diffuse) const;

  // Pixels [xa, xa + len) of row Y, of triangle f, as lanes of the batch.
  KOKKOS_INLINE_FUNCTION void addLanes(LaneBatch& L, const TriFrag& f, int32_t xa, int32_t Y, int32_t len) const;

  // The batch's pixels of row Y (rowStart: its first pixel's index): as
  // shadeLanes, each lane with its own triangle's constants.
  KOKKOS_INLINE_FUNCTION void shadeBatch(LaneBatch& L, int64_t rowStart, int32_t Y) const;  // empties it

  // Pixels [xa, xa + m) of row Y, all of st's triangle (a raster triangle).
  KOKKOS_INLINE_FUNCTION void span(SpanTri& st, int64_t out, int32_t xa, int32_t Y, int32_t m) const;

  // m pixels of st's triangle: a row span from pixel `out` on (X null), or
  // any pixels, given by their coordinates (X, Y; whole blocks of them).
  KOKKOS_INLINE_FUNCTION void shadeLanes(SpanTri& st, int32_t m, int64_t out, const int32_t* X,
                                         const int32_t* Y) const;

  // The base colour times the texture at each pixel of the span (weights b0..b2).
  // m pixels, mb lanes (as in span()).
  KOKKOS_INLINE_FUNCTION void texture(const SpanTri& st, int32_t m, int32_t mb, const float* b0, const float* b1,
                                      const float* b2, float* br, float* bg, float* bb, float* ba) const;
};

}  // namespace shading
}  // namespace rast

#include "pipeline/cpu/span_lanes.h"
