// The binned method's pieces that another stage reuses: the tile grid, the
// binning (per-tile lists of raster triangles in primitive order), and the
// host backends' fine stage, which hands each finished tile (depth bits and
// ids, in cache) to a sink: the visibility buffer (VisSink), or on the CPU the
// shade stage directly (shade_stage.cpp), so that a frame needs no full-screen
// visibility buffer written and read back.
#pragma once

#include "backends/cpu_clones.h"
#include "pipeline/data/frame_buffers.h"
#include "pipeline/rules/raster_rules.h"

namespace rast {

constexpr int kTileShift = 5;  // 32x32-pixel tiles
constexpr int kTileSize = 1 << kTileShift;
constexpr int kTilePixels = kTileSize * kTileSize;

struct BinGeometry {
  int32_t tilesX, tilesY;
  uint32_t batches, trisPerBatch, triSlots;

  KOKKOS_INLINE_FUNCTION uint32_t numTiles() const { return uint32_t(tilesX) * uint32_t(tilesY); }
};

// The entries [begin, end) of `tile`'s list in the binned work array,
// clamped to the entries binning wrote: a frame that overflowed the array
// (counters(kRasterWork) > capacity) keeps what fit, and grows for the next.
struct TileEntries {
  uint32_t begin, end;
};
KOKKOS_INLINE_FUNCTION TileEntries tileEntries(const DView<uint32_t>& tileStart, const DView<uint32_t>& counters,
                                               uint32_t capacity, uint32_t tile) {
  const uint32_t total = counters(kRasterWork) < capacity ? counters(kRasterWork) : capacity;
  const uint32_t begin = tileStart(tile) < total ? tileStart(tile) : total;
  const uint32_t end = tileStart(tile + 1) < total ? tileStart(tile + 1) : total;
  return {begin, end};
}

// Bins the raster triangles to tiles: f.tileStart, f.work (the lists) and
// f.counters(kRasterWork).
BinGeometry binTriangles(FrameBuffers& f);

// Depth-tests one row span of a triangle in a host tile (FineRasterHost):
// depthAt over the span, vectorized, and the tile's depth bits and ids kept
// where it is nearer.
// The loop runs over whole blocks of kDepthBlock pixels, the lanes past the
// span's end keeping what they hold (the tile's arrays have room for a block
// past their last row), so that a short span is one vector, not a scalar
// remainder loop.
constexpr int kDepthBlock = 8;
KOKKOS_FORCEINLINE_FUNCTION void depthSpan(int32_t m, double s0, double s2, double a0, double a2, float z0, float dz1, float dz2,
                               float ia, uint32_t id, uint32_t* __restrict__ zr, uint32_t* __restrict__ ir) {
  const int32_t mb = (m + kDepthBlock - 1) & ~(kDepthBlock - 1);
  for (int32_t j = 0; j < mb; ++j) {
    // depthAt(t, e0, e1, e2): l1 from edge 2, l2 from edge 0
    const float l1 = float(s2 + a2 * double(j)) * ia, l2 = float(s0 + a0 * double(j)) * ia;
    const uint32_t bits = floatBits(clamp01(z0 + (l1 * dz1 + l2 * dz2)));
    const bool win = (bits < zr[j]) & (j < m);
    zr[j] = win ? bits : zr[j];
    ir[j] = win ? id : ir[j];
  }
}

// The same, built also for AVX-512 and AVX2; worth its indirect call on longer spans.
RAST_CPU_CLONES void depthSpanWide(int32_t m, double s0, double s2, double a0, double a2, float z0, float dz1,
                                   float dz2, float ia, uint32_t id, uint32_t* __restrict__ zr,
                                   uint32_t* __restrict__ ir) {
  depthSpan(m, s0, s2, a0, a2, z0, dz1, dz2, ia, id, zr, ir);
}

// A triangle whose box within a tile is at most kDepthBlock pixels wide
// (most triangles of a dense mesh): its rows' coverage as a mask over one
// block per row, from the edge values stepped exactly in double (integers
// below 2^53, as in depthSpan), instead of each row's span found by
// division. e0..e2: the unbiased edge values at (x0, y0); bias0..2 the
// edges' top-left biases (inside: e + bias > 0); n: the box's width. The
// same depth bits as depthSpan for every covered pixel.
KOKKOS_FORCEINLINE_FUNCTION void depthBox(int32_t rows, int32_t n, double e0, double e1, double e2, double a0, double a1,
                                          double a2, double b0, double b1, double b2, double bias0, double bias1,
                                          double bias2, float z0, float dz1, float dz2, float ia, uint32_t id,
                                          uint32_t* __restrict__ zr, uint32_t* __restrict__ ir) {
  for (int32_t r = 0; r < rows; ++r) {
    const double r0 = e0 + b0 * double(r), r1 = e1 + b1 * double(r), r2 = e2 + b2 * double(r);
    uint32_t* __restrict__ zrow = zr + r * kTileSize;
    uint32_t* __restrict__ irow = ir + r * kTileSize;
    for (int32_t j = 0; j < kDepthBlock; ++j) {
      const double f0 = r0 + a0 * double(j), f1 = r1 + a1 * double(j), f2 = r2 + a2 * double(j);
      const bool in = (f0 + bias0 > 0.0) & (f1 + bias1 > 0.0) & (f2 + bias2 > 0.0) & (j < n);
      const float l1 = float(f2) * ia, l2 = float(f0) * ia;  // depthAt: l1 from edge 2, l2 from edge 0
      const uint32_t bits = floatBits(clamp01(z0 + (l1 * dz1 + l2 * dz2)));
      const bool win = in & (bits < zrow[j]);
      zrow[j] = win ? bits : zrow[j];
      irow[j] = win ? id : irow[j];
    }
  }
}
RAST_CPU_CLONES void depthBoxWide(int32_t rows, int32_t n, double e0, double e1, double e2, double a0, double a1, double a2,
                                  double b0, double b1, double b2, double bias0, double bias1, double bias2, float z0,
                                  float dz1, float dz2, float ia, uint32_t id, uint32_t* __restrict__ zr,
                                  uint32_t* __restrict__ ir) {
  depthBox(rows, n, e0, e1, e2, a0, a1, a2, b0, b1, b2, bias0, bias1, bias2, z0, dz1, dz2, ia, id, zr, ir);
}

// The fine stage on a host backend with one sample per pixel: one thread per
// tile, the tile's depth bits and ids in two small arrays (on the stack), and
// each triangle walked row by row over exactly the pixels it covers (the
// span where all three edge functions pass, found by integer division, so no
// per-pixel inside test), with the depth interpolated over the span in a
// loop the compiler vectorizes. Bit-identical to FineRaster:
// * edge values step exactly in double (integers below 2^53), and
//   float(double(e)) rounds like float(e), so depthAt gets the same bits;
// * the tile's list is in primitive order, so every stored id is smaller than
//   the incoming one and "key < stored key" reduces to "depth bits < stored
//   depth bits" (equal depths keep the earlier triangle, as visKey's minimum).
template <class Sink>
struct FineRasterHost {
  DView<RasterTri> tris;
  DView<uint32_t> tileStart, list, counters;
  BinGeometry g;
  int32_t width, height;
  uint32_t capacity;
  Sink sink;  // takes each finished tile (VisSink: into the visibility buffer)

