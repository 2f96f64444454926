// The work lists of the MASK and BLEND raster triangles and the MASK pass
// (blend.h): MASK fragments are alpha-tested where their keys are written,
// into the same visibility buffer, after the raster method, so that a
// discarded fragment never wins the depth test and the surface behind shows.
// The keys are the raster methods' (visKey) combined by the same atomic
// minimum: the result does not depend on the method or on the order.
#include "pipeline/blend/alpha_fragment.h"
#include "pipeline/blend/blend.h"
#include "pipeline/geometry/geometry.h"

namespace rast {

namespace blending {

AlphaScene makeAlphaScene(const DeviceScene& s, const FrameBuffers& f, TexFilter filter, bool perspective) {
  AlphaScene a;
  a.tris = f.tris;
  a.draws = s.draws;
  a.drawTriStart = s.drawTriStart;
  a.indices = s.indices;
  a.triDraw = s.triDraw;
  a.uvs = s.uvs;
  a.colors = s.colors;
  a.materials = s.materials;
  a.textures = s.textures;
  a.texels = s.texels;
  a.lut = s.srgbToLinear;
  a.alphaDraws = s.alphaDraws;
  a.numDraws = s.numDraws;
  a.hasUV = s.hasUV ? 1 : 0;
  a.hasColor = s.hasColor ? 1 : 0;
  a.perspective = perspective ? 1 : 0;
  // --filter auto: each texture's own magnification filter (the glTF sampler's).
  a.nearest = filter == TexFilter::Nearest ? 1 : filter == TexFilter::Auto ? 2 : 0;
  return a;
}

}  // namespace blending

namespace {

using namespace blending;

// Exclusive scan of the work items of one class's raster triangles; the
// total into totals(slot). The BLEND class's also clears the frame's BLEND
// totals (kBlendFrags on) for blendCollect's passes, which
// follow it: a launch of their own cost the frame a graph node. (Where the
// setup's single-pass scan numbers the BLEND class's items, it does both and
// this scan is not run for that class: setupNumbersBlendItems.)
struct ClassScan {
  DView<RasterTri> tris;
  DView<uint32_t> counters;
  DView<uint64_t> start, totals;
  uint32_t capacity;
  Viewport vp;
  int32_t cls;
  int slot;
  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t i, uint64_t& upd, const bool final) const {
    const uint32_t n = counters(kRasterTris) < capacity ? counters(kRasterTris) : capacity;
    uint64_t v = 0;
    if (i < n) v = classItems(tris(i), vp, cls);
    if (final) {
      start(i) = upd;
      if (i + 1 == capacity) totals(slot) = upd + v;
      // (kBlendListed too: the counted layout's scan writes it, the strided
      // one's fill only on overflow.)
      if (i == 0 && cls == kAlphaBlend)
        for (int k = kBlendFrags; k < kNumBlendTotals; ++k) totals(k) = 0;
    }
    upd += v;
  }
};
static_assert(kMaskItems < kBlendFrags && kBlendItems < kBlendFrags,
              "the BLEND scan clears the frame's totals, which follow the item counts");

struct MaskRaster {
  AlphaScene sc;
  DView<uint64_t> start, totals, vis;
  DView<uint32_t> counters;
  Viewport vp;
  uint32_t capacity, threads;
  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t th) const {
    const uint64_t total = totals(kMaskItems);
    const uint32_t n = counters(kRasterTris) < capacity ? counters(kRasterTris) : capacity;
    AlphaTri a;
    const int S = vp.samples.count;
    int32_t px = -1, py = -1;  // the pixel whose coverage `cov` holds (alpha-to-coverage)
    float cov = 0.0f;
    for (uint64_t w = th; w < total; w += threads) {
      const uint32_t i = itemOwner(start, n, w);
      if (i != a.index) {
        sc.prepare(i, a);
        px = -1;
      }
      forItemSamples(sc.tris(i), vp, uint32_t(w - start(i)),
                     [&](int64_t k, int32_t X, int32_t Y, int s, int64_t e0, int64_t e1, int64_t e2, float z) {
                       const uint64_t key = visKey(z, i);
                       if (key >= vis(k)) return;  // a plain read only skips what cannot win
                       if (S > 1) {  // alpha-to-coverage: one alpha a pixel, a dithered share of its samples
                         if (X != px || Y != py) {
                           px = X;
                           py = Y;
                           cov = sc.coverageAt(a, sc.tris(i), X, Y);
                         }
                         if (!(cov > coverageThreshold(s, S, X, Y))) return;
                       } else if (!(sc.alphaAt(a, e0, e1, e2) >= a.cutoff)) {
                         return;  // glTF: alpha < cutoff is discarded
                       }
                       Kokkos::atomic_fetch_min(&vis(k), key);
                     });
    }
  }
};

}  // namespace

void alphaWorkLists(const DeviceScene& s, FrameBuffers& f, const BlendPlan& b) {
  BlendBuffers& bb = f.blend;
  if (!bb.totals.data()) bb.totals = allocZeroed<uint64_t>("blend.totals", kNumBlendTotals);
  using Policy = Kokkos::RangePolicy<Exec, Kokkos::IndexType<uint32_t>>;
  if (b.mask) {
    ensureCapacity(bb.maskStart, "blend.maskStart", f.triCapacity);
    Kokkos::parallel_scan("rast::blend::mask_items", Policy(0, f.triCapacity),
                          ClassScan{f.tris, f.counters, bb.maskStart, bb.totals, f.triCapacity, f.vp, kAlphaMask, kMaskItems});
  }
  if (b.blend && !setupNumbersBlendItems(s.numTris)) {  // else numbered by the setup
    ensureCapacity(bb.blendStart, "blend.blendStart", f.triCapacity);
    Kokkos::parallel_scan("rast::blend::blend_items", Policy(0, f.triCapacity),
                          ClassScan{f.tris, f.counters, bb.blendStart, bb.totals, f.triCapacity, f.vp, kAlphaBlend, kBlendItems});
  }
}

void rasterMask(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p) {
  const uint32_t threads = persistentThreads();
  Kokkos::parallel_for("rast::blend::mask", heavyweight(Kokkos::RangePolicy<Exec, Kokkos::IndexType<uint32_t>>(0, threads)),
                       MaskRaster{makeAlphaScene(s, f, p.filter, p.perspective != 0), f.blend.maskStart, f.blend.totals,
                                  f.vis, f.counters, f.vp, f.triCapacity, threads});
}

}  // namespace rast
