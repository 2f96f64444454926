// The BLEND passes (blend.h, docs/transparency.md). Collect, after the opaque
// raster and before shading: every fragment of a BLEND triangle that lies in
// front of the opaque depth of its sample (LESS, not written) and has an alpha
// above 0 is
//   exact:    counted per sample, the counts scanned into a layout, then
//             written there (a counted two-pass layout) with its key
//             depth << 32 | raster index + 1;
//   sorted:   the same, keyed by its draw's centre depth in view space (and
//             later triangles first), as engines sort draws;
//   kbuffer:  inserted among the sample's k nearest keys by a cascade of
//             atomic minima (which leaves the k smallest whatever the order);
//             a key pushed out is shaded and merged into the weighted sums;
//   weighted: shaded at once and summed with McGuire and Bavoil's weight.
// Resolve, after shading into the float film: per sample, the fragments in
// key order composited front to back with "over" (premultiplied, linear
// light) over the opaque colour, the samples averaged. Keys are unique, so
// the order, and exact's result, do not depend on the thread schedule.
#include "pipeline/blend/alpha_fragment.h"
#include "pipeline/blend/blend.h"
#include "pipeline/shade/shade_fragment.h"

namespace rast {
namespace {

using namespace blending;
using shading::Shade;
using shading::TriFrag;

constexpr uint64_t kEmptySlot = ~uint64_t(0);
enum : int32_t { kCount = 0, kWrite = 1 };

// Bits of a float that order like its value (any sign; NaN as 0).
KOKKOS_INLINE_FUNCTION uint32_t orderBits(float v) {
  const uint32_t b = floatBits(v == v ? v : 0.0f);
  return (b & 0x80000000u) ? ~b : (b | 0x80000000u);
}

// A fragment's colour (linear, from the shade stage's fragment maths) and
// alpha (alpha_fragment.h) at sample s of pixel (X, Y).
struct FragShade {
  AlphaScene sc;
  Shade sh;
  SamplePattern sp;
  KOKKOS_INLINE_FUNCTION float4 at(uint32_t index, int32_t X, int32_t Y, int s, AlphaTri& a, TriFrag& tf) const {
    if (a.index != index) sc.prepare(index, a);
    sh.use(index, tf);
    const RasterTri& t = sc.tris(index);
    const Edges e(t);
    const int64_t s0 = e.atSample(0, e.eval(0, X, Y), sp.ox[s], sp.oy[s]);
    const int64_t s1 = e.atSample(1, e.eval(1, X, Y), sp.ox[s], sp.oy[s]);
    const int64_t s2 = e.atSample(2, e.eval(2, X, Y), sp.ox[s], sp.oy[s]);
    const float alpha = sc.alphaAt(a, s0, s1, s2);
    float3 n;
    const float4 c = sh.shadeFragment(tf, X, Y, sp.ox[s], sp.oy[s], DepthTerms(t).at(s0, s2), &n);
    return float4{c.x, c.y, c.z, alpha};
  }
  // Weighted blended OIT's weight (McGuire and Bavoil 2013, eq. 7) at window depth d.
  KOKKOS_INLINE_FUNCTION float weight(float d) const {
    const float n = sh.p.frame(0).camera.znear, f = sh.p.frame(0).camera.zfar;
    const float z = 2.0f * n * f / ((f + n) - (2.0f * d - 1.0f) * (f - n));
    const float a = z / 5.0f, b = z / 200.0f, b2 = b * b;
    const float w = 10.0f / (1e-5f + a * a + b2 * b2 * b2);
    return w < 1e-2f ? 1e-2f : (w > 3e3f ? 3e3f : w);
  }
};

KOKKOS_INLINE_FUNCTION void addWeighted(float4& acc, float& rev, const float4 c, float w) {
  Kokkos::atomic_add(&acc.x, c.x * c.w * w);
  Kokkos::atomic_add(&acc.y, c.y * c.w * w);
  Kokkos::atomic_add(&acc.z, c.z * c.w * w);
  Kokkos::atomic_add(&acc.w, c.w * w);
  Kokkos::atomic_fetch_mul(&rev, 1.0f - c.w);
}

struct Collect {
  FragShade fs;
  DView<uint64_t> start, totals, vis, frags, slots;
  DView<uint32_t> counters, count, end;
  DView<float4> accum;
  DView<float> reveal;
  Viewport vp;
  uint32_t capacity, threads;
  uint64_t fragCapacity;
  int32_t method, pass, k;
  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t th) const {
    const uint64_t total = totals(kBlendItems);
    const uint32_t n = counters(kRasterTris) < capacity ? counters(kRasterTris) : capacity;
    AlphaTri a, a2;
    TriFrag tf, tf2;
    for (uint64_t w = th; w < total; w += threads) {
      const uint32_t i = itemOwner(start, n, w);
      if (i != a.index) fs.sc.prepare(i, a);
      forItemSamples(fs.sc.tris(i), vp, uint32_t(w - start(i)),
                     [&](int64_t q, int32_t X, int32_t Y, int s, int64_t e0, int64_t e1, int64_t e2, float z) {
                       // LESS against the opaque depth, which is not written.
                       if (!(floatBits(z) < uint32_t(vis(q) >> 32))) return;
                       const float alpha = fs.sc.alphaAt(a, e0, e1, e2);
                       if (!(alpha > 0.0f)) return;
                       fragment(q, X, Y, s, i, z, alpha, a, tf, a2, tf2);
                     });
    }
  }
  KOKKOS_INLINE_FUNCTION void fragment(int64_t q, int32_t X, int32_t Y, int s, uint32_t i, float z, float alpha,
                                       AlphaTri& a, TriFrag& tf, AlphaTri& a2, TriFrag& tf2) const {
    if (method == int32_t(Transparency::Exact) || method == int32_t(Transparency::Sorted)) {
      if (pass == kCount) {
        const uint32_t c = Kokkos::atomic_fetch_add(&count(q), 1u) + 1u;
        if (c > totals(kBlendMaxDepth)) Kokkos::atomic_fetch_max(&totals(kBlendMaxDepth), uint64_t(c));
        return;
      }
      const uint32_t slot = Kokkos::atomic_fetch_add(&end(q), 1u);
      if (slot >= fragCapacity) return;  // the frame is drawn again with more room (Renderer::lastFrameFit)
      frags(slot) = method == int32_t(Transparency::Exact) ? visKey(z, i) : sortedKey(a.draw, i);
      return;
    }
    if (method == int32_t(Transparency::Weighted)) {
      const float4 c = fs.at(i, X, Y, s, a, tf);
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
    const float4 c = fs.at(uint32_t(key & 0xffffffffu) - 1u, X, Y, s, a2, tf2);
    addWeighted(accum(q), reveal(q), c, 1.0f);
  }
  // sorted: the draw's bounding box centre, its depth in view space, nearest
  // first; within a draw, later triangles first (drawn last, they lie on top).
  KOKKOS_INLINE_FUNCTION uint64_t sortedKey(uint32_t draw, uint32_t i) const {
    const float* m = fs.sh.draws(draw).modelF.m;
    const float3 c = fs.sc.alphaDraws(draw).centre;
    const float wx = m[0] * c.x + m[4] * c.y + m[8] * c.z + m[12];
    const float wy = m[1] * c.x + m[5] * c.y + m[9] * c.z + m[13];
    const float wz = m[2] * c.x + m[6] * c.y + m[10] * c.z + m[14];
    const float* v = fs.sh.p.frame(0).camera.view.m;
    const float depth = -(v[2] * wx + v[6] * wy + v[10] * wz + v[14]);
    return uint64_t(orderBits(depth)) << 32 | uint64_t(0xffffffffu - i);
  }
};

// Exclusive scan of the per-sample counts into `end` (32-bit offsets), with
// the 64-bit total in totals(kBlendFrags): a total beyond any capacity is
// seen as such and never wraps.
struct CountScan {
  DView<uint32_t> count, end;
  DView<uint64_t> totals;
  uint64_t n;
  KOKKOS_INLINE_FUNCTION void operator()(const int64_t i, uint64_t& upd, const bool final) const {
    const uint32_t v = count(i);
    if (final) {
      end(i) = uint32_t(upd);
      if (uint64_t(i) + 1 == n) totals(kBlendFrags) = upd + v;
    }
    upd += v;
  }
};

// The resolve's work item: a run of kResolveRun pixels along a row, keeping
// the per-triangle lookups (AlphaTri, TriFrag) of the last kResolveCache
// triangles it shaded: the layers over neighbouring pixels are mostly the
// same few triangles, and one entry re-prepared for each fragment of a pixel
// of 8 layers cost more than the shading. A GPU keeps a pixel a thread and one
// entry (registers).
constexpr int32_t kResolveRun = kOnDevice ? 1 : 16;
constexpr int kResolveCache = kOnDevice ? 1 : 8;
struct FragCache {
  AlphaTri a[kResolveCache];
  TriFrag tf[kResolveCache];
  int next = 0;
  KOKKOS_INLINE_FUNCTION int slot(uint32_t index) {
    for (int k = 0; k < kResolveCache; ++k)
      if (a[k].index == index) return k;
    const int k = next;
    next = next + 1 == kResolveCache ? 0 : next + 1;
    return k;
  }
};

struct Resolve {
  FragShade fs;
  DView<float4> hdr, accum;
  DView<float> reveal;
  DView<uint32_t> count, end;
  DView<uint64_t> frags, slots;
  uint64_t fragCapacity;
  int32_t width, method, k, runsPerRow;

