// Visibility-buffer rasterisation with bounded work items: each raster
// triangle's bounding box is cut along a fixed 8x8-pixel grid, and every
// (triangle, block) pair is one work item. A full-screen triangle becomes
// thousands of small items instead of one thread walking two million pixels;
// a sub-pixel triangle is one item. Depth is resolved by the 64-bit atomic
// minimum of visKey, so the result does not depend on scheduling.
#include "raster_common.h"
#include "stages.h"

namespace rast {
namespace {

constexpr int kBlockShift = 3;  // 8x8 pixel blocks

KOKKOS_INLINE_FUNCTION uint32_t blocksOf(const RasterTri& t, uint32_t& bw) {
  bw = uint32_t((t.maxX >> kBlockShift) - (t.minX >> kBlockShift) + 1);
  const uint32_t bh = uint32_t((t.maxY >> kBlockShift) - (t.minY >> kBlockShift) + 1);
  return bw * bh;
}

struct CountBlocks {
  DView<RasterTri> tris;
  DView<uint32_t> counters, blocks;
  uint32_t capacity;
  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t i) const {
    const uint32_t n = counters(kRasterTris) < capacity ? counters(kRasterTris) : capacity;
    uint32_t bw;
    blocks(i) = i < n ? blocksOf(tris(i), bw) : 0u;
  }
};

// Grid-stride loop over the work items: their number is only known on the
// device, so the launch is sized to fill the machine instead.
struct RasterBlocks {
  DView<RasterTri> tris;
  DView<uint32_t> counters, blockStart;
  DView<uint64_t> vis;
  int32_t width;
  uint32_t numTriSlots, stride;
  SamplePattern samples;
  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t thread) const {
    const uint32_t total = counters(kRasterWork);
    for (uint32_t w = thread; w < total; w += stride) {
      const uint32_t i = findRange(blockStart, numTriSlots, w);
      const RasterTri& t = tris(i);
      uint32_t bw;
      blocksOf(t, bw);
      const uint32_t local = w - blockStart(i);
      const int32_t bx = (t.minX >> kBlockShift) + int32_t(local % bw);
      const int32_t by = (t.minY >> kBlockShift) + int32_t(local / bw);
      const int32_t x0 = imax(t.minX, bx << kBlockShift), x1 = imin(t.maxX, ((bx + 1) << kBlockShift) - 1);
      const int32_t y0 = imax(t.minY, by << kBlockShift), y1 = imin(t.maxY, ((by + 1) << kBlockShift) - 1);
      rasterRect(t, Edges(t), i, x0, x1, y0, y1, vis.data(), width, samples);
    }
  }
};

}  // namespace

void rasterVisBuffer(FrameBuffers& f) {
  ensureCapacity(f.workOffset, "frame.workOffset", f.triCapacity);
  using Policy = Kokkos::RangePolicy<Exec, Kokkos::IndexType<uint32_t>>;
  Kokkos::parallel_for("rast::raster::visbuffer::count", Policy(0, f.triCapacity),
                       CountBlocks{f.tris, f.counters, f.workOffset, f.triCapacity});
  scanExclusive("rast::raster::visbuffer::scan", f.workOffset, f.triCapacity, f.counters, kRasterWork);
  const uint32_t threads = persistentThreads();
  Kokkos::parallel_for("rast::raster::visbuffer::blocks", Policy(0, threads),
                       RasterBlocks{f.tris, f.counters, f.workOffset, f.vis, f.vp.width, f.triCapacity, threads, f.vp.samples});
}

}  // namespace rast
