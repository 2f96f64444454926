// The point/line pass: bounded work per item for lines as for triangles. Each
// line item is clipped and snapped and counts its spans of kLineSpan major-axis
// pixels; an exclusive scan gives every span a slot, and a grid-stride loop over
// the spans (a count only the device knows) lights each span's columns, so a
// 4000-pixel line is 125 work items, not one thread's walk. Points go the same
// way, one work item per row of the point's square (raster_points.cpp).
// Fragments enter the visibility buffer with the 64-bit atomic minimum, like
// the triangles', so they depth-test against the frame's triangles and the
// result does not depend on scheduling.
#include "pipeline/raster/raster_lines.h"

#include "pipeline/data/frame_buffers.h"
#include "pipeline/raster/raster.h"
#include "pipeline/data/scan.h"

namespace rast {

void rasterPointItems(const LineSource& src, FrameBuffers& f);  // raster_points.cpp

namespace {

KOKKOS_INLINE_FUNCTION void lightColumns(const LineRaster& r, int32_t p0, int32_t p1, const LinePass& pass, uint32_t key,
                                          uint64_t* vis, const Viewport& vp) {
  lineColumns(r, p0, p1, [&](int32_t X, int32_t Y, float z) {
    writeLineFragment(vis, vp.width, vp.samples.count, X, Y, overlayDepth(pass, key, z), key);
  });
}

// A line of one span (most lines) is lit right here, within the same bound;
// longer lines count their spans for the span kernel.
struct CountLineSpans {
  LineSource src;
  DView<float4> clip;
  DView<uint32_t> spans;
  DView<uint64_t> vis;
  Viewport vp;
  float gx, gy;
  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t k) const {
    uint32_t a, b;
    LineRaster r{};
    const bool ok = src.lineItem(k, a, b) && setupLine(clip(a), clip(b), vp, gx, gy, src.pass.width, r);
    const uint32_t n = ok ? lineSpans(r) : 0u;
    if (n == 1) lightColumns(r, r.lo, r.hi, src.pass, src.pass.lineKey(k), vis.data(), vp);
    spans(k) = n > 1 ? n : 0u;
  }
};

struct RasterLineSpans {
  LineSource src;
  DView<float4> clip;
  DView<uint32_t> spanStart, counters;
  DView<uint64_t> vis;
  Viewport vp;
  float gx, gy;
  uint32_t numItems, stride;
  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t thread) const {
    const uint32_t total = counters(0);
    for (uint32_t w = thread; w < total; w += stride) {
      const uint32_t k = findRange(spanStart, numItems, w);
      uint32_t a, b;
      LineRaster r{};
      // The same bits as when counting, so this always succeeds.
      if (!src.lineItem(k, a, b) || !setupLine(clip(a), clip(b), vp, gx, gy, src.pass.width, r)) continue;
      const int32_t p0 = r.lo + int32_t(w - spanStart(k)) * kLineSpan;
      const int32_t p1 = p0 + kLineSpan - 1 < r.hi ? p0 + kLineSpan - 1 : r.hi;
      lightColumns(r, p0, p1, src.pass, src.pass.lineKey(k), vis.data(), vp);
    }
  }
};

}  // namespace

LinePass makeLinePass(const DeviceScene& s, const RenderSettings& rs) {
  if (!(rs.lineWidth >= 1.0f && rs.lineWidth <= kMaxLineWidth))
    throw Error("line width must be 1..64 pixels, not " + std::to_string(rs.lineWidth));
  if (!(rs.pointSize >= 1.0f && rs.pointSize <= kMaxLineWidth))
    throw Error("point size must be 1..64 pixels, not " + std::to_string(rs.pointSize));
  LinePass p;
  p.numLines = s.numLines;
  p.numPoints = s.numPoints;
  p.numTris = s.numTris;
  p.edges = rs.polygon == PolygonMode::Line ? 1 : rs.wireframe == Wireframe::On ? 2 : rs.wireframe == Wireframe::Hidden ? 3 : 0;
  if (rs.polygon == PolygonMode::Point) p.edges = 0;
  p.corners = rs.polygon == PolygonMode::Point ? 1 : 0;
  p.width = int32_t(rs.lineWidth * float(kSubOne) + 0.5f);
  p.size = int32_t(rs.pointSize * float(kSubOne) + 0.5f);
  p.cullBack = rs.cull == CullMode::Back ? 1 : 0;
  if ((p.edges || p.corners) && uint64_t(p.numLines) + p.numPoints + 6ull * p.numTris >= (1ull << 31))
    throw Error("polygon modes and the wireframe support up to 2^31 / 6 triangles");
  return p;
}

void rasterLinesAndPoints(const DeviceScene& s, FrameBuffers& f, const LinePass& pass) {
  LineFrame& lf = f.lines;
  lf.pass = pass;
  const uint32_t nLines = pass.lineItems(), nPoints = pass.pointItems();
  if (nLines == 0 && nPoints == 0) return;
  if (!lf.counters.data()) lf.counters = allocZeroed<uint32_t>("frame.lines.counters", 2);
  const LineSource src{s.lines, s.points, s.draws, s.drawTriStart, s.indices, f.snap, s.numDraws, pass};
  const float gx = guardBand(f.vp.width), gy = guardBand(f.vp.height);
  using Policy = Kokkos::RangePolicy<Exec, Kokkos::IndexType<uint32_t>>;
  if (nLines > 0) {
    ensureCapacity(lf.lineOffset, "frame.lines.lineOffset", nLines);
    Kokkos::parallel_for("rast::raster::lines::count", lightweight(Policy(0, nLines)),
                         CountLineSpans{src, f.clip, lf.lineOffset, f.vis, f.vp, gx, gy});
    scanExclusive("rast::raster::lines::scan", lf.lineOffset, nLines, lf.counters, 0);
    const uint32_t threads = persistentThreads();
    Kokkos::parallel_for("rast::raster::lines::spans", lightweight(Policy(0, threads)),
                         RasterLineSpans{src, f.clip, lf.lineOffset, lf.counters, f.vis, f.vp, gx, gy, nLines, threads});
  }
  if (nPoints > 0) rasterPointItems(src, f);
}

LineShade makeLineShade(const DeviceScene& s, const LineFrame& f) {
  return LineShade{s.lines, s.points, s.draws, s.drawTriStart, s.indices, s.materials, s.colors,
                   s.numDraws, s.hasColor ? 1 : 0, f.pass};
}

}  // namespace rast
