// Primitive assembly and triangle setup: fetch indices, clip in homogeneous
// space, cull, snap, and write the raster triangles in primitive order.
//
// Done in three kernels so the output is compact and ordered without any
// atomics: count the raster triangles each drawn triangle yields (0 when it is
// culled, degenerate, non-finite or off-screen; up to kMaxClipVerts-2 when
// clipped), exclusive-scan the counts, then redo the work and write each
// triangle at its offset. The total goes to counters(kRasterTris) on the device,
// so no host round trip is needed inside the frame.
#include "raster_common.h"
#include "stages.h"

namespace rast {
namespace {

struct SetupCommon {
  DView<DrawGPU> draws;
  DView<uint32_t> drawTriStart;
  DView<uint32_t> indices;
  DView<float4> clip;
  uint32_t numDraws;
  Viewport vp;
  float gx, gy;
  int32_t cullBack;

  // Fetches drawn triangle t's corners in clip space.
  KOKKOS_INLINE_FUNCTION void fetch(uint32_t t, ClipVert (&v)[3], bool& frontCCW) const {
    const uint32_t d = findRange(drawTriStart, numDraws, t);
    const DrawGPU& dr = draws(d);
    const uint32_t local = t - dr.dstTri;
    const uint32_t base = 3 * (dr.srcTri + local);
    for (int k = 0; k < 3; ++k) v[k].p = clip(dr.dstVertex + indices(base + k));
    v[0].b1 = 0.0f; v[0].b2 = 0.0f;
    v[1].b1 = 1.0f; v[1].b2 = 0.0f;
    v[2].b1 = 0.0f; v[2].b2 = 1.0f;
    frontCCW = dr.mirrored == 0;
  }

  // Clips a triangle that needs it; returns the polygon size (0: nothing left).
  KOKKOS_INLINE_FUNCTION int clipSlow(const ClipVert (&v)[3], ClipVert (&poly)[kMaxClipVerts]) const {
    for (int k = 0; k < 3; ++k) poly[k] = v[k];
    return clipTriangle(poly, gx, gy);
  }

  // Raster triangle i of the fan of polygon poly (n vertices).
  KOKKOS_INLINE_FUNCTION bool fanTriangle(const ClipVert (&poly)[kMaxClipVerts], int i, bool frontCCW, uint32_t t,
                                          RasterTri& out) const {
    return setupTriangle(poly[0], poly[i + 1], poly[i + 2], vp, cullBack != 0, frontCCW, t, out);
  }
};

struct CountTris {
  SetupCommon c;
  DView<uint32_t> count;
  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t t) const {
    ClipVert v[3];
    bool frontCCW;
    c.fetch(t, v, frontCCW);
    const int cls = classifyTriangle(v[0].p, v[1].p, v[2].p, c.gx, c.gy);
    RasterTri rt;
    if (cls != 2) {  // fast path: no polygon in local memory (the result is the same)
      count(t) = cls == 1 && setupTriangle(v[0], v[1], v[2], c.vp, c.cullBack != 0, frontCCW, t, rt) ? 1u : 0u;
      return;
    }
    ClipVert poly[kMaxClipVerts];
    const int n = c.clipSlow(v, poly);
    uint32_t k = 0;
    for (int i = 0; i + 2 < n; ++i) k += c.fanTriangle(poly, i, frontCCW, t, rt) ? 1u : 0u;
    count(t) = k;
  }
};

// Exclusive prefix sum in place; the grand total goes to counters(slot).
struct ExclusiveScan {
  DView<uint32_t> data;
  DView<uint32_t> counters;
  uint32_t n;
  int slot;
  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t i, uint32_t& update, const bool final) const {
    const uint32_t v = data(i);
    if (final) {
      data(i) = update;
      if (i + 1 == n) counters(slot) = update + v;
    }
    update += v;
  }
};

struct WriteTris {
  SetupCommon c;
  DView<uint32_t> offset;
  DView<RasterTri> tris;
  uint32_t capacity;
  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t t) const {
    ClipVert v[3];
    bool frontCCW;
    c.fetch(t, v, frontCCW);
    const int cls = classifyTriangle(v[0].p, v[1].p, v[2].p, c.gx, c.gy);
    uint32_t o = offset(t);
    if (cls != 2) {
      RasterTri rt;
      if (cls == 1 && setupTriangle(v[0], v[1], v[2], c.vp, c.cullBack != 0, frontCCW, t, rt) && o < capacity) tris(o) = rt;
      return;
    }
    ClipVert poly[kMaxClipVerts];
    const int n = c.clipSlow(v, poly);
    for (int i = 0; i + 2 < n; ++i) {
      RasterTri rt;
      if (!c.fanTriangle(poly, i, frontCCW, t, rt)) continue;
      if (o < capacity) tris(o) = rt;
      ++o;
    }
  }
};

}  // namespace

void scanExclusive(const char* label, const DView<uint32_t>& data, uint32_t n, const DView<uint32_t>& counters, int slot) {
  if (n == 0) {
    Kokkos::parallel_for(label, Range(0, 1), KOKKOS_LAMBDA(const int) { counters(slot) = 0; });
    return;
  }
  Kokkos::parallel_scan(label, Kokkos::RangePolicy<Exec, Kokkos::IndexType<uint32_t>>(0, n),
                        ExclusiveScan{data, counters, n, slot});
}

void primitiveSetup(const DeviceScene& s, FrameBuffers& f, bool cullBack) {
  ensureCapacity(f.triOffset, "frame.triOffset", s.numTris);
  SetupCommon c{s.draws, s.drawTriStart, s.indices, f.clip, s.numDraws, f.vp,
                guardBand(f.vp.width), guardBand(f.vp.height), cullBack ? 1 : 0};
  using Policy = Kokkos::RangePolicy<Exec, Kokkos::IndexType<uint32_t>>;
  Kokkos::parallel_for("rast::setup::count", Policy(0, s.numTris), CountTris{c, f.triOffset});
  scanExclusive("rast::setup::scan", f.triOffset, s.numTris, f.counters, kRasterTris);
  Kokkos::parallel_for("rast::setup::write", Policy(0, s.numTris), WriteTris{c, f.triOffset, f.tris, f.triCapacity});
}

}  // namespace rast
