// Points of the point/line pass (raster_lines.h): each point counts the rows of
// its square inside the viewport; a scan gives each row a work item, and a
// grid-stride loop lights each row (at most 64 pixels), so a large point is
// spread over as many work items as it has rows.
#include "pipeline/data/frame_buffers.h"
#include "pipeline/raster/raster_lines.h"
#include "pipeline/raster/raster.h"
#include "pipeline/data/scan.h"

namespace rast {
namespace {

// Pixels a work item may light directly: a point of up to 8x8 pixels (most
// points) is lit here; a larger one counts its rows for the row kernel.
constexpr int32_t kDirectPixels = 64;

struct CountPointRows {
  LineSource src;
  DView<float4> clip;
  DView<uint32_t> rows;
  DView<uint64_t> vis;
  Viewport vp;
  float gx, gy;
  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t k) const {
    uint32_t a;
    PointRaster r{};
    const bool ok = src.pointItem(k, a) && setupPoint(clip(a), vp, gx, gy, src.pass.size, r);
    const int32_t n = ok ? r.y1 - r.y0 + 1 : 0;
    if (n > 0 && n * (r.x1 - r.x0 + 1) <= kDirectPixels) {
      const uint32_t key = src.pass.pointKey(k);
      for (int32_t Y = r.y0; Y <= r.y1; ++Y)
        for (int32_t X = r.x0; X <= r.x1; ++X) writeLineFragment(vis.data(), vp.width, vp.samples.count, X, Y, r.z, key);
      rows(k) = 0;
      return;
    }
    rows(k) = uint32_t(n);
  }
};

struct RasterPointRows {
  LineSource src;
  DView<float4> clip;
  DView<uint32_t> rowStart, counters;
  DView<uint64_t> vis;
  Viewport vp;
  float gx, gy;
  uint32_t numItems, stride;
  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t thread) const {
    const uint32_t total = counters(1);
    for (uint32_t w = thread; w < total; w += stride) {
      const uint32_t k = findRange(rowStart, numItems, w);
      uint32_t a;
      PointRaster r{};
      if (!src.pointItem(k, a) || !setupPoint(clip(a), vp, gx, gy, src.pass.size, r)) continue;
      if ((r.y1 - r.y0 + 1) * (r.x1 - r.x0 + 1) <= kDirectPixels) continue;  // lit when counted (never reached)
      const uint32_t key = src.pass.pointKey(k);
      const int32_t Y = r.y0 + int32_t(w - rowStart(k));
      for (int32_t X = r.x0; X <= r.x1; ++X) writeLineFragment(vis.data(), vp.width, vp.samples.count, X, Y, r.z, key);
    }
  }
};

}  // namespace

void rasterPointItems(const LineSource& src, FrameBuffers& f) {
  LineFrame& lf = f.lines;
  const uint32_t n = src.pass.pointItems();
  const float gx = guardBand(f.vp.width), gy = guardBand(f.vp.height);
  using Policy = Kokkos::RangePolicy<Exec, Kokkos::IndexType<uint32_t>>;
  ensureCapacity(lf.pointOffset, "frame.lines.pointOffset", n);
  Kokkos::parallel_for("rast::raster::points::count", lightweight(Policy(0, n)), CountPointRows{src, f.clip, lf.pointOffset, f.vis, f.vp, gx, gy});
  scanExclusive("rast::raster::points::scan", lf.pointOffset, n, lf.counters, 1);
  const uint32_t threads = persistentThreads();
  Kokkos::parallel_for("rast::raster::points::rows", lightweight(Policy(0, threads)),
                       RasterPointRows{src, f.clip, lf.pointOffset, lf.counters, f.vis, f.vp, gx, gy, n, threads});
}

}  // namespace rast
