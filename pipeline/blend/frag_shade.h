// What the BLEND passes share (docs/transparency.md): a fragment's colour and
// alpha at one sample (the shade stage's fragment maths and alpha_fragment.h),
// the sort keys of the exact and sorted methods, "over", and the lookups a
// thread keeps across the fragments it shades. The kbuffer and weighted
// passes (blend_passes.cpp) and the exact and sorted methods' tile lists
// (blend_tiles.cpp) composite with the same functions, so that kbuffer with
// k >= layers gives exact's bits.
#pragma once

#include <type_traits>

#include "backends/flatten.h"
#include "pipeline/blend/alpha_fragment.h"
#include "pipeline/blend/blend.h"
#include "pipeline/shade/shade_fragment.h"

namespace rast {
namespace blending {

using shading::Shade;
using shading::TriFrag;

// Bits of a float that order like its value (any sign; NaN as 0).
KOKKOS_INLINE_FUNCTION uint32_t orderBits(float v) {
  const uint32_t b = floatBits(v == v ? v : 0.0f);
  return (b & 0x80000000u) ? ~b : (b | 0x80000000u);
}

// The fragment shading of the BLEND passes, chosen once per frame on the host
// (withFragPath) and compiled into each pass's functor:
//   kFragLit:     Lambert or Blinn-Phong with a nearest or bilinear filter
//                 (Shade::litFragment; kFeat: vertex colours, 0 or 1);
//   kFragPbr:     the glTF shading (Shade::shadePbr<kFeat>, kFeat the scene's
//                 PbrFeature set, as the shade stage's own kernel takes it);
//   kFragGeneral: every other mode (depth, the diagnostic views, trilinear
//                 filtering), the shade stage's general fragment maths.
// The specialised paths evaluate the general one's expressions in its order
// (the same bits: tests/pipeline/test_transparency.cpp compares them through
// TestHooks::generalShade), from the sample's edge values computed once for
// the alpha and the colour, with no code for what the frame does not use and
// nothing whose address is taken (a GPU keeps it all in registers).
enum FragFamily : int { kFragGeneral, kFragLit, kFragPbr };
// Whether the tile lists' resolve of a family writes the colour's bytes where
// the plan asks it to (BlendPlan::encode, blendResolveEncodes): on CPUs every
// family (kBlendResolveEncodes); on GPUs the glTF shading's, whose uniform
// blocks' pixels a light kernel of their own writes.
constexpr bool familyEncodes(const int fam) { return kBlendResolveEncodes || fam == kFragPbr; }

// A pass's per-triangle lookups for the glTF shading (none for the others).
struct NoPbrTri {};
template <int kFam>
using FragPbrTri = std::conditional_t<kFam == kFragPbr, shading::PbrTri, NoPbrTri>;

// A fragment's colour (linear) and alpha (alpha_fragment.h) at sample s of
// pixel (X, Y).
struct FragShade {
  AlphaScene sc;
  Shade sh;
  SamplePattern sp;
  template <int kFam = kFragGeneral, int kFeat = 0>
  RAST_GPU_INLINE float4 at(uint32_t index, int32_t X, int32_t Y, int s, AlphaTri& a, TriFrag& tf,
                            FragPbrTri<kFam>& pt) const {
    if (a.index != index) sc.prepare(index, a);
    if constexpr (kFam == kFragGeneral) {
      sh.use(index, tf);
      const RasterTri& t = sc.tris(index);
      const Edges& e = tf.e;  // Edges(t), set up once per triangle by use()
      const int64_t s0 = e.sample(0, X, Y, sp.ox[s], sp.oy[s]);
      const int64_t s1 = e.sample(1, X, Y, sp.ox[s], sp.oy[s]);
      const int64_t s2 = e.sample(2, X, Y, sp.ox[s], sp.oy[s]);
      const float alpha = sc.alphaAt(a, s0, s1, s2);
      float3 n;
      const float4 c = sh.shadeFragment(tf, X, Y, sp.ox[s], sp.oy[s], DepthTerms(t).at(s0, s2), &n);
      return float4{c.x, c.y, c.z, alpha};
    } else {
      use<kFam>(index, tf, pt);
      const Edges& e = tf.e;
      const int32_t ox = sp.ox[s], oy = sp.oy[s];
      return shadeAt<kFam, kFeat>(X, Y, s, e.sample(0, X, Y, ox, oy), e.sample(1, X, Y, ox, oy), e.sample(2, X, Y, ox, oy), a,
                                  tf, pt);
    }
  }
  // The specialised paths' shading lookups of triangle `index` (its AlphaTri
  // apart); whether they were prepared now.
  template <int kFam>
  RAST_GPU_INLINE bool use(uint32_t index, TriFrag& tf, FragPbrTri<kFam>& pt) const {
    if (tf.index == index) return false;
    sh.prepare(index, tf);
    if constexpr (kFam == kFragPbr) pt = sh.pbrTri(tf);
    return true;
  }
  // A specialised path's fragment at sample s of pixel (X, Y), whose exact
  // edge values are E0, E1, E2 (the barycentrics, alpha and colour from them).
  template <int kFam, int kFeat>
  RAST_GPU_INLINE float4 shadeAt(int32_t X, int32_t Y, int s, int64_t E0, int64_t E1, int64_t E2, const AlphaTri& a,
                                 const TriFrag& tf, const FragPbrTri<kFam>& pt) const {
    float4 k;
    if (constantColour<kFam, kFeat>(a, pt, k))  // nothing to interpolate (a GPU's branch: one triangle a warp)
      return k.w > 0.0f ? k : float4{0.0f, 0.0f, 0.0f, 0.0f};
    float b0, b1, b2;
    sh.baryFrom(tf, E0, E1, E2, b0, b1, b2);
    const float alpha = sc.alphaFrom(a, b0, b1, b2);
    if (!(alpha > 0.0f)) return float4{0.0f, 0.0f, 0.0f, 0.0f};  // no fragment: its colour is not read
    float4 c;
    if constexpr (kFam == kFragLit) {
      c = sh.template litFragment<kFeat>(tf, b0, b1, b2);
    } else {
      static_assert(kFam == kFragPbr, "a fragment family without its shading");
      // The normal and position only where the material is lit.
      c = sh.template shadePbrWith<kFeat>(tf, pt, X, Y, sp.ox[s], sp.oy[s], b0, b1, b2, [&](float3& N, float3& P) {
        N = normalize(tf.n[0] * b0 + tf.n[1] * b1 + tf.n[2] * b2);
        P = tf.pos[0] * b0 + tf.pos[1] * b1 + tf.pos[2] * b2;
      });
    }
    return float4{c.x, c.y, c.z, alpha};
  }
  // The colour and alpha (w) every fragment of a triangle has, where they do
  // not vary over it: the glTF shading's unlit material, untextured, in a
  // scene without vertex colours (shadePbrWith returns its base colour,
  // alphaFrom its material's alpha); false elsewhere. shadeAt returns it
  // without the barycentrics, and the CPU's block walk composites such a
  // triangle's fragments without a call a fragment (peel_block.h): the same
  // values, so the same bits.
  template <int kFam, int kFeat>
  RAST_GPU_INLINE bool constantColour(const AlphaTri& a, const FragPbrTri<kFam>& pt, float4& c) const {
    if constexpr (kFam == kFragPbr && kFeat != shading::kPbrAny) {
      if (!(pt.m.flags & kMaterialUnlit) || pt.textured || a.textured || sh.hasColor || sc.hasColor) return false;
      c = float4{pt.m.baseColor.x, pt.m.baseColor.y, pt.m.baseColor.z, cleanAlpha(a.alpha)};
      return true;
    } else {
      return false;
    }
  }
  // The same for raster triangle i, read from its draw's material alone
  // (what AlphaScene::prepare and use() would take from it), without
  // setting the triangle up: the uniform blocks' classification, a thread
  // a block over its list (uniform_blocks.h), where the set-up's vertex
  // loads took most of the time.
  template <int kFam, int kFeat>
  RAST_GPU_INLINE bool constantColourOf(const uint32_t i, float4& c) const {
    if constexpr (kFam == kFragPbr && kFeat != shading::kPbrAny) {
      if (sh.hasColor || sc.hasColor) return false;
      const int32_t mat = sc.draws(drawOf(sc.triDraw, sc.drawTriStart, sc.numDraws, sc.tris(i).prim)).material;
      if (mat < 0) return false;  // the spec's default material is lit
      const MaterialGPU& m = sh.materials(mat);  // PbrTri::m
      const MaterialGPU& ma = sc.materials(mat);  // AlphaTri's alpha and texture
      if (!(m.flags & kMaterialUnlit) || sh.pbrTextured(m) || (ma.texture >= 0 && sc.hasUV)) return false;
      c = float4{m.baseColor.x, m.baseColor.y, m.baseColor.z, cleanAlpha(ma.baseColor.w)};
      return true;
    } else {
      return false;
    }
  }
  // Weighted blended OIT's weight (McGuire and Bavoil 2013, eq. 7) at window depth d.
  RAST_GPU_INLINE float weight(float d) const {
    return weightOf(d, sh.p.frame(0).camera.znear, sh.p.frame(0).camera.zfar);
  }
  // The same with the camera's near and far planes n and f given (a loop over
  // many fragments: peel_block.h).
  RAST_GPU_INLINE static float weightOf(float d, const float n, const float f) {
    const float z = 2.0f * n * f / ((f + n) - (2.0f * d - 1.0f) * (f - n));
    const float a = z / 5.0f, b = z / 200.0f, b2 = b * b;
    const float w = 10.0f / (1e-5f + a * a + b2 * b2 * b2);
    return w < 1e-2f ? 1e-2f : (w > 3e3f ? 3e3f : w);
  }
  // sorted: the draw's bounding box centre, its depth in view space, nearest
  // first; within a draw, later triangles first (drawn last, they lie on top).
  RAST_GPU_INLINE uint64_t sortedKey(uint32_t draw, uint32_t i) const {
    const float* m = sh.draws(draw).modelF.m;
    const float3 c = sc.alphaDraws(draw).centre;
    const float wx = m[0] * c.x + m[4] * c.y + m[8] * c.z + m[12];
    const float wy = m[1] * c.x + m[5] * c.y + m[9] * c.z + m[13];
    const float wz = m[2] * c.x + m[6] * c.y + m[10] * c.z + m[14];
    const float* v = sh.p.frame(0).camera.view.m;
    const float depth = -(v[2] * wx + v[6] * wy + v[10] * wz + v[14]);
    return uint64_t(orderBits(depth)) << 32 | uint64_t(0xffffffffu - i);
  }
};

// The raster index in a key: exact's keys end in index + 1, sorted's in ~index.
KOKKOS_INLINE_FUNCTION uint32_t keyIndex(uint64_t key, bool sorted) {
  return sorted ? 0xffffffffu - uint32_t(key) : uint32_t(key) - 1u;
}

// Front to back, premultiplied, in linear light.
RAST_GPU_INLINE void over(float3& acc, float& T, const float4 c) {
  acc = acc + float3{c.x, c.y, c.z} * (T * c.w);
  T = T * (1.0f - c.w);
}

// A sample's result over its opaque colour: overOpaque (base/color.h).

// Weighted blended OIT (McGuire and Bavoil 2013): a fragment's terms of the
// sample's sums (premultiplied colour and alpha times its weight w) and of
// its revealage (the product of 1 - alpha); from them, what lies in front:
// the sums' average colour at coverage 1 - revealage. The tile lists' walk
// (peel.h) adds the terms in raster-index order; the fixed-memory collect
// (blend_passes.cpp) adds the same terms with atomics, in any order.
KOKKOS_INLINE_FUNCTION void weightedTerms(float4& sum, float& reveal, const float4 c, const float w) {
  sum.x += c.x * c.w * w;
  sum.y += c.y * c.w * w;
  sum.z += c.z * c.w * w;
  sum.w += c.w * w;
  reveal *= 1.0f - c.w;
}
KOKKOS_INLINE_FUNCTION void weightedFront(const float4 sum, const float reveal, float3& acc, float& T) {
  acc = float3{0.0f, 0.0f, 0.0f};
  T = 1.0f;
  if (sum.w > 0.0f) {
    T = reveal;
    acc = float3{sum.x, sum.y, sum.z} * ((1.0f - T) / sum.w);
  }
}

// The resolves' per-thread lookups (AlphaTri, TriFrag, and PbrTri for the
// glTF shading) of the last N triangles shaded: the layers over neighbouring
// pixels are mostly the same few triangles, and one entry re-prepared for each
// fragment of a pixel of 8 layers cost more than the shading. A GPU keeps one
// entry (registers).
template <int N, int kFam = kFragGeneral>
struct FragCacheOf {
  AlphaTri a[N];
  TriFrag tf[N];
  FragPbrTri<kFam> pt[N];
  int next = 0, hint = 0;
  // The entry of `index`, else the oldest. Pixels side by side composite
  // the same triangles in the same order: the entry after the last one used
  // is tried first.
  KOKKOS_INLINE_FUNCTION int slot(uint32_t index) {
    int k = hint;
    if (a[k].index != index) {
      for (k = 0; k < N && a[k].index != index; ++k) {
      }
      if (k == N) {
        k = next;
        next = next + 1 == N ? 0 : next + 1;
      }
    }
    hint = k + 1 == N ? 0 : k + 1;
    return k;
  }
  // A CPU entry's edge values at its last fragment (row evY, sample evS,
  // pixel evX): the next pixel along the row steps them by A (exact
  // integers, the values eval gives) instead of evaluating the edges again.
  int64_t ev[N][3];
  int32_t evX[N], evY[N], evS[N];
  template <int kFeat = 0>
  RAST_GPU_INLINE float4 at(const FragShade& fs, uint32_t index, int32_t X, int32_t Y, int s) {
    if constexpr (N == 1 || kFam == kFragGeneral) {
      const int e = N == 1 ? 0 : slot(index);
      return fs.template at<kFam, kFeat>(index, X, Y, s, a[e], tf[e], pt[e]);
    } else {
      const int e = slot(index);
      if (a[e].index != index) fs.sc.prepare(index, a[e]);
      const bool fresh = fs.template use<kFam>(index, tf[e], pt[e]);
      const Edges& E = tf[e].e;
      int64_t(&v)[3] = ev[e];
      if (fresh || evY[e] != Y || evS[e] != s || evX[e] >= X) {
        const int32_t ox = fs.sp.ox[s], oy = fs.sp.oy[s];
        for (int i = 0; i < 3; ++i) v[i] = E.sample(i, X, Y, ox, oy);
      } else {
        for (int i = 0; i < 3; ++i) v[i] += E.A[i] * int64_t(X - evX[e]);
      }
      evX[e] = X;
      evY[e] = Y;
      evS[e] = s;
      return fs.template shadeAt<kFam, kFeat>(X, Y, s, v[0], v[1], v[2], a[e], tf[e], pt[e]);
    }
  }
};
constexpr int kResolveCache = kOnDevice ? 1 : 8;
template <int kFam = kFragGeneral>
using FragCache = FragCacheOf<kResolveCache, kFam>;

// The frame's fragment family and features (above): go.template run<kFam,
// kFeat>() with them. A family or PbrFeature added without its case here
// does not compile (the switch over FragFamily has no default; -Wswitch).
FragFamily fragFamily(const FragShade& fs);
FragFamily fragFamily(const ShadeParams& p);
template <class Go>
void withFragPath(const FragShade& fs, Go&& go) {
  using shading::kPbrClearcoat;
  using shading::kPbrEnv;
  using shading::kPbrPunctual;
  using shading::kPbrTextured;
  static_assert((kPbrTextured | kPbrEnv | kPbrPunctual) == 7 && kPbrClearcoat == 8,
                "withFragPath takes three glTF shading features and the clear coat's instance");
  const Shade& k = fs.sh;
  switch (fragFamily(fs)) {
    case kFragGeneral: return go.template run<kFragGeneral, 0>();
    case kFragLit: return k.hasColor ? go.template run<kFragLit, 1>() : go.template run<kFragLit, 0>();
    case kFragPbr:
      if (k.hasClearcoat) return go.template run<kFragPbr, kPbrClearcoat>();
      switch ((k.hasUV ? kPbrTextured : 0) | (k.p.useEnv ? kPbrEnv : 0) | (k.numPunctual > 0 ? kPbrPunctual : 0)) {
        case 0: return go.template run<kFragPbr, 0>();
        case 1: return go.template run<kFragPbr, 1>();
        case 2: return go.template run<kFragPbr, 2>();
        case 3: return go.template run<kFragPbr, 3>();
        case 4: return go.template run<kFragPbr, 4>();
        case 5: return go.template run<kFragPbr, 5>();
        case 6: return go.template run<kFragPbr, 6>();
        default: return go.template run<kFragPbr, 7>();
      }
  }
}

FragShade makeFragShade(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights);

// The methods that walk tile lists (blend_tiles.cpp: exact, sorted,
// weighted): the lists, built before shading (they read the opaque depth;
// with the uniform blocks' buffers under the team form of fragment family
// `fam`), and the resolve after it (which first puts weighted's in
// raster-index order).
void tileLists(FrameBuffers& f, const DView<uint64_t>& opaqueKeys, FragFamily fam, bool copyDepth);
void peelResolve(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights,
                 const BlendPlan& b);
// Whether the specialised fragment families resolve a team a block (GPUs;
// host backends under TestHooks::teamResolve).
bool teamForm();
// Whether family `fam` resolves with the uniform blocks (uniform_blocks.h):
// the glTF shading in its team form. The lists' buffers, the classification,
// the longest list's count and the shade stage's composite all follow it.
inline bool uniformBlocksOn(const FragFamily fam) { return fam == kFragPbr && teamForm(); }
// Where the shade stage composites the uniform blocks (BlendPlan::shadeComposite):
// their classification (uniform_blocks.h), after the lists and before
// shading, from the opaque keys' depth.
void uniformBlocksBeforeShading(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p,
                                const DView<LightGPU>& lights, const BlendPlan& b, const DView<uint64_t>& opaqueKeys);

}  // namespace blending
}  // namespace rast
