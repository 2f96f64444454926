// The arithmetic of a span, apart from the kernel that walks the rows
// (shade_spans.h): the span arrays' sizes, the per-triangle constants
// (SpanConsts), one pixel's weights, normal and headlight (litPixel), the
// loops that run litPixel over a span's pixels (spanLighting and its lane and
// AVX-512/AVX2 variants) and the packing of lit colours to sRGB RGBA8.
//
// It exists on its own because it is the part that must stay bit-identical
// to Shade::shadeFragment: every expression here is the per-pixel shader's,
// in the same order and without contraction, written as plain loops over
// small arrays so that the compiler vectorizes them. The texturing
// (span_texture.h), the lane batches (lane_batch.h) and the kernel build on it.
#pragma once

#include "backends/cpu_clones.h"
#include "pipeline/shade/shade_fragment.h"

namespace rast {
namespace shading {

constexpr int kMaxSpanRun = 64;  // longest run a ShadeSpans work item takes
// A span of kSpanWideMin pixels or more runs the wide (AVX-512 or AVX2) loops
// over whole blocks of kSpanBlock pixels (past the span's end into the spare
// room of its arrays, extrapolating the plane; nothing past the end is stored
// outside them), so that a short span is one vector instead of a scalar
// remainder loop. A single pixel (most of them on scenes of tiny triangles) runs the
// inline loops over itself only. (Measured on duck, cow, engine, tiny: 2
// beats 4 and 8.)
constexpr int kSpanBlock = 8;
constexpr int kSpanWideMin = 2;
static_assert(kMaxSpanRun % kSpanBlock == 0, "span arrays hold whole blocks");
KOKKOS_INLINE_FUNCTION int32_t spanBlocks(int32_t m) { return (m + kSpanBlock - 1) & ~(kSpanBlock - 1); }

// What spanLighting needs of a span's triangle, the camera and the light.
struct SpanConsts {
  double s0, s1, s2, a0, a1, a2;  // edge values at the span's first pixel, steps per pixel
  // E_i(X, Y) = a_i X + r_i Y + k_i at any pixel: every term and partial sum
  // is an integer below 2^50 (raster_rules.h), so double evaluates it exactly,
  // in any order, and equals Edges::eval.
  double r0, r1, r2, k0, k1, k2;
  float ia, iw0, iw1, iw2;        // 1 / area, per-vertex 1/w (1 when affine)
  float t00, t10, t20, t01, t11, t21;  // raster vertices' barycentrics in the drawn triangle
  float3 n0, n1, n2, q0, q1, q2;  // drawn vertices' world normals and positions
  float3 eye;
  float ambient, headI;           // headI: the headlight's intensity, 0 without it
};

// Every field of k but the span's own (s0, s1, s2) for triangle f (its
// set-up, TriFrag) at sample offset (ox, oy) of every pixel: the opaque span
// shading's at the pixel centre (shade_spans.h) and the BLEND resolve's lit
// block rows at a sample (pipeline/blend/blend_tiles.cpp).
KOKKOS_INLINE_FUNCTION void fillSpanConsts(SpanConsts& k, const shading::TriFrag& f, int32_t ox, int32_t oy,
                                           bool perspective, float3 eye, float ambient, float headI) {
  const RasterTri& t = *f.t;
  const Edges& e = f.e;
  k.a0 = double(e.A[0]);
  k.a1 = double(e.A[1]);
  k.a2 = double(e.A[2]);
  k.r0 = double(e.B[0]);
  k.r1 = double(e.B[1]);
  k.r2 = double(e.B[2]);
  k.k0 = double(e.atSample(0, e.C[0], ox, oy));
  k.k1 = double(e.atSample(1, e.C[1], ox, oy));
  k.k2 = double(e.atSample(2, e.C[2], ox, oy));
  k.ia = t.invArea;
  k.iw0 = perspective ? t.invW[0] : 1.0f;
  k.iw1 = perspective ? t.invW[1] : 1.0f;
  k.iw2 = perspective ? t.invW[2] : 1.0f;
  k.t00 = t.bary[0][0]; k.t10 = t.bary[1][0]; k.t20 = t.bary[2][0];
  k.t01 = t.bary[0][1]; k.t11 = t.bary[1][1]; k.t21 = t.bary[2][1];
  k.n0 = f.n[0]; k.n1 = f.n[1]; k.n2 = f.n[2];
  k.q0 = f.pos[0]; k.q1 = f.pos[1]; k.q2 = f.pos[2];
  k.eye = eye;
  k.ambient = ambient;
  k.headI = headI;
}

// One pixel of spanLightingFrom's loop (and of laneLighting's): from the
// screen-space weights times 1/w (w0..w2), the weights in the drawn triangle
// (c0..c2), the unit normal and the headlight's diffuse term, as
// Shade::shadeFragment computes them. Forced inline, so that both loops
// vectorize over it.
KOKKOS_FORCEINLINE_FUNCTION void litPixel(float w0, float w1, float w2, float t00, float t10, float t20, float t01,
                                          float t11, float t21, float3 n0, float3 n1, float3 n2, float3 q0, float3 q1,
                                          float3 q2, float3 eye, float ambient, float headI, float& c0, float& c1,
                                          float& c2, float& nx, float& ny, float& nz, float& diffuse) {
  const float third = 1.0f / 3.0f;
  const float sum = w0 + w1 + w2;
  const bool ok = (sum != 0.0f) & (sum - sum == 0.0f);  // nonzero and finite (isFinite); no branch
  const float inv = 1.0f / sum;
  w0 = ok ? w0 * inv : third;
  w1 = ok ? w1 * inv : third;
  w2 = ok ? w2 * inv : third;
  c1 = w0 * t00 + w1 * t10 + w2 * t20;
  c2 = w0 * t01 + w1 * t11 + w2 * t21;
  c0 = 1.0f - c1 - c2;
  // normalize() of the interpolated normal
  float x = n0.x * c0 + n1.x * c1 + n2.x * c2, y = n0.y * c0 + n1.y * c1 + n2.y * c2,
        z = n0.z * c0 + n1.z * c1 + n2.z * c2;
  float l2 = x * x + y * y + z * z;
  float s = 1.0f / ::sqrtf(l2 > 0.0f ? l2 : 1.0f);
  x = l2 > 0.0f ? x * s : 0.0f;
  y = l2 > 0.0f ? y * s : 0.0f;
  z = l2 > 0.0f ? z * s : 0.0f;
  nx = x;
  ny = y;
  nz = z;
  const float Px = q0.x * c0 + q1.x * c1 + q2.x * c2, Py = q0.y * c0 + q1.y * c1 + q2.y * c2,
              Pz = q0.z * c0 + q1.z * c1 + q2.z * c2;
  // The headlight: L = V = normalize(eye - P), intensity 1 - ambient.
  float vx = eye.x - Px, vy = eye.y - Py, vz = eye.z - Pz;
  l2 = vx * vx + vy * vy + vz * vz;
  s = 1.0f / ::sqrtf(l2 > 0.0f ? l2 : 1.0f);
  vx = l2 > 0.0f ? vx * s : 0.0f;
  vy = l2 > 0.0f ? vy * s : 0.0f;
  vz = l2 > 0.0f ? vz * s : 0.0f;
  const float ndl = x * vx + y * vy + z * vz;
  diffuse = ambient + headI * (ndl > 0.0f ? ndl : 0.0f);  // exactly ambient without the headlight
}

// The arithmetic of a span, as loops over its pixels that the compiler
// vectorizes (also for AVX-512 and AVX2: cpu_clones.h): spanLighting for a row span,
// spanLightingLanes for pixels given by their coordinates; both then
// spanLightingFrom the screen-space weights.
KOKKOS_FORCEINLINE_FUNCTION void spanLightingFrom(const SpanConsts& k, int32_t m, float* __restrict__ b0,
                                                  float* __restrict__ b1, float* __restrict__ b2, float* __restrict__ nx,
                                                  float* __restrict__ ny, float* __restrict__ nz,
                                                  float* __restrict__ diffuse);
KOKKOS_FORCEINLINE_FUNCTION void spanLighting(const SpanConsts& k, int32_t m, float* __restrict__ b0, float* __restrict__ b1, float* __restrict__ b2, float* __restrict__ nx,
                                     float* __restrict__ ny, float* __restrict__ nz, float* __restrict__ diffuse) {
  // The edge values step in double, exactly (integers below 2^53), and
  // float(double(e)) rounds as float(e) does, so the weights are
  // bit-identical; unlike int64 -> float, double -> float conversion vectorizes.
  for (int32_t j = 0; j < m; ++j) {
    b0[j] = float(k.s1 + k.a1 * double(j)) * k.ia;
    b1[j] = float(k.s2 + k.a2 * double(j)) * k.ia;
    b2[j] = float(k.s0 + k.a0 * double(j)) * k.ia;
  }
  spanLightingFrom(k, m, b0, b1, b2, nx, ny, nz, diffuse);
}
// X, Y: each pixel's coordinates; its exact edge values come from the
// plane equations in double (SpanConsts), in the vector loop.
KOKKOS_FORCEINLINE_FUNCTION void spanLightingLanes(const SpanConsts& k, int32_t m, const int32_t* __restrict__ X,
                                                   const int32_t* __restrict__ Y,
                                                   float* __restrict__ b0, float* __restrict__ b1, float* __restrict__ b2,
                                                   float* __restrict__ nx, float* __restrict__ ny, float* __restrict__ nz,
                                                   float* __restrict__ diffuse) {
  for (int32_t j = 0; j < m; ++j) {
    const double x = double(X[j]), y = double(Y[j]);
    b0[j] = float(k.a1 * x + k.r1 * y + k.k1) * k.ia;
    b1[j] = float(k.a2 * x + k.r2 * y + k.k2) * k.ia;
    b2[j] = float(k.a0 * x + k.r0 * y + k.k0) * k.ia;
  }
  spanLightingFrom(k, m, b0, b1, b2, nx, ny, nz, diffuse);
}
KOKKOS_FORCEINLINE_FUNCTION void spanLightingFrom(const SpanConsts& k, int32_t m, float* __restrict__ b0,
                                                  float* __restrict__ b1, float* __restrict__ b2, float* __restrict__ nx,
                                                  float* __restrict__ ny, float* __restrict__ nz,
                                                  float* __restrict__ diffuse) {
  const float iw0 = k.iw0, iw1 = k.iw1, iw2 = k.iw2;
  const float t00 = k.t00, t10 = k.t10, t20 = k.t20, t01 = k.t01, t11 = k.t11, t21 = k.t21;
  const float3 n0 = k.n0, n1 = k.n1, n2 = k.n2, q0 = k.q0, q1 = k.q1, q2 = k.q2, eye = k.eye;
  const float ambient = k.ambient, headI = k.headI;
  for (int32_t j = 0; j < m; ++j)
    litPixel(b0[j] * iw0, b1[j] * iw1, b2[j] * iw2, t00, t10, t20, t01, t11, t21, n0, n1, n2, q0, q1, q2, eye, ambient,
             headI, b0[j], b1[j], b2[j], nx[j], ny[j], nz[j], diffuse[j]);
}
RAST_CPU_CLONES void spanLightingLanesWide(const SpanConsts& k, int32_t m, const int32_t* __restrict__ X,
                                           const int32_t* __restrict__ Y,
                                           float* __restrict__ b0, float* __restrict__ b1, float* __restrict__ b2,
                                           float* __restrict__ nx, float* __restrict__ ny, float* __restrict__ nz,
                                           float* __restrict__ diffuse) {
  spanLightingLanes(k, m, X, Y, b0, b1, b2, nx, ny, nz, diffuse);
}
// The same, built also for AVX-512 and AVX2; worth its indirect call on longer spans.
RAST_CPU_CLONES void spanLightingWide(const SpanConsts& k, int32_t m, float* __restrict__ b0, float* __restrict__ b1,
                                      float* __restrict__ b2, float* __restrict__ nx, float* __restrict__ ny,
                                      float* __restrict__ nz, float* __restrict__ diffuse) {
  spanLighting(k, m, b0, b1, b2, nx, ny, nz, diffuse);
}

// A span's colours (r, g, b, a: the base colour), lit and packed as sRGB
// RGBA8 (Shade::display of shadeFragment's rgb * diffuse + spec, spec being 0
// in Lambert).
KOKKOS_FORCEINLINE_FUNCTION void packSpan(int32_t mb, int32_t m, const float* __restrict__ r, const float* __restrict__ g,
                                     const float* __restrict__ b, const float* __restrict__ a,
                                     const float* __restrict__ diffuse, const uint32_t* __restrict__ table,
                                     uint32_t* __restrict__ dst) {
  uint32_t packed[kMaxSpanRun];  // mb lanes computed, the span's m stored
  for (int32_t j = 0; j < mb; ++j) {
    const float d = diffuse[j];
    const float al = clamp01(a[j]) * 255.0f + 0.5f;  // unorm8, in [0.5, 255.5]: int conversion is exact
    packed[j] = encodeSrgb8Packed(r[j] * d + 0.0f, table) | encodeSrgb8Packed(g[j] * d + 0.0f, table) << 8 |
                encodeSrgb8Packed(b[j] * d + 0.0f, table) << 16 | uint32_t(int32_t(al)) << 24;
  }
  const int32_t n = m < mb ? m : mb;  // m <= mb (the bound helps the compiler see packed[] is set)
  for (int32_t j = 0; j < n; ++j) dst[j] = packed[j];  // the span only
}
// Table lookups per channel: no AVX-512 variant (cpu_clones.h).
RAST_CPU_CLONES_GATHER void packSpanWide(int32_t mb, int32_t m, const float* __restrict__ r, const float* __restrict__ g,
                                         const float* __restrict__ b, const float* __restrict__ a,
                                         const float* __restrict__ diffuse, const uint32_t* __restrict__ table,
                                         uint32_t* __restrict__ dst) {
  packSpan(mb, m, r, g, b, a, diffuse, table, dst);
}

}  // namespace shading
}  // namespace rast
