// The naive baseline: one work item per raster triangle walks its whole
// bounding box. Kept on purpose as the reference point for the other methods:
// it is fast for small triangles and collapses on large ones, where a single
// thread walks millions of pixels while the others idle.
#include "pipeline/rules/raster_rules.h"
#include "pipeline/rules/visbuffer_blocks.h"
#include "pipeline/raster/raster.h"

namespace rast {
namespace {

// With one sample per pixel, a triangle that wrote keys tags the 8x8 blocks
// of its box with the frame (FrameBuffers::blockFrame), as the visbuffer raster
// does, so that shading reads no keys elsewhere. A box may tag a block it
// wrote nothing in: shading then reads clear keys there, nothing worse. The
// boxes auto gives this method are at most one block's area: a few stores.
struct NaiveRaster {
  DView<RasterTri> tris;
  DView<uint32_t> counters;
  DView<uint64_t> vis;
  int32_t width;
  uint32_t capacity;
  SamplePattern samples;
  DView<uint32_t> blockFrame;  // written when tagBlocks
  DView<FrameUniforms> frame;
  int32_t blocksPerRow, tagBlocks;
  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t i) const {
    const uint32_t n = counters(kRasterTris) < capacity ? counters(kRasterTris) : capacity;
    if (i >= n) return;
    const RasterTri& t = tris(i);
    const RectResult r = rasterRect(t, Edges(t), i, t.minX, t.maxX, t.minY, t.maxY, vis.data(), width, samples);
    if (!tagBlocks || r.covered == 0) return;
    const uint32_t thisFrame = frame(0).frame;
    for (int32_t by = t.minY >> kVisBlockShift; by <= t.maxY >> kVisBlockShift; ++by)
      for (int32_t bx = t.minX >> kVisBlockShift; bx <= t.maxX >> kVisBlockShift; ++bx)
        blockFrame(uint32_t(by) * uint32_t(blocksPerRow) + uint32_t(bx)) = thisFrame;  // every writer stores the same value
  }
};

}  // namespace

void rasterNaive(FrameBuffers& f) {
  int32_t bx = 0;
  const bool tag = f.vp.samples.count == 1;
  if (tag) ensureCapacity(f.blockFrame, "frame.blockFrame", visBlocks(f.vp, bx));  // stale tags only make shading read clear keys
  // One work item per triangle slot; slots past the device-side count return at once.
  Kokkos::parallel_for("rast::raster::naive", Kokkos::RangePolicy<Exec, Kokkos::IndexType<uint32_t>>(0, f.triCapacity),
                       NaiveRaster{f.tris, f.counters, f.vis, f.vp.width, f.triCapacity, f.vp.samples, f.blockFrame,
                                   f.uniforms, bx, tag ? 1 : 0});
}

void clearVisibility(FrameBuffers& f) {
  if (f.visClear) return;  // the last shading pass left it clear
  auto vis = f.vis;
  Kokkos::parallel_for("rast::raster::clear", Range(0, int64_t(f.vp.width) * f.vp.height * f.vp.samples.count),
                       KOKKOS_LAMBDA(const int64_t i) { vis(i) = kClearKey; });
}

}  // namespace rast

namespace rast {
namespace {

KOKKOS_INLINE_FUNCTION uint64_t bboxArea(const RasterTri& t) {
  return uint64_t(t.maxX - t.minX + 1) * uint64_t(t.maxY - t.minY + 1);
}

struct AreaSum {
  DView<RasterTri> tris;
  DView<uint32_t> counters;
  uint32_t capacity;
  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t i, uint64_t& sum) const {
    const uint32_t n = counters(kRasterTris) < capacity ? counters(kRasterTris) : capacity;
    if (i < n) sum += bboxArea(tris(i));
  }
};
struct AreaMax {
  DView<RasterTri> tris;
  DView<uint32_t> counters;
  uint32_t capacity;
  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t i, uint64_t& mx) const {
    const uint32_t n = counters(kRasterTris) < capacity ? counters(kRasterTris) : capacity;
    if (i < n && bboxArea(tris(i)) > mx) mx = bboxArea(tris(i));
  }
};

