// Sort-middle binned rasterisation (after cudaraster, Laine & Karras 2011):
// raster triangles are binned to 32x32-pixel tiles, then one team per tile
// depth-tests its list in primitive order with the tile's depth held in team
// scratch memory. No atomics anywhere; the fine stage touches global memory
// only to read triangles and to write each finished tile once (which also
// replaces the clear pass).
//
// Binning keeps submission order without sorting: the triangles are cut into
// B contiguous batches; each batch is binned by one work item, sequentially,
// into its own segment of every tile's list; an exclusive scan over the
// (tile, batch) counts in tile-major order lays the segments out so that each
// tile's list is the concatenation of its batches in order. (cudaraster's
// per-CTA bin queues, merged in order by its coarse stage, work the same way.)
#include "pipeline/raster/raster_binned.h"
#include "pipeline/raster/raster.h"
#include "pipeline/data/scan.h"

#include <algorithm>
#include <type_traits>

namespace rast {
namespace {

// Counts, per (tile, batch), the triangles of the batch whose bounding box
// touches the tile.
struct CountBins {
  DView<RasterTri> tris;
  DView<uint32_t> counters, binCount;
  BinGeometry g;
  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t b) const {
    const uint32_t nTri = counters(kRasterTris) < g.triSlots ? counters(kRasterTris) : g.triSlots;
    const uint32_t nt = g.numTiles();
    for (uint32_t t = 0; t < nt; ++t) binCount(t * g.batches + b) = 0;  // own column only
    const uint32_t lo = b * g.trisPerBatch, hi = lo + g.trisPerBatch < nTri ? lo + g.trisPerBatch : nTri;
    for (uint32_t i = lo; i < hi; ++i) {
      const RasterTri& r = tris(i);
      for (int32_t ty = r.minY >> kTileShift; ty <= (r.maxY >> kTileShift); ++ty)
        for (int32_t tx = r.minX >> kTileShift; tx <= (r.maxX >> kTileShift); ++tx)
          ++binCount((uint32_t(ty) * g.tilesX + tx) * g.batches + b);
    }
  }
};

// Writes each batch's triangles into its segments; the scanned counts serve as
// cursors (each (tile, batch) cell belongs to one work item).
struct FillBins {
  DView<RasterTri> tris;
  DView<uint32_t> counters, binCursor, list;
  BinGeometry g;
  uint32_t capacity;
  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t b) const {
    const uint32_t nTri = counters(kRasterTris) < g.triSlots ? counters(kRasterTris) : g.triSlots;
    const uint32_t lo = b * g.trisPerBatch, hi = lo + g.trisPerBatch < nTri ? lo + g.trisPerBatch : nTri;
    for (uint32_t i = lo; i < hi; ++i) {
      const RasterTri& r = tris(i);
      for (int32_t ty = r.minY >> kTileShift; ty <= (r.maxY >> kTileShift); ++ty)
        for (int32_t tx = r.minX >> kTileShift; tx <= (r.maxX >> kTileShift); ++tx) {
          const uint32_t pos = binCursor((uint32_t(ty) * g.tilesX + tx) * g.batches + b)++;
          if (pos < capacity) list(pos) = i;
        }
    }
  }
};

using Member = TeamMember;
using ScratchKeys = Kokkos::View<uint64_t*, Exec::scratch_memory_space, Kokkos::MemoryTraits<Kokkos::Unmanaged>>;

// One team per tile: depth-test the tile's list in order. Each pixel belongs
// to one thread of the team for the whole list, so per-pixel processing order
// is the list order and no atomics are needed.
struct FineRaster {
  DView<RasterTri> tris;
  DView<uint32_t> tileStart, list, counters;
  DView<uint64_t> vis;
  BinGeometry g;
  int32_t width, height;
  uint32_t capacity;
  SamplePattern samples;
  int scratchLevel;

