// Visibility-buffer rasterisation with bounded work items: each raster
// triangle's bounding box is cut along a fixed 8x8-pixel grid, and every
// (triangle, block) pair is one work item. A full-screen triangle becomes
// thousands of small items instead of one thread walking two million pixels;
// a sub-pixel triangle is one item. Depth is resolved by the 64-bit atomic
// minimum of visKey, so the result does not depend on scheduling.
//
// Seen from inside a dense model, most (triangle, block) items lie behind
// walls drawn earlier. Each 8x8 block keeps a bound on the depth of all its
// pixels (f.blockDepth, float bits): an item whose triangle cannot come
// nearer than the bound is skipped whole. An item whose rectangle is the whole
// block lowers the bound to the farthest depth it left there, from the keys
// it read and its own (keys only decrease, so that holds from then on): the
// block's bound tightens as triangles fill it, not only when one covers it.
// The bound only ever holds for every pixel, so a skipped item is one whose
// every fragment would lose its depth test: the keys are those of the full
// pass, whatever the order items run in. (Single-sample frames only.)
#include "raster_common.h"
#include "stages.h"

#include <algorithm>

namespace rast {
namespace {

constexpr int kBlockShift = 3;  // 8x8 pixel blocks

KOKKOS_INLINE_FUNCTION uint32_t blocksOf(const RasterTri& t, uint32_t& bw) {
  bw = uint32_t((t.maxX >> kBlockShift) - (t.minX >> kBlockShift) + 1);
  const uint32_t bh = uint32_t((t.maxY >> kBlockShift) - (t.minY >> kBlockShift) + 1);
  return bw * bh;
}

constexpr uint32_t kFarBits = 0x3f800000u;  // depth 1.0: the clear value's

// Per raster triangle, its number of blocks, summed into the exclusive offsets
// of its items (blockStart) and the total (counters(kRasterWork)) in one scan:
// counting inside the scan saves a kernel launch, which costs more than
// reading the bounding boxes twice. The same items reset the block depth
// bounds for this frame (the range covers both; the raster kernel runs after).
struct ScanBlocks {
  DView<RasterTri> tris;
  DView<uint32_t> counters, blockStart, blockDepth;
  uint32_t capacity, numBlocks, n;
  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t i, uint32_t& upd, const bool final) const {
    const uint32_t nt = counters(kRasterTris) < capacity ? counters(kRasterTris) : capacity;
    uint32_t bw;
    const uint32_t b = i < nt ? blocksOf(tris(i), bw) : 0u;
    if (final) {
      if (i < capacity) blockStart(i) = upd;
      if (i < numBlocks) blockDepth(i) = kFarBits;
      if (i + 1 == n) counters(kRasterWork) = upd + b;
    }
    upd += b;
  }
};

// Grid-stride loop over the work items: their number is only known on the
// device, so the launch is sized to fill the machine instead.
struct RasterBlocks {
  DView<RasterTri> tris;
  DView<uint32_t> counters, blockStart, blockDepth;
  DView<uint64_t> vis;
  int32_t width, blocksPerRow;
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
      if (samples.count > 1) {
        rasterRect(t, Edges(t), i, x0, x1, y0, y1, vis.data(), width, samples);
        continue;
      }
      const Edges e(t);
      if (rectOutside(e, x0, x1, y0, y1)) continue;  // the block is in the box, not in the triangle
      const uint32_t b = uint32_t(by) * uint32_t(blocksPerRow) + uint32_t(bx);
      const DepthBounds z = depthBounds(t);
      if (floatBits(z.lo) > blockDepth(b)) continue;  // behind every pixel of the block
      const RectResult r = rasterRect(t, e, i, x0, x1, y0, y1, vis.data(), width, samples);
      // Whole blocks only: the bound must hold for all 64 pixels.
      const bool whole = x1 - x0 == (1 << kBlockShift) - 1 && y1 - y0 == (1 << kBlockShift) - 1;
      if (whole && r.maxDepthBits < blockDepth(b)) Kokkos::atomic_fetch_min(&blockDepth(b), r.maxDepthBits);
    }
  }
};

}  // namespace

void rasterVisBuffer(FrameBuffers& f) {
  ensureCapacity(f.workOffset, "frame.workOffset", f.triCapacity);
  const int32_t bx = (f.vp.width + (1 << kBlockShift) - 1) >> kBlockShift;
  const int32_t by = (f.vp.height + (1 << kBlockShift) - 1) >> kBlockShift;
  const uint32_t numBlocks = uint32_t(bx) * uint32_t(by);
  ensureCapacity(f.blockDepth, "frame.blockDepth", numBlocks);
  using Policy = Kokkos::RangePolicy<Exec, Kokkos::IndexType<uint32_t>>;
  const uint32_t n = std::max(f.triCapacity, numBlocks);
  Kokkos::parallel_scan("rast::raster::visbuffer::scan", Policy(0, n),
                        ScanBlocks{f.tris, f.counters, f.workOffset, f.blockDepth, f.triCapacity, numBlocks, n});
  const uint32_t threads = persistentThreads();
  Kokkos::parallel_for("rast::raster::visbuffer::blocks", lightweight(Policy(0, threads)),
                       RasterBlocks{f.tris, f.counters, f.workOffset, f.blockDepth, f.vis, f.vp.width, bx, f.triCapacity,
                                    threads, f.vp.samples});
}

}  // namespace rast
