// What the BLEND passes share (docs/transparency.md): a fragment's colour and
// alpha at one sample (the shade stage's fragment maths and alpha_fragment.h),
// the sort keys of the exact and sorted methods, "over", and the lookups a
// thread keeps across the fragments it shades. The kbuffer and weighted
// passes (blend_passes.cpp) and the exact and sorted methods' tile lists
// (blend_tiles.cpp) composite with the same functions, so that kbuffer with
// k >= layers gives exact's bits.
#pragma once

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
    const Edges& e = tf.e;  // Edges(t), set up once per triangle by use()
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
  // sorted: the draw's bounding box centre, its depth in view space, nearest
  // first; within a draw, later triangles first (drawn last, they lie on top).
  KOKKOS_INLINE_FUNCTION uint64_t sortedKey(uint32_t draw, uint32_t i) const {
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
KOKKOS_INLINE_FUNCTION void over(float3& acc, float& T, const float4 c) {
  acc = acc + float3{c.x, c.y, c.z} * (T * c.w);
  T = T * (1.0f - c.w);
}

// A sample's result: what lies in front (acc, transmittance T) over its
// opaque colour; the film's alpha composited the same way.
KOKKOS_INLINE_FUNCTION float4 overOpaque(const float3 acc, float T, const float4 opq) {
  return float4{acc.x + T * opq.x, acc.y + T * opq.y, acc.z + T * opq.z, 1.0f - T * (1.0f - opq.w)};
}

// The resolves' per-thread lookups (AlphaTri, TriFrag) of the last N
// triangles shaded: the layers over neighbouring pixels are mostly the same
// few triangles, and one entry re-prepared for each fragment of a pixel of 8
// layers cost more than the shading. A GPU keeps one entry (registers).
template <int N>
struct FragCacheOf {
  AlphaTri a[N];
  TriFrag tf[N];
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
  KOKKOS_INLINE_FUNCTION float4 at(const FragShade& fs, uint32_t index, int32_t X, int32_t Y, int s) {
    const int e = slot(index);
    return fs.at(index, X, Y, s, a[e], tf[e]);
  }
};
constexpr int kResolveCache = kOnDevice ? 1 : 8;
using FragCache = FragCacheOf<kResolveCache>;

FragShade makeFragShade(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights);

// The exact and sorted methods (blend_tiles.cpp): the tile lists, built
// before shading (they read the opaque depth), and the resolve after it.
void tileLists(FrameBuffers& f);
void peelResolve(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights,
                 bool sorted);

}  // namespace blending
}  // namespace rast
