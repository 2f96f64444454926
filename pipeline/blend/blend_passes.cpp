// The BLEND passes (blend.h, docs/transparency.md). Collect, after the opaque
// raster and before shading: exact, sorted and weighted build their tile
// lists (blend_tiles.cpp); for the fixed-memory methods every fragment of a
// BLEND triangle that lies in front of the opaque depth of its sample (LESS,
// not written) and has an alpha above 0 is
//   kbuffer:  inserted among the sample's k nearest keys by a cascade of
//             atomic minima (which leaves the k smallest whatever the order);
//             a key pushed out is shaded and merged into the weighted sums;
//   weighted, when its lists would exceed the memory budget: shaded at once
//             and summed with McGuire and Bavoil's weight.
// Resolve, after shading into the float film: per sample, the fragments in
// key order composited front to back with "over" (premultiplied, linear
// light) over the opaque colour, the samples averaged (the listed methods:
// blend_tiles.cpp, peeling the tile lists in registers).
#include "pipeline/blend/frag_shade.h"
#include "pipeline/data/test_hooks.h"

namespace rast {
namespace {

using namespace blending;

constexpr uint64_t kEmptySlot = ~uint64_t(0);

KOKKOS_INLINE_FUNCTION void addWeighted(float4& acc, float& rev, const float4 c, float w) {
  Kokkos::atomic_add(&acc.x, c.x * c.w * w);
  Kokkos::atomic_add(&acc.y, c.y * c.w * w);
  Kokkos::atomic_add(&acc.z, c.z * c.w * w);
  Kokkos::atomic_add(&acc.w, c.w * w);
  Kokkos::atomic_fetch_mul(&rev, 1.0f - c.w);
}

// The fixed-memory collect and resolve passes are compiled for the frame's fragment
// family and features (frag_shade.h), as the exact resolve is: every method
// shades a fragment with the same code, so that kbuffer with k >= layers
// keeps exact's bits on every backend.
template <int kFam, int kFeat>
struct Collect {
  FragShade fs;
  DView<uint64_t> start, totals, vis, slots;
  DView<uint32_t> counters;
  DView<float4> accum;
  DView<float> reveal;
  Viewport vp;
  uint32_t capacity, threads;
  int32_t method, k;
  RAST_FLATTEN void operator()(const uint32_t th) const {
    const uint64_t total = totals(kBlendItems);
    const uint32_t n = counters(kRasterTris) < capacity ? counters(kRasterTris) : capacity;
    AlphaTri a, a2;
    TriFrag tf, tf2;
    FragPbrTri<kFam> pt, pt2;
    for (uint64_t w = th; w < total; w += threads) {
      const uint32_t i = itemOwner(start, n, w);
      if (i != a.index) fs.sc.prepare(i, a);
      forItemSamples(fs.sc.tris(i), vp, uint32_t(w - start(i)),
                     [&](int64_t q, int32_t X, int32_t Y, int s, int64_t e0, int64_t e1, int64_t e2, float z) {
                       // LESS against the opaque depth, which is not written.
                       if (!(floatBits(z) < uint32_t(vis(q) >> 32))) return;
                       const float alpha = fs.sc.alphaAt(a, e0, e1, e2);
                       if (!(alpha > 0.0f)) return;
                       fragment(q, X, Y, s, i, z, alpha, a, tf, pt, a2, tf2, pt2);
                     });
    }
  }
  KOKKOS_INLINE_FUNCTION void fragment(int64_t q, int32_t X, int32_t Y, int s, uint32_t i, float z, float alpha,
                                       AlphaTri& a, TriFrag& tf, FragPbrTri<kFam>& pt, AlphaTri& a2, TriFrag& tf2,
                                       FragPbrTri<kFam>& pt2) const {
    if (method == int32_t(Transparency::Weighted)) {
      const float4 c = fs.template at<kFam, kFeat>(i, X, Y, s, a, tf, pt);
      addWeighted(accum(q), reveal(q), c, fs.weight(z));
      return;
    }
    // kbuffer: the cascade keeps the k smallest keys; what falls off the end is merged.
    uint64_t key = visKey(z, i);
    uint64_t* sl = slots.data() + size_t(q) * size_t(k);
    for (int j = 0; j < k; ++j) {
      const uint64_t old = Kokkos::atomic_fetch_min(&sl[j], key);
      if (old == kEmptySlot) return;
      key = old > key ? old : key;
    }
    (void)alpha;
    const float4 c = fs.template at<kFam, kFeat>(uint32_t(key & 0xffffffffu) - 1u, X, Y, s, a2, tf2, pt2);
    addWeighted(accum(q), reveal(q), c, 1.0f);
  }
};

// The resolve's work item (kbuffer, weighted): a run of kResolveRun pixels
// along a row, sharing one FragCache; a GPU resolves a pixel a thread.
constexpr int32_t kResolveRun = kOnDevice ? 1 : 16;
template <int kFam, int kFeat>
struct Resolve {
  FragShade fs;
  DView<float4> hdr, accum;
  DView<float> reveal;
  DView<uint64_t> slots;
  int32_t width, method, k, runsPerRow;