  KOKKOS_INLINE_FUNCTION float4 at(uint32_t index, int32_t X, int32_t Y, int s, FragCache& c) const {
    const int e = c.slot(index);
    return fs.at(index, X, Y, s, c.a[e], c.tf[e]);
  }

  KOKKOS_INLINE_FUNCTION static void sortKeys(uint64_t* v, uint32_t c) {
    // Shell sort with Ciura's gaps, in place: keys are unique, so the order
    // is the same whatever order they were written in.
    constexpr uint32_t gaps[8] = {701, 301, 132, 57, 23, 10, 4, 1};
    for (uint32_t g : gaps) {
      if (g >= c) continue;
      for (uint32_t i = g; i < c; ++i) {
        const uint64_t x = v[i];
        uint32_t j = i;
        for (; j >= g && v[j - g] > x; j -= g) v[j] = v[j - g];
        v[j] = x;
      }
    }
  }
  KOKKOS_INLINE_FUNCTION uint32_t indexOf(uint64_t key) const {
    return method == int32_t(Transparency::Sorted) ? 0xffffffffu - uint32_t(key) : uint32_t(key) - 1u;
  }
  KOKKOS_INLINE_FUNCTION static void over(float3& acc, float& T, const float4 c) {
    acc = acc + float3{c.x, c.y, c.z} * (T * c.w);
    T = T * (1.0f - c.w);
  }