  KOKKOS_INLINE_FUNCTION void operator()(const Member& m) const {
    const uint32_t tile = uint32_t(m.league_rank());
    const int32_t tx0 = int32_t(tile % uint32_t(g.tilesX)) * kTileSize;
    const int32_t ty0 = int32_t(tile / uint32_t(g.tilesX)) * kTileSize;
    const int S = samples.count;
    ScratchKeys depth(m.team_scratch(scratchLevel), kTilePixels * S);
    Kokkos::parallel_for(Kokkos::TeamThreadRange(m, kTilePixels * S), [&](const int p) { depth(p) = kClearKey; });
    m.team_barrier();

    const TileEntries te = tileEntries(tileStart, counters, capacity, tile);
    const int nThreads = m.team_size(), me = m.team_rank();
    for (uint32_t k = te.begin; k < te.end; ++k) {
      const uint32_t i = list(k);
      const RasterTri& t = tris(i);
      const int32_t x0 = imax(t.minX, tx0), x1 = imin(t.maxX, tx0 + kTileSize - 1);
      const int32_t y0 = imax(t.minY, ty0), y1 = imin(t.maxY, ty0 + kTileSize - 1);
      const Edges e(t);
      if (S > 1) {
        // Multisampling: each sample of a pixel follows the rules at its position.
        for (int p = me; p < kTilePixels; p += nThreads) {
          const int32_t x = tx0 + (p & (kTileSize - 1)), y = ty0 + (p >> kTileShift);
          if (x < x0 || x > x1 || y < y0 || y > y1) continue;
          const int64_t c0 = e.eval(0, x, y), c1 = e.eval(1, x, y), c2 = e.eval(2, x, y);
          for (int s = 0; s < S; ++s) {
            const int64_t e0 = e.atSample(0, c0, samples.ox[s], samples.oy[s]);
            const int64_t e1 = e.atSample(1, c1, samples.ox[s], samples.oy[s]);
            const int64_t e2 = e.atSample(2, c2, samples.ox[s], samples.oy[s]);
            if (e.inside(e0, e1, e2)) {
              const uint64_t key = visKey(depthAt(t, e0, e1, e2), i);
              if (key < depth(p * S + s)) depth(p * S + s) = key;
            }
          }
        }
      } else if (nThreads == 1) {
        // One thread (host backends): walk the rectangle with incremental edges.
        for (int32_t y = y0; y <= y1; ++y) {
          int64_t e0 = e.eval(0, x0, y), e1 = e.eval(1, x0, y), e2 = e.eval(2, x0, y);
          uint64_t* row = &depth((y - ty0) * kTileSize);
          for (int32_t x = x0; x <= x1; ++x) {
            if (e.inside(e0, e1, e2)) {
              const uint64_t key = visKey(depthAt(t, e0, e1, e2), i);
              if (key < row[x - tx0]) row[x - tx0] = key;
            }
            e0 += e.A[0];
            e1 += e.A[1];
            e2 += e.A[2];
          }
        }
      } else {
        for (int p = me; p < kTilePixels; p += nThreads) {
          const int32_t x = tx0 + (p & (kTileSize - 1)), y = ty0 + (p >> kTileShift);
          if (x < x0 || x > x1 || y < y0 || y > y1) continue;
          const int64_t e0 = e.eval(0, x, y), e1 = e.eval(1, x, y), e2 = e.eval(2, x, y);
          if (e.inside(e0, e1, e2)) {
            const uint64_t key = visKey(depthAt(t, e0, e1, e2), i);
            if (key < depth(p)) depth(p) = key;
          }
        }
      }
    }
    m.team_barrier();
    Kokkos::parallel_for(Kokkos::TeamThreadRange(m, kTilePixels * S), [&](const int q) {
      const int p = q / S;
      const int32_t x = tx0 + (p & (kTileSize - 1)), y = ty0 + (p >> kTileShift);
      if (x < width && y < height) vis((int64_t(y) * width + x) * S + q % S) = depth(q);
    });
  }
};

}  // namespace