  RAST_FLATTEN void operator()(const int64_t item) const {
    const int32_t Y = int32_t(item / runsPerRow), x0 = int32_t(item - int64_t(Y) * runsPerRow) * kResolveRun;
    const int32_t x1 = x0 + kResolveRun < width ? x0 + kResolveRun : width;
    FragCache<kFam> c;
    for (int32_t X = x0; X < x1; ++X) pixel(int64_t(Y) * width + X, X, Y, c);
  }

  KOKKOS_INLINE_FUNCTION void pixel(const int64_t i, const int32_t X, const int32_t Y, FragCache<kFam>& cache) const {
    const int S = fs.sp.count;
    const float4 opq = hdr(i);
    float4 sum{0.0f, 0.0f, 0.0f, 0.0f};
    for (int s = 0; s < S; ++s) {
      const int64_t q = i * S + s;
      float3 acc{0.0f, 0.0f, 0.0f};
      float T = 1.0f;
      if (method == int32_t(Transparency::Weighted)) {
        weightedFront(accum(q), reveal(q), acc, T);
      } else if (method == int32_t(Transparency::KBuffer)) {
        const uint64_t* sl = slots.data() + size_t(q) * size_t(k);
        for (int j = 0; j < k && sl[j] != kEmptySlot && T > 0.0f; ++j)
          over(acc, T, cache.template at<kFeat>(fs, uint32_t(sl[j]) - 1u, X, Y, s));
        const float4 w = accum(q);
        if (w.w > 0.0f) {  // the merged rest, behind the k nearest
          const float A = 1.0f - reveal(q);
          over(acc, T, float4{w.x / w.w, w.y / w.w, w.z / w.w, A});
        }
      }
      const float4 out = overOpaque(acc, T, opq);
      if (S == 1) {
        hdr(i) = out;
        return;
      }
      sum = sum + out;
    }
    hdr(i) = sum * (1.0f / float(S));
  }
};

// The launches of the frame's instances (withFragPath): heavyweight, as
// the collect's atomics and the general fragment maths leave code out of
// line on a GPU.
struct CollectLaunch {
  const FragShade& fs;
  const FrameBuffers& f;
  const DView<uint64_t>& opaqueKeys;
  uint32_t threads;
  int32_t method, k;
  template <int kFam, int kFeat>
  void run() const {
    const BlendBuffers& bb = f.blend;
    using Policy = Kokkos::RangePolicy<Exec, Kokkos::IndexType<uint32_t>>;
    Kokkos::parallel_for("rast::blend::collect", heavyweight(Policy(0, threads)),
                         Collect<kFam, kFeat>{fs, bb.blendStart, bb.totals, opaqueKeys, bb.slots, f.counters, bb.accum,
                                              bb.reveal, f.vp, f.triCapacity, threads, method, k});
  }
};
struct ResolveLaunch {
  const FragShade& fs;
  const FrameBuffers& f;
  Range items;
  int32_t method, k, runs;
  template <int kFam, int kFeat>
  void run() const {
    const BlendBuffers& bb = f.blend;
    Kokkos::parallel_for("rast::blend::resolve", heavyweight(items),
                         Resolve<kFam, kFeat>{fs, f.post.hdr, bb.accum, bb.reveal, bb.slots, f.vp.width, method, k, runs});
  }
};

}  // namespace

FragShade blending::makeFragShade(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p,
                                  const DView<LightGPU>& lights) {
  ShadeParams q = p;
  q.wantDepth = q.wantPrimId = q.wantNormals = q.wantGeom = 0;  // outputs are the opaque pass's
  return FragShade{makeAlphaScene(s, f, p.filter, p.perspective != 0), makeShade(s, f, q, lights), f.vp.samples};
}

FragFamily blending::fragFamily(const FragShade& fs) { return fragFamily(fs.sh.p); }

FragFamily blending::fragFamily(const ShadeParams& p) {
  if (testHooks().generalShade) return kFragGeneral;  // tests compare the paths
  if ((p.mode == ShadingMode::Lambert || p.mode == ShadingMode::BlinnPhong) && p.filter != TexFilter::Trilinear)
    return kFragLit;
  if (p.mode == ShadingMode::Pbr) return kFragPbr;
  return kFragGeneral;
}

bool blendResolveEncodes(const ShadeParams& p) {
  return blending::familyEncodes(blending::fragFamily(p));
}

bool blendShadeComposites(const ShadeParams& p) {
  return blending::uniformBlocksOn(blending::fragFamily(p));
}

bool blendLaunchesLightweight(const BlendPlan& b, const ShadeParams& p) {
  return !b.blend || (b.lists && blending::fragFamily(p) != blending::kFragGeneral);
}

uint64_t blendBytesPerSample(const BlendPlan& b) {
  // The listed methods: the opaque depth, and a count and an end per 8x8
  // block, with the team form's uniform composite and count under the glTF
  // shading and its list of walked blocks (32 bytes a block: a byte a
  // pixel, rounded up); the tile lists
  // themselves: lastFrameFit.
  constexpr uint64_t listed = sizeof(uint32_t) + 1;
  switch (b.method) {
    case Transparency::Exact:
    case Transparency::Sorted:
      return listed;  // always listed (over the budget they become kbuffer)
    case Transparency::KBuffer:
      return uint64_t(b.k) * sizeof(uint64_t) + sizeof(float4) + sizeof(float);
    case Transparency::Weighted:
      return b.lists ? listed : sizeof(float4) + sizeof(float);
    case Transparency::Auto:
      break;
  }
  return 0;
}

void blendCollect(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights,
                  const BlendPlan& b, const DView<uint64_t>& opaqueKeys) {
  BlendBuffers& bb = f.blend;
  const size_t n = size_t(f.vp.width) * size_t(f.vp.height) * size_t(f.vp.samples.count);
  // (The frame's totals: cleared by alphaWorkLists' BLEND scan, ClassScan.)
  if (b.lists) {
    tileLists(f, opaqueKeys, fragFamily(makeFragShade(s, f, p, lights)), !b.shadeDepth);
    if (b.shadeComposite) uniformBlocksBeforeShading(s, f, p, lights, b, opaqueKeys);
    return;
  }
  ensureCapacity(bb.accum, "blend.accum", n);
  ensureCapacity(bb.reveal, "blend.reveal", n);
  Kokkos::deep_copy(Exec(), Kokkos::subview(bb.accum, std::make_pair(size_t(0), n)), float4{0.0f, 0.0f, 0.0f, 0.0f});
  Kokkos::deep_copy(Exec(), Kokkos::subview(bb.reveal, std::make_pair(size_t(0), n)), 1.0f);
  if (b.method == Transparency::KBuffer) {
    if (bb.k != b.k) bb.slots = DView<uint64_t>();
    bb.k = b.k;
    ensureCapacity(bb.slots, "blend.slots", n * size_t(b.k));
    Kokkos::deep_copy(Exec(), Kokkos::subview(bb.slots, std::make_pair(size_t(0), n * size_t(b.k))), kEmptySlot);
  }
  const uint32_t threads = persistentThreads();
  const FragShade fs = makeFragShade(s, f, p, lights);
  withFragPath(fs, CollectLaunch{fs, f, opaqueKeys, threads, int32_t(b.method), b.k});
}

void blendResolve(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights,
                  const BlendPlan& b) {
  if (b.lists) {
    peelResolve(s, f, p, lights, b);
    return;
  }
  const int32_t runs = (f.vp.width + kResolveRun - 1) / kResolveRun;
  const FragShade fs = makeFragShade(s, f, p, lights);
  withFragPath(fs, ResolveLaunch{fs, f, Range(0, int64_t(runs) * f.vp.height), int32_t(b.method), b.k, runs});
}

}  // namespace rast