  // Offsets [lo, hi] from x0 (at most n - 1) where E(x0 + d) + bias > 0, E
  // stepping by A per pixel; lo > hi when none.
  KOKKOS_INLINE_FUNCTION static void passing(int64_t c, int64_t A, int32_t n, int32_t& lo, int32_t& hi) {
    // c: the biased edge value at d = 0; inside means c + A d > 0.
    if (A == 0) {
      if (c <= 0) hi = -1;
      return;
    }
    // Only an edge that crosses the row needs the division (the row's far end
    // tells): most rows of a large triangle are inside all three edges.
    if (A > 0) {
      if (c <= 0) {
        if (c + A * (n - 1) <= 0) {  // outside over the whole row: d >= n
          lo = n;
          return;
        }
        const int64_t d = (-c) / A + 1;  // smallest d with c + A d > 0
        if (d > lo) lo = d > n ? n : int32_t(d);
      }
    } else {
      if (c <= 0) {
        hi = -1;
        return;
      }
      if (c + A * (n - 1) > 0) return;  // inside over the whole row: d >= n - 1 >= hi
      const int64_t d = (c - 1) / (-A);  // largest d with c + A d > 0
      if (d < hi) hi = int32_t(d);
    }
  }

  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t tile) const {
    const int32_t tx0 = int32_t(tile % uint32_t(g.tilesX)) * kTileSize;
    const int32_t ty0 = int32_t(tile / uint32_t(g.tilesX)) * kTileSize;
    const TileEntries te = tileEntries(tileStart, counters, capacity, tile);
    if (te.begin == te.end) {  // nothing drawn here (most tiles of a sparse frame): no arrays to clear
      sink.emptyTile(tx0, ty0, imin(kTileSize, width - tx0), imin(kTileSize, height - ty0));
      return;
    }
    uint32_t zb[kTilePixels + kDepthBlock], ib[kTilePixels + kDepthBlock];  // + a block: depthSpan's last lanes
    for (int p = 0; p < kTilePixels + kDepthBlock; ++p) {
      zb[p] = uint32_t(kClearKey >> 32);
      ib[p] = 0;
    }
    for (uint32_t k = te.begin; k < te.end; ++k) {
      const uint32_t i = list(k);
      const RasterTri& t = tris(i);
      const int32_t x0 = imax(t.minX, tx0), x1 = imin(t.maxX, tx0 + kTileSize - 1);
      const int32_t y0 = imax(t.minY, ty0), y1 = imin(t.maxY, ty0 + kTileSize - 1);
      const Edges e(t);
      const int32_t n = x1 - x0 + 1;
      const float z0 = t.z[0], dz1 = t.z[1] - t.z[0], dz2 = t.z[2] - t.z[0], ia = t.invArea;
      const double a0 = double(e.A[0]), a2 = double(e.A[2]);
      const uint32_t id = i + 1;
      if (n <= kDepthBlock) {  // a narrow box: coverage masks, no divisions
        if (y1 >= y0) {
          const size_t at = size_t(y0 - ty0) * kTileSize + size_t(x0 - tx0);
          depthBoxWide(y1 - y0 + 1, n, double(e.eval(0, x0, y0)), double(e.eval(1, x0, y0)), double(e.eval(2, x0, y0)),
                       a0, double(e.A[1]), a2, double(e.B[0]), double(e.B[1]), double(e.B[2]), double(e.bias[0]),
                       double(e.bias[1]), double(e.bias[2]), z0, dz1, dz2, ia, id, zb + at, ib + at);
        }
        continue;
      }
      for (int32_t y = y0; y <= y1; ++y) {
        const int64_t c0 = e.eval(0, x0, y), c1 = e.eval(1, x0, y), c2 = e.eval(2, x0, y);
        int32_t lo = 0, hi = n - 1;
        passing(c0 + e.bias[0], e.A[0], n, lo, hi);
        passing(c1 + e.bias[1], e.A[1], n, lo, hi);
        passing(c2 + e.bias[2], e.A[2], n, lo, hi);
        if (lo > hi) continue;
        const double s0 = double(c0 + e.A[0] * lo), s2 = double(c2 + e.A[2] * lo);
        uint32_t* zr = zb + (y - ty0) * kTileSize + (x0 - tx0) + lo;
        uint32_t* ir = ib + (y - ty0) * kTileSize + (x0 - tx0) + lo;
        depthSpanWide(hi - lo + 1, s0, s2, a0, a2, z0, dz1, dz2, ia, id, zr, ir);
      }
    }
    sink.tile(tx0, ty0, imin(kTileSize, width - tx0), imin(kTileSize, height - ty0), zb, ib);
  }
};

// The usual sink: the finished tile into the visibility buffer, as keys
// (emptyTile: a tile no triangle touches).
struct VisSink {
  DView<uint64_t> vis;
  int32_t width;
  KOKKOS_INLINE_FUNCTION void tile(int32_t tx0, int32_t ty0, int32_t w, int32_t h, const uint32_t* zb,
                                   const uint32_t* ib) const {
    for (int r = 0; r < h; ++r)
      for (int c = 0; c < w; ++c)
        vis(int64_t(ty0 + r) * width + tx0 + c) = uint64_t(zb[r * kTileSize + c]) << 32 | ib[r * kTileSize + c];
  }
  KOKKOS_INLINE_FUNCTION void emptyTile(int32_t tx0, int32_t ty0, int32_t w, int32_t h) const {
    for (int r = 0; r < h; ++r)
      for (int c = 0; c < w; ++c) vis(int64_t(ty0 + r) * width + tx0 + c) = kClearKey;
  }
};

}  // namespace rast