// The area in pixels of the occluder candidates (visbuffer_blocks.h) inside the
// viewport: how much of the frame large triangles cover, layers counted
// (RasterMethod::Auto turns the occluder pass on when it is several frames'
// worth). MASK and BLEND triangles are no candidates (the occluder pass skips
// their empty boxes): counted, eight full-screen BLEND layers over one opaque
// quad turned the pass on for nothing (its bounds, and the block layout instead
// of the rows: 0.072 against 0.041 ms of raster on the H100). Clipped to the
// viewport, since a triangle cut at the near plane reaches far beyond it
// (bigtri's two pieces: 2,000 frames' area unclipped).
KOKKOS_INLINE_FUNCTION float areaInViewport(const RasterTri& t, float w, float h) {
  // Sutherland-Hodgman against x >= 0, x <= w, y >= 0, y <= h (in pixels).
  float px[9], py[9], qx[9], qy[9];
  int n = 3;
  for (int i = 0; i < 3; ++i) {
    px[i] = float(t.x[i]) * (1.0f / float(kSubOne));
    py[i] = float(t.y[i]) * (1.0f / float(kSubOne));
  }
  for (int plane = 0; plane < 4; ++plane) {
    int m = 0;
    for (int i = 0; i < n; ++i) {
      const int j = i + 1 == n ? 0 : i + 1;
      const float vi = plane == 0 ? px[i] : plane == 1 ? w - px[i] : plane == 2 ? py[i] : h - py[i];
      const float vj = plane == 0 ? px[j] : plane == 1 ? w - px[j] : plane == 2 ? py[j] : h - py[j];
      if (vi >= 0.0f) {
        qx[m] = px[i];
        qy[m] = py[i];
        ++m;
      }
      if ((vi >= 0.0f) != (vj >= 0.0f)) {
        const float a = vi / (vi - vj);
        qx[m] = px[i] + a * (px[j] - px[i]);
        qy[m] = py[i] + a * (py[j] - py[i]);
        ++m;
      }
    }
    n = m;
    for (int i = 0; i < n; ++i) {
      px[i] = qx[i];
      py[i] = qy[i];
    }
  }
  float twice = 0.0f;
  for (int i = 0; i < n; ++i) {
    const int j = i + 1 == n ? 0 : i + 1;
    twice += px[i] * py[j] - px[j] * py[i];
  }
  return 0.5f * (twice < 0.0f ? -twice : twice);
}
struct OccluderArea {
  DView<RasterTri> tris;
  DView<uint32_t> counters;
  uint32_t capacity;
  float width, height;
  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t i, uint64_t& sum) const {
    const uint32_t n = counters(kRasterTris) < capacity ? counters(kRasterTris) : capacity;
    if (i < n && alphaClassOf(tris(i)) == kAlphaOpaque && occluderCandidate(tris(i)))
      sum += uint64_t(areaInViewport(tris(i), width, height));
  }
};

}  // namespace

void rasterStatistics(FrameBuffers& f) {
  if (!f.sumArea.data()) {
    f.sumArea = allocScalar<uint64_t>("frame.sumArea");
    f.maxArea = allocScalar<uint64_t>("frame.maxArea");
    f.occArea = allocScalar<uint64_t>("frame.occArea");
  }
  using Policy = Kokkos::RangePolicy<Exec, Kokkos::IndexType<uint32_t>>;
  Kokkos::parallel_reduce("rast::raster::stats::area_sum", Policy(0, f.triCapacity),
                          AreaSum{f.tris, f.counters, f.triCapacity}, Kokkos::Sum<uint64_t, Mem>(f.sumArea));
  Kokkos::parallel_reduce("rast::raster::stats::area_max", Policy(0, f.triCapacity),
                          AreaMax{f.tris, f.counters, f.triCapacity}, Kokkos::Max<uint64_t, Mem>(f.maxArea));
  Kokkos::parallel_reduce("rast::raster::stats::occluder_area", Policy(0, f.triCapacity),
                          OccluderArea{f.tris, f.counters, f.triCapacity, float(f.vp.width), float(f.vp.height)},
                          Kokkos::Sum<uint64_t, Mem>(f.occArea));
}

}  // namespace rast