  KOKKOS_INLINE_FUNCTION void operator()(const int64_t item) const {
    const int32_t Y = int32_t(item / runsPerRow), x0 = int32_t(item - int64_t(Y) * runsPerRow) * kResolveRun;
    const int32_t x1 = x0 + kResolveRun < width ? x0 + kResolveRun : width;
    FragCache c;
    for (int32_t X = x0; X < x1; ++X) pixel(int64_t(Y) * width + X, X, Y, c);
  }

  KOKKOS_INLINE_FUNCTION void pixel(const int64_t i, const int32_t X, const int32_t Y, FragCache& cache) const {
    const int S = fs.sp.count;
    const float4 opq = hdr(i);
    float4 sum{0.0f, 0.0f, 0.0f, 0.0f};
    for (int s = 0; s < S; ++s) {
      const int64_t q = i * S + s;
      float3 acc{0.0f, 0.0f, 0.0f};
      float T = 1.0f;
      if (method == int32_t(Transparency::Weighted)) {
        const float4 w = accum(q);
        if (w.w > 0.0f) {
          T = reveal(q);
          acc = float3{w.x, w.y, w.z} * ((1.0f - T) / w.w);
        }
      } else if (method == int32_t(Transparency::KBuffer)) {
        const uint64_t* sl = slots.data() + size_t(q) * size_t(k);
        for (int j = 0; j < k && sl[j] != kEmptySlot && T > 0.0f; ++j)
          over(acc, T, at(uint32_t(sl[j]) - 1u, X, Y, s, cache));
        const float4 w = accum(q);
        if (w.w > 0.0f) {  // the merged rest, behind the k nearest
          const float A = 1.0f - reveal(q);
          over(acc, T, float4{w.x / w.w, w.y / w.w, w.z / w.w, A});
        }
      } else {
        const uint32_t c = count(q), e = end(q);
        if (c > 0 && uint64_t(e) <= fragCapacity && e >= c) {
          uint64_t* v = frags.data() + (e - c);
          sortKeys(v, c);
          for (uint32_t j = 0; j < c && T > 0.0f; ++j) over(acc, T, at(indexOf(v[j]), X, Y, s, cache));
        }
      }
      const float4 out{acc.x + T * opq.x, acc.y + T * opq.y, acc.z + T * opq.z, 1.0f - T * (1.0f - opq.w)};
      if (S == 1) {
        hdr(i) = out;
        return;
      }
      sum = sum + out;
    }
    hdr(i) = sum * (1.0f / float(S));
  }
};

FragShade makeFragShade(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights) {
  ShadeParams q = p;
  q.wantDepth = q.wantPrimId = q.wantNormals = q.wantGeom = 0;  // outputs are the opaque pass's
  return FragShade{makeAlphaScene(s, f, p.filter, p.perspective != 0), makeShade(s, f, q, lights), f.vp.samples};
}

}  // namespace

uint64_t blendBytesPerSample(const BlendPlan& b) {
  switch (b.method) {
    case Transparency::Exact:
    case Transparency::Sorted:
      return 2 * sizeof(uint32_t);
    case Transparency::KBuffer:
      return uint64_t(b.k) * sizeof(uint64_t) + sizeof(float4) + sizeof(float);
    case Transparency::Weighted:
      return sizeof(float4) + sizeof(float);
    case Transparency::Auto:
      break;
  }
  return 0;
}

void blendCollect(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights,
                  const BlendPlan& b) {
  BlendBuffers& bb = f.blend;
  const size_t n = size_t(f.vp.width) * size_t(f.vp.height) * size_t(f.vp.samples.count);
  const bool exact = b.method == Transparency::Exact || b.method == Transparency::Sorted;
  auto totals = bb.totals;
  Kokkos::parallel_for("rast::blend::clear_totals", Range(0, 1), KOKKOS_LAMBDA(const int) {
    totals(kBlendFrags) = 0;
    totals(kBlendMaxDepth) = 0;
  });
  if (exact) {
    ensureCapacity(bb.count, "blend.count", n);
    ensureCapacity(bb.end, "blend.end", n);
    if (!bb.frags.data()) {
      bb.fragCapacity = bb.fragCapacity ? bb.fragCapacity : n;
      bb.frags = allocUninit<uint64_t>("blend.frags", bb.fragCapacity);
    }
    Kokkos::deep_copy(Exec(), Kokkos::subview(bb.count, std::make_pair(size_t(0), n)), 0u);
  } else {
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
  }
  const uint32_t threads = persistentThreads();
  Collect c{makeFragShade(s, f, p, lights), bb.blendStart, bb.totals, f.vis, bb.frags, bb.slots, f.counters,
            bb.count, bb.end, bb.accum, bb.reveal, f.vp, f.triCapacity, threads, bb.fragCapacity,
            int32_t(b.method), kCount, b.k};
  using Policy = Kokkos::RangePolicy<Exec, Kokkos::IndexType<uint32_t>>;
  if (!exact) {
    Kokkos::parallel_for("rast::blend::collect", heavyweight(Policy(0, threads)), c);
    return;
  }
  Kokkos::parallel_for("rast::blend::count", heavyweight(Policy(0, threads)), c);
  Kokkos::parallel_scan("rast::blend::layout", Kokkos::RangePolicy<Exec, Kokkos::IndexType<int64_t>>(0, int64_t(n)),
                        CountScan{bb.count, bb.end, bb.totals, uint64_t(n)});
  c.pass = kWrite;
  Kokkos::parallel_for("rast::blend::write", heavyweight(Policy(0, threads)), c);
}

void blendResolve(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights,
                  const BlendPlan& b) {
  const BlendBuffers& bb = f.blend;
  const int32_t runs = (f.vp.width + kResolveRun - 1) / kResolveRun;
  Kokkos::parallel_for("rast::blend::resolve", heavyweight(Range(0, int64_t(runs) * f.vp.height)),
                       Resolve{makeFragShade(s, f, p, lights), f.post.hdr, bb.accum, bb.reveal, bb.count, bb.end,
                               bb.frags, bb.slots, bb.fragCapacity, f.vp.width, int32_t(b.method), b.k, runs});
}

}  // namespace rast