// The host fine stage (FineRasterHost) is compiled only for host backends.
template <bool kHost>
static void launchFine(FrameBuffers& f, const BinGeometry& g) {
  if constexpr (kHost) {
    using Host = std::conditional_t<kHost, FineRasterHost<VisSink>, void>;  // dependent: not built for GPUs
    if (f.vp.samples.count == 1 && kTeamSize == 1) {
      // Tiles cost what they hold (background is cheap): handed out dynamically.
      using Policy = Kokkos::RangePolicy<Exec, Kokkos::Schedule<Kokkos::Dynamic>, Kokkos::IndexType<uint32_t>>;
      Kokkos::parallel_for("rast::raster::binned::fine_host", Policy(0, g.numTiles()),
                           Host{f.tris, f.tileStart, f.work, f.counters, g, f.vp.width, f.vp.height, f.workCapacity,
                                VisSink{f.vis, f.vp.width}});
      return;
    }
  }
  const int teamSize = kTeamSize;
  // The tile's keys live in team scratch; with many samples they outgrow fast
  // on-chip memory (level 0) and go to level 1 (global, still private to the team).
  const size_t scratch = ScratchKeys::shmem_size(size_t(kTilePixels) * f.vp.samples.count);
  const int level = scratch <= kFastScratchBytes ? 0 : 1;
  Kokkos::parallel_for("rast::raster::binned::fine",
                       TeamPolicy(int(g.numTiles()), teamSize).set_scratch_size(level, Kokkos::PerTeam(scratch)),
                       FineRaster{f.tris, f.tileStart, f.work, f.counters, f.vis, g, f.vp.width, f.vp.height,
                                  f.workCapacity, f.vp.samples, level});
}

BinGeometry binTriangles(FrameBuffers& f) {
  BinGeometry g;
  g.tilesX = (f.vp.width + kTileSize - 1) / kTileSize;
  g.tilesY = (f.vp.height + kTileSize - 1) / kTileSize;
  g.triSlots = f.triCapacity;
  // Enough batches to keep every core (or a good part of a GPU) busy, few
  // enough that the (tile, batch) count table stays small.
  const uint32_t maxBatches = binBatchLimit();
  g.batches = std::max(1u, std::min(maxBatches, (f.triCapacity + 31) / 32));
  g.trisPerBatch = (f.triCapacity + g.batches - 1) / g.batches;
  const uint32_t cells = g.numTiles() * g.batches;

  ensureCapacity(f.workOffset, "frame.binCounts", size_t(cells) + 1);
  ensureCapacity(f.tileStart, "frame.tileStart", size_t(g.numTiles()) + 1);
  if (f.workCapacity == 0) f.workCapacity = f.triCapacity * 2 + g.numTiles();
  ensureCapacity(f.work, "frame.binList", f.workCapacity);

  using Policy = Kokkos::RangePolicy<Exec, Kokkos::IndexType<uint32_t>>;
  Kokkos::parallel_for("rast::raster::binned::count", Policy(0, g.batches), CountBins{f.tris, f.counters, f.workOffset, g});
  scanExclusive("rast::raster::binned::scan", f.workOffset, cells, f.counters, kRasterWork);
  {
    auto start = f.tileStart;
    auto offs = f.workOffset;
    auto counters = f.counters;
    const uint32_t nt = g.numTiles(), B = g.batches;
    Kokkos::parallel_for("rast::raster::binned::tile_start", Policy(0, nt + 1), KOKKOS_LAMBDA(const uint32_t t) {
      start(t) = t < nt ? offs(t * B) : counters(kRasterWork);
    });
  }
  Kokkos::parallel_for("rast::raster::binned::fill", Policy(0, g.batches),
                       FillBins{f.tris, f.counters, f.workOffset, f.work, g, f.workCapacity});
  return g;
}

void rasterBinned(FrameBuffers& f) {
  const BinGeometry g = binTriangles(f);
  launchFine<!kOnDevice>(f, g);
}

}  // namespace rast
