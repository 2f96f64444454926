// The CPU's shade kernel for Lambert shading with one sample per pixel: a work
// item takes a run of pixels along a row (kShadeRun), cuts it into spans of
// one triangle, and shades each span a stage at a time over small arrays
// (barycentrics, normals, positions, lighting for every pixel of the span,
// then texturing, then packing), so that the compiler turns the arithmetic
// stages into SIMD loops over pixels instead of one scalar fragment at a time.
//
// Every value is computed by the same operations in the same order as
// Shade::shadeFragment (edge values exactly in integers, then the same float
// expressions, no contraction), so the image is bit-identical to the per-pixel
// kernel's; only the order in which pixels are visited differs. Pixels of
// points and lines, and frames this kernel does not cover (other modes,
// trilinear filtering, MSAA, normals or SSAO outputs), use the per-pixel
// shader (see usable()).
#pragma once

#include "../backends/bit_scan.h"
#include "../backends/cpu_clones.h"
#include "shade_fragment.h"

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
  // is an integer below 2^50 (raster_common.h), so double evaluates it exactly,
  // in any order, and equals Edges::eval.
  double r0, r1, r2, k0, k1, k2;
  float ia, iw0, iw1, iw2;        // 1 / area, per-vertex 1/w (1 when affine)
  float t00, t10, t20, t01, t11, t21;  // raster vertices' barycentrics in the drawn triangle
  float3 n0, n1, n2, q0, q1, q2;  // drawn vertices' world normals and positions
  float3 eye;
  float ambient, headI;           // headI: the headlight's intensity, 0 without it
};

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

// Bilinear texturing of a span (Shade::shadeFragment's uvAt and
// sampleBilinear, the same float operations in the same order), in two loops
// the compiler vectorizes: where each pixel's four texels are and their
// weights, then the fetches (gathers with AVX2), sRGB decoding and blend.
struct SpanTex {
  const uint32_t* texels;  // the texture's level 0
  const float* lut;        // sRGB byte -> linear
  int32_t width, height, wrapS, wrapT;
  float u0, u1, u2, v0, v1, v2;  // the drawn vertices' texture coordinates
  int32_t indexable;             // fewer than 2^31 texels: int32 indices (else: per pixel)
};

// Float selects on the bits: GCC turns float ?: into branches that its
// if-conversion then refuses, so that a loop of them does not vectorize.
KOKKOS_FORCEINLINE_FUNCTION float selectFloat(bool c, float a, float b) {
  const uint32_t mask = 0u - uint32_t(c);
  return bitsFloat((floatBits(a) & mask) | (floatBits(b) & ~mask));
}

// floorTexel (the host's) without branches: the same value for every input.
// Magnitudes from 2^23 up, infinities and NaN are their own floor; the
// conversion sees +0 for them.
KOKKOS_FORCEINLINE_FUNCTION float floorTexelFlat(float x) {
  const bool small = (floatBits(x) & 0x7fffffffu) < 0x4b000000u;  // |x| < 2^23
  const float xs = selectFloat(small, x, 0.0f);
  const float t = float(int32_t(xs));  // towards zero
  const float f = t - selectFloat(t > xs, 1.0f, 0.0f);  // t - 0 is t (t is never -0)
  return selectFloat(small, f, x);
}

// reduceCoord without branches.
KOKKOS_FORCEINLINE_FUNCTION float reduceCoordFlat(float u, int32_t mode) {
  const float clamped = selectFloat(u < -1.0f, -1.0f, selectFloat(u > 2.0f, 2.0f, u));
  const float periodic = u - 2.0f * floorTexelFlat(u * 0.5f);
  return selectFloat(isFinite(u), mode == WrapClamp ? clamped : periodic, 0.0f);
}

// wrapIndex without branches or division, for the indices reduceCoordFlat's
// coordinates give (repeat and mirror: within [-1, 2n]); `bad` is set where i
// lies outside the range where these forms equal wrapIndex (then the caller
// samples per pixel).
KOKKOS_FORCEINLINE_FUNCTION int32_t wrapIndexFlat(int32_t i, int32_t n, int32_t mode, int32_t& bad) {
  const int32_t c = i < 0 ? 0 : (i >= n ? n - 1 : i);
  int32_t r = i < 0 ? i + n : i;  // repeat, for i in [-n, 3n)
  r = r >= n ? r - n : r;
  r = r >= n ? r - n : r;
  const int32_t p2 = 2 * n;
  int32_t q = i < 0 ? i + p2 : i;  // mirror, for i in [-2n, 4n)
  q = q >= p2 ? q - p2 : q;
  q = q < n ? q : p2 - 1 - q;
  bad |= (mode != WrapClamp) & ((i < -n) | (i >= 3 * n));
  return mode == WrapClamp ? c : (mode == WrapMirror ? q : r);
}

// One pixel of bilinearSetup; kRepeat: both wrap modes are repeat (the
// common case: the other modes' selects are left out).
template <bool kRepeat>
KOKKOS_FORCEINLINE_FUNCTION void bilinearPixel(const SpanTex& t, int32_t j, const float* __restrict__ b0,
                                          const float* __restrict__ b1, const float* __restrict__ b2,
                                          int32_t* __restrict__ i00, int32_t* __restrict__ i10,
                                          int32_t* __restrict__ i01, int32_t* __restrict__ i11,
                                          float* __restrict__ fa, float* __restrict__ fb, int32_t& bad) {
  const int32_t w = t.width, h = t.height, ws = kRepeat ? int32_t(WrapRepeat) : t.wrapS,
                wt = kRepeat ? int32_t(WrapRepeat) : t.wrapT;
  const float u = t.u0 * b0[j] + t.u1 * b1[j] + t.u2 * b2[j], v = t.v0 * b0[j] + t.v1 * b1[j] + t.v2 * b2[j];  // uvAt
  const float fu = reduceCoordFlat(u, ws) * float(w) - 0.5f, fv = reduceCoordFlat(v, wt) * float(h) - 0.5f;
  const float flu = floorTexelFlat(fu), flv = floorTexelFlat(fv);
  fa[j] = fu - flu;
  fb[j] = fv - flv;
  const int32_t x0 = int32_t(flu), y0 = int32_t(flv);
  uint32_t xa, xb, ya, yb;
  if (kRepeat) {  // repeat: wrap(i + 1) is wrap(i) + 1, or 0 past the end
    const int32_t wa = wrapIndexFlat(x0, w, ws, bad), ha = wrapIndexFlat(y0, h, wt, bad);
    xa = uint32_t(wa);
    xb = uint32_t(wa + 1 == w ? 0 : wa + 1);
    ya = uint32_t(ha);
    yb = uint32_t(ha + 1 == h ? 0 : ha + 1);
  } else {
    xa = uint32_t(wrapIndexFlat(x0, w, ws, bad));
    xb = uint32_t(wrapIndexFlat(x0 + 1, w, ws, bad));
    ya = uint32_t(wrapIndexFlat(y0, h, wt, bad));
    yb = uint32_t(wrapIndexFlat(y0 + 1, h, wt, bad));
  }
  // below 2^31: a texture's texels are counted in int32 (DeviceScene); signed
  // indices let AVX2 gather them
  i00[j] = int32_t(ya * uint32_t(w) + xa);
  i10[j] = int32_t(ya * uint32_t(w) + xb);
  i01[j] = int32_t(yb * uint32_t(w) + xa);
  i11[j] = int32_t(yb * uint32_t(w) + xb);
}

// Texel indices (i00 .. i11, from the texture's first texel) and the weights'
// fractions (fa, fb) of m lanes of a span; returns nonzero if
// some index is outside what wrapIndexFlat covers.
KOKKOS_FORCEINLINE_FUNCTION int32_t bilinearSetup(const SpanTex& tr, int32_t m, const float* __restrict__ b0,
                                             const float* __restrict__ b1, const float* __restrict__ b2,
                                             int32_t* __restrict__ i00, int32_t* __restrict__ i10,
                                             int32_t* __restrict__ i01, int32_t* __restrict__ i11,
                                             float* __restrict__ fa, float* __restrict__ fb) {
  const SpanTex t = tr;  // a local copy: its fields stay in registers across the loop
  int32_t bad = 0;
  if (t.wrapS == WrapRepeat && t.wrapT == WrapRepeat) {
    for (int32_t j = 0; j < m; ++j) bilinearPixel<true>(t, j, b0, b1, b2, i00, i10, i01, i11, fa, fb, bad);
  } else {
    for (int32_t j = 0; j < m; ++j) bilinearPixel<false>(t, j, b0, b1, b2, i00, i10, i01, i11, fa, fb, bad);
  }
  return bad;
}
RAST_CPU_CLONES int32_t bilinearSetupWide(const SpanTex& t, int32_t m, const float* __restrict__ b0,
                                          const float* __restrict__ b1, const float* __restrict__ b2,
                                          int32_t* __restrict__ i00, int32_t* __restrict__ i10,
                                          int32_t* __restrict__ i01, int32_t* __restrict__ i11,
                                          float* __restrict__ fa, float* __restrict__ fb) {
  return bilinearSetup(t, m, b0, b1, b2, i00, i10, i01, i11, fa, fb);
}

// The four texels of each pixel, decoded and blended as sampleBilinear does,
// times the base colour (r, g, b, a: base * texture).
KOKKOS_FORCEINLINE_FUNCTION void bilinearBlend(const uint32_t* __restrict__ tx, const float* __restrict__ lut, int32_t m,
                                          const int32_t* __restrict__ i00, const int32_t* __restrict__ i10,
                                          const int32_t* __restrict__ i01, const int32_t* __restrict__ i11,
                                          const float* __restrict__ fa, const float* __restrict__ fb,
                                          float* __restrict__ r, float* __restrict__ g, float* __restrict__ b,
                                          float* __restrict__ a) {
  for (int32_t j = 0; j < m; ++j) {
    const uint32_t c00 = tx[i00[j]], c10 = tx[i10[j]], c01 = tx[i01[j]], c11 = tx[i11[j]];
    const float A = fa[j], B = fb[j];
    const float w00 = (1.0f - A) * (1.0f - B), w10 = A * (1.0f - B), w01 = (1.0f - A) * B, w11 = A * B;
    r[j] = r[j] * ((lut[int32_t(c00 & 0xff)] * w00 + lut[int32_t(c10 & 0xff)] * w10) + (lut[int32_t(c01 & 0xff)] * w01 + lut[int32_t(c11 & 0xff)] * w11));
    g[j] = g[j] * ((lut[int32_t((c00 >> 8) & 0xff)] * w00 + lut[int32_t((c10 >> 8) & 0xff)] * w10) +
                   (lut[int32_t((c01 >> 8) & 0xff)] * w01 + lut[int32_t((c11 >> 8) & 0xff)] * w11));
    b[j] = b[j] * ((lut[int32_t((c00 >> 16) & 0xff)] * w00 + lut[int32_t((c10 >> 16) & 0xff)] * w10) +
                   (lut[int32_t((c01 >> 16) & 0xff)] * w01 + lut[int32_t((c11 >> 16) & 0xff)] * w11));
    // unpackSrgb8's alpha, float(c >> 24) / 255 (below 256: the int conversion is the same)
    const float a00 = float(int32_t(c00 >> 24)) * (1.0f / 255.0f), a10 = float(int32_t(c10 >> 24)) * (1.0f / 255.0f);
    const float a01 = float(int32_t(c01 >> 24)) * (1.0f / 255.0f), a11 = float(int32_t(c11 >> 24)) * (1.0f / 255.0f);
    a[j] = a[j] * ((a00 * w00 + a10 * w10) + (a01 * w01 + a11 * w11));
  }
}
// Sixteen table lookups a pixel: no AVX-512 variant (cpu_clones.h).
RAST_CPU_CLONES_GATHER void bilinearBlendWide(const uint32_t* __restrict__ tx, const float* __restrict__ lut, int32_t m,
                                              const int32_t* __restrict__ i00, const int32_t* __restrict__ i10,
                                              const int32_t* __restrict__ i01, const int32_t* __restrict__ i11,
                                              const float* __restrict__ fa, const float* __restrict__ fb,
                                              float* __restrict__ r, float* __restrict__ g, float* __restrict__ b,
                                              float* __restrict__ a) {
  bilinearBlend(tx, lut, m, i00, i10, i01, i11, fa, fb, r, g, b, a);
}

// Where the runs of equal ids of a row of n <= kRunMaskBits pixels start: bit j is set
// where idx[j] differs from idx[j - 1] (bit 0 always), in one pass without
// branches. A search for each run's end (the earlier runEnd) mispredicted
// its exit about once a run: duck 800x800 2.15 -> 2.03 ms with the mask, cow
// 1.53 -> 1.42. A row of one run (a large triangle's, the background) is
// told first by a cheaper vectorized test: bigtri 1080p 5.48 -> 5.02 ms.
constexpr int32_t kRunMaskBits = 64;  // the longest row runStarts takes
KOKKOS_FORCEINLINE_FUNCTION uint64_t runStarts(const uint32_t* __restrict__ idx, int32_t n) {
  uint32_t differs = 0;
  for (int32_t j = 1; j < n; ++j) differs |= idx[j] ^ idx[0];
  if (differs == 0) return 1;
  uint64_t starts = 1;
  for (int32_t j = 1; j < n; ++j) starts |= uint64_t(idx[j] != idx[j - 1]) << j;
  return starts;
}
static_assert(kMaxSpanRun <= kRunMaskBits, "shadeTile finds a row's runs with one runStarts");

// Pixels of short runs of different triangles, shaded together as the lanes
// of one vector (ShadeSpans::shadeRow). On scenes of tiny triangles nearly
// every pixel is a triangle of its own, and a span of one pixel ran the
// span's loops over a single lane: a chain of dependent divisions and square
// roots a pixel. Here each lane carries its own triangle's constants (those
// of SpanConsts, and the base colour), so that the loops below are those of
// spanLightingFrom with a lane's constants for the span's: the same
// operations, so the same bits.
constexpr int32_t kLaneRunMax = 4;  // runs shorter than this (untextured) go to a batch
struct LaneBatch {
  int32_t m = 0;                   // lanes in use
  int32_t X[kMaxSpanRun];          // each lane's pixel column (the row is the batch's)
  float e0[kMaxSpanRun], e1[kMaxSpanRun], e2[kMaxSpanRun];  // exact edge values, as float(double(E))
  float ia[kMaxSpanRun], iw0[kMaxSpanRun], iw1[kMaxSpanRun], iw2[kMaxSpanRun];
  float t00[kMaxSpanRun], t10[kMaxSpanRun], t20[kMaxSpanRun], t01[kMaxSpanRun], t11[kMaxSpanRun], t21[kMaxSpanRun];
  float n[9][kMaxSpanRun], q[9][kMaxSpanRun];  // normals and positions of corners 0..2, x y z each
  float base[4][kMaxSpanRun];                  // base colour
  float col[12][kMaxSpanRun];                  // vertex colours of corners 0..2, rgba each (scenes with them)
};

// spanLightingFrom's loop with each lane's triangle constants: the weights
// (b0..b2) out, and the normal and headlight of every lane.
KOKKOS_FORCEINLINE_FUNCTION void laneLighting(const LaneBatch& L, int32_t m, float3 eye, float ambient, float headI,
                                              float* __restrict__ b0, float* __restrict__ b1, float* __restrict__ b2,
                                              float* __restrict__ nx, float* __restrict__ ny, float* __restrict__ nz,
                                              float* __restrict__ diffuse) {
  for (int32_t j = 0; j < m; ++j) {
    const float ia = L.ia[j];
    // Shade::bary's screen-space weights: l0 from edge 1, l1 from edge 2, l2 from edge 0
    litPixel((L.e1[j] * ia) * L.iw0[j], (L.e2[j] * ia) * L.iw1[j], (L.e0[j] * ia) * L.iw2[j], L.t00[j], L.t10[j],
             L.t20[j], L.t01[j], L.t11[j], L.t21[j], float3{L.n[0][j], L.n[1][j], L.n[2][j]},
             float3{L.n[3][j], L.n[4][j], L.n[5][j]}, float3{L.n[6][j], L.n[7][j], L.n[8][j]},
             float3{L.q[0][j], L.q[1][j], L.q[2][j]}, float3{L.q[3][j], L.q[4][j], L.q[5][j]},
             float3{L.q[6][j], L.q[7][j], L.q[8][j]}, eye, ambient, headI, b0[j], b1[j], b2[j], nx[j], ny[j], nz[j],
             diffuse[j]);
  }
}
RAST_CPU_CLONES void laneLightingWide(const LaneBatch& L, int32_t m, float3 eye, float ambient, float headI,
                                      float* __restrict__ b0, float* __restrict__ b1, float* __restrict__ b2,
                                      float* __restrict__ nx, float* __restrict__ ny, float* __restrict__ nz,
                                      float* __restrict__ diffuse) {
  laneLighting(L, m, eye, ambient, headI, b0, b1, b2, nx, ny, nz, diffuse);
}

// What a span needs of its triangle, looked up and computed once per
// triangle (Shade::prepare, then the triangle's constants of spanLighting and
// of the texture) and kept in a small cache while a tile or run is shaded:
// rows of a tile alternate between the same few triangles.
struct SpanTri {
  TriFrag f;
  SpanConsts k;  // all but the span's edge values s0, s1, s2
  SpanTex tex;
  int32_t spanReady;  // k and tex are set (prepareSpan)
};

struct SpanTriCache {
  static constexpr int kSlots = 8;
  uint32_t key[kSlots] = {~0u, ~0u, ~0u, ~0u, ~0u, ~0u, ~0u, ~0u};  // slot[s].f.index, together in one line
  SpanTri slot[kSlots];
  int next = 0;
};

struct ShadeSpans : Shade {
  // Whether this kernel covers a frame of these settings.
  static bool usable(const ShadeParams& p, int samples, int run) {
    return run > 1 && run <= kMaxSpanRun && samples == 1 && p.mode == ShadingMode::Lambert &&
           p.filter != TexFilter::Trilinear && !p.wantNormals && !p.wantGeom;
  }

  KOKKOS_INLINE_FUNCTION void put(int64_t i, float4 c) const {
    if (p.floatOut) hdr(i) = c;
    else color(i) = display(c);
  }

  KOKKOS_INLINE_FUNCTION void operator()(const int64_t item) const {
    const int32_t Y = int32_t(item / runsPerRow);
    const int32_t x0 = int32_t(item % runsPerRow) * run;
    const int32_t n = (x0 + run < width ? x0 + run : width) - x0;
    const int64_t row = int64_t(Y) * width + x0;
    uint32_t idx[kMaxSpanRun], depthBits[kMaxSpanRun];
    for (int32_t j = 0; j < n; ++j) {
      const uint64_t key = vis(row + j);
      idx[j] = uint32_t(key & 0xffffffffu);
      depthBits[j] = uint32_t(key >> 32);
    }
    SpanTriCache cache;
    shadeRow(x0, Y, n, idx, depthBits, cache);
  }

  // The rows of a finished tile of the fused binned raster (shade_stage.cpp):
  // w x h pixels from (tx0, ty0), ids (raster index + 1) and depth bits in
  // rows of `stride`.
  //
  // A triangle's runs on different rows of the tile are shaded together, up
  // to kMaxSpanRun pixels at a time (shadeLanes): the triangles of a dense
  // mesh cover a few pixels of each row, and shading them row by row paid a
  // span's fixed cost and a partly empty vector for each.
  static constexpr int32_t kMaxTileRuns = 1024;
  static constexpr int32_t kBatchRunMax = 16;     // runs from this long are shaded as row spans at once
  KOKKOS_INLINE_FUNCTION void shadeTile(int32_t tx0, int32_t ty0, int32_t w, int32_t h, int32_t stride,
                                        const uint32_t* ib, const uint32_t* zb) const {
    SpanTriCache cache;
    if (w * h > kMaxTileRuns || w > kMaxSpanRun) {
      for (int32_t r = 0; r < h; ++r) shadeRow(tx0, ty0 + r, w, ib + r * stride, zb + r * stride, cache);
      return;
    }
    // Rows: ids, depth, background and lines at once; triangles' runs listed.
    uint32_t runId[kMaxTileRuns];
    int32_t runAt[kMaxTileRuns];  // row in the tile << 16 | column
    int32_t runLen[kMaxTileRuns];
    int32_t nr = 0;
    for (int32_t r = 0; r < h; ++r) {
      const int32_t Y = ty0 + r;
      const int64_t row = int64_t(Y) * width + tx0;
      const uint32_t* idx = ib + r * stride;
      const uint32_t* depthBits = zb + r * stride;
      if (p.wantDepth)
        for (int32_t j = 0; j < w; ++j) depthOut(row + j) = bitsFloat(depthBits[j]);
      if (p.wantPrimId)
        for (int32_t j = 0; j < w; ++j) {
          const uint32_t id = idx[j];
          primOut(row + j) = id == 0 ? 0 : (id - 1) & kLineFlag ? lineShade.primId((id - 1) & ~kLineFlag) : tris(id - 1).prim + 1;
        }
      for (uint64_t starts = runStarts(idx, w); starts;) {
        const int32_t j = lowestBit(starts);
        starts &= starts - 1;
        const int32_t k = starts ? lowestBit(starts) : w;
        const uint32_t id = idx[j];
        if (id == 0) {
          if (p.floatOut) {
            for (int32_t m = j; m < k; ++m) hdr(row + m) = p.backgroundFilm;
          } else {
            uint32_t* const dst = color.data() + row;
            const uint32_t bg = p.backgroundPacked;
            for (int32_t m = j; m < k; ++m) dst[m] = bg;
          }
        } else if ((id - 1) & kLineFlag) {
          SpanTri& st = lookup(id - 1, cache);
          for (int32_t m = j; m < k; ++m) put(row + m, shadeFragment(st.f, tx0 + m, Y, 0, 0, 0.0f, nullptr));
        } else if (k - j >= kBatchRunMax) {  // a long run is a full vector by itself
          span(lookup(id - 1, cache), row + j, tx0 + j, Y, k - j);
        } else {
          runId[nr] = id;
          runAt[nr] = r << 16 | j;
          runLen[nr] = k - j;
          ++nr;
        }
      }
    }
    // Each run chained to the next run of its triangle (runNext, -1: none)
    // through a small open-addressing table from id to its latest run, so that
    // a batch follows its triangle's runs instead of searching for them.
    int32_t runNext[kMaxTileRuns];
    {
      uint32_t hKey[2 * kMaxTileRuns];  // 0: empty (background is never a run here)
      int32_t hLast[2 * kMaxTileRuns];
      int32_t bits = 6;  // at least twice as many slots as runs
      while ((1 << bits) < 2 * nr) ++bits;
      const uint32_t mask = (1u << bits) - 1u;
      for (uint32_t i = 0; i <= mask; ++i) hKey[i] = 0;
      for (int32_t t = 0; t < nr; ++t) {
        const uint32_t id = runId[t];
        uint32_t h = (id * 0x9E3779B1u) >> (32 - bits);  // Fibonacci hashing: the product's top bits
        while (hKey[h] != 0 && hKey[h] != id) h = (h + 1) & mask;
        if (hKey[h] == id) runNext[hLast[h]] = t;
        else hKey[h] = id;
        hLast[h] = t;
        runNext[t] = -1;
      }
    }
    // Batches of one triangle's runs, in the order their first runs appear:
    // a batch takes runs along the chain while they fit in kMaxSpanRun lanes;
    // the rest start a later batch when the scan reaches them.
    // Each lane is a pixel's coordinates: its edge values are evaluated in the
    // vector loop (spanLightingLanes), nothing per run but its pixels' places.
    int32_t laneX[kMaxSpanRun], laneY[kMaxSpanRun];
    for (int32_t q = 0; q < nr; ++q) {
      if (runLen[q] == 0) continue;  // already shaded in an earlier batch
      const uint32_t id = runId[q];
      SpanTri& st = lookup(id - 1, cache);
      int32_t m = 0;
      for (int32_t t = q; t >= 0; t = runNext[t]) {
        const int32_t len = runLen[t];
        if (m + len > kMaxSpanRun) break;
        const int32_t X = tx0 + (runAt[t] & 0xffff), Y = ty0 + (runAt[t] >> 16);
        for (int32_t i = 0; i < len; ++i) {
          laneX[m + i] = X + i;
          laneY[m + i] = Y;
        }
        m += len;
        runLen[t] = 0;
      }
      for (int32_t i = m; i < spanBlocks(m); ++i) {  // the last block's spare lanes: a pixel of the batch
        laneX[i] = laneX[0];
        laneY[i] = laneY[0];
      }
      shadeLanes(st, m, 0, laneX, laneY);
    }
  }

  // A tile no triangle touches: background, and the cleared depth and ids
  // (what shadeRow gives for ids 0 and depth bits of kClearKey).
  KOKKOS_INLINE_FUNCTION void shadeEmpty(int32_t tx0, int32_t ty0, int32_t w, int32_t h) const {
    for (int32_t r = 0; r < h; ++r) {
      const int64_t row = int64_t(ty0 + r) * width + tx0;
      if (p.wantDepth)
        for (int32_t j = 0; j < w; ++j) depthOut(row + j) = bitsFloat(uint32_t(kClearKey >> 32));
      if (p.wantPrimId)
        for (int32_t j = 0; j < w; ++j) primOut(row + j) = 0;
      if (p.floatOut) {
        for (int32_t j = 0; j < w; ++j) hdr(row + j) = p.backgroundFilm;
      } else {
        uint32_t* const dst = color.data() + row;
        const uint32_t bg = p.backgroundPacked;
        for (int32_t j = 0; j < w; ++j) dst[j] = bg;
      }
    }
  }

  // The cached SpanTri of raster triangle `index`, prepared on a miss.
  // spanConsts: with k and tex too (a batch's lanes need only f).
  KOKKOS_INLINE_FUNCTION SpanTri& lookup(uint32_t index, SpanTriCache& c, bool spanConsts = true) const {
    for (int s = 0; s < SpanTriCache::kSlots; ++s)
      if (c.key[s] == index) {
        SpanTri& st = c.slot[s];
        if (spanConsts && !st.spanReady && !(index & kLineFlag)) prepareSpan(st);
        return st;
      }
    c.key[c.next] = index;
    SpanTri& st = c.slot[c.next];
    c.next = c.next + 1 < SpanTriCache::kSlots ? c.next + 1 : 0;
    prepare(index, st.f);
    st.spanReady = 0;
    if (spanConsts && !(index & kLineFlag)) prepareSpan(st);
    return st;
  }

  // The per-triangle part of span(): spanLighting's constants and the texture's.
  KOKKOS_INLINE_FUNCTION void prepareSpan(SpanTri& st) const {
    st.spanReady = 1;
    const TriFrag& f = st.f;
    const RasterTri& t = *f.t;
    const Edges& e = f.e;
    SpanConsts& k = st.k;
    k.a1 = double(e.A[1]);
    k.a2 = double(e.A[2]);
    k.a0 = double(e.A[0]);
    k.r0 = double(e.B[0]);
    k.r1 = double(e.B[1]);
    k.r2 = double(e.B[2]);
    k.k0 = double(e.C[0]);
    k.k1 = double(e.C[1]);
    k.k2 = double(e.C[2]);
    k.ia = t.invArea;
    k.iw0 = p.perspective ? t.invW[0] : 1.0f;
    k.iw1 = p.perspective ? t.invW[1] : 1.0f;
    k.iw2 = p.perspective ? t.invW[2] : 1.0f;
    k.t00 = t.bary[0][0]; k.t10 = t.bary[1][0]; k.t20 = t.bary[2][0];
    k.t01 = t.bary[0][1]; k.t11 = t.bary[1][1]; k.t21 = t.bary[2][1];
    k.n0 = f.n[0]; k.n1 = f.n[1]; k.n2 = f.n[2];
    k.q0 = f.pos[0]; k.q1 = f.pos[1]; k.q2 = f.pos[2];
    k.eye = p.frame(0).camera.eye;
    k.ambient = p.ambient;
    k.headI = p.headlight ? 1.0f - p.ambient : 0.0f;
    if (f.textured) {
      SpanTex& x = st.tex;
      x.texels = texels.data() + f.tex.offset;
      x.lut = lut.data();
      x.width = f.tex.width;
      x.height = f.tex.height;
      x.wrapS = f.tex.wrapS;
      x.wrapT = f.tex.wrapT;
      x.indexable = int64_t(x.width) * int64_t(x.height) < (int64_t(1) << 31);
      x.u0 = f.uv[0].x; x.u1 = f.uv[1].x; x.u2 = f.uv[2].x;
      x.v0 = f.uv[0].y; x.v1 = f.uv[1].y; x.v2 = f.uv[2].y;
    }
  }

  // Pixels [x0, x0 + n) of row Y, given the visibility keys' halves: raster
  // index + 1 (0: none) and depth bits.
  KOKKOS_INLINE_FUNCTION void shadeRow(int32_t x0, int32_t Y, int32_t n, const uint32_t* idx,
                                       const uint32_t* depthBits, SpanTriCache& cache) const {
    const int64_t row = int64_t(Y) * width + x0;
    if (p.wantDepth)
      for (int32_t j = 0; j < n; ++j) depthOut(row + j) = bitsFloat(depthBits[j]);
    if (p.wantPrimId)
      for (int32_t j = 0; j < n; ++j) {
        const uint32_t id = idx[j];
        primOut(row + j) = id == 0 ? 0 : (id - 1) & kLineFlag ? lineShade.primId((id - 1) & ~kLineFlag) : tris(id - 1).prim + 1;
      }
    // Runs found kRunMaskBits pixels at a time (runStarts); a run across a
    // boundary becomes two spans, which shade the same pixels alike. Short
    // runs of untextured triangles go to a batch, shaded last (n <=
    // kMaxSpanRun: one batch holds them all).
    LaneBatch batch;
    for (int32_t base = 0; base < n; base += kRunMaskBits) {
      const int32_t end = n - base < kRunMaskBits ? n : base + kRunMaskBits;
      for (uint64_t starts = runStarts(idx + base, end - base); starts;) {
        const int32_t j = base + lowestBit(starts);
        starts &= starts - 1;
        const int32_t k = starts ? base + lowestBit(starts) : end;
        const uint32_t id = idx[j];
        if (id == 0) {
          if (p.floatOut) {
            for (int32_t m = j; m < k; ++m) hdr(row + m) = p.backgroundFilm;
          } else {
            uint32_t* const dst = color.data() + row;  // a plain fill the compiler vectorizes
            const uint32_t bg = p.backgroundPacked;
            for (int32_t m = j; m < k; ++m) dst[m] = bg;
          }
        } else if ((id - 1) & kLineFlag) {
          SpanTri& st = lookup(id - 1, cache);
          for (int32_t m = j; m < k; ++m) put(row + m, shadeFragment(st.f, x0 + m, Y, 0, 0, 0.0f, nullptr));
        } else if (k - j < kLaneRunMax) {
          SpanTri& st = lookup(id - 1, cache, false);
          if (st.f.textured) {
            span(lookup(id - 1, cache), row + j, x0 + j, Y, k - j);
          } else {
            if (batch.m + (k - j) > kMaxSpanRun) shadeBatch(batch, int64_t(Y) * width, Y);  // rows of a wide tile
            addLanes(batch, st.f, x0 + j, Y, k - j);
          }
        } else {
          span(lookup(id - 1, cache), row + j, x0 + j, Y, k - j);
        }
      }
    }
    if (batch.m) shadeBatch(batch, int64_t(Y) * width, Y);
  }

  // The scene's directional lights (without the headlight) added to the
  // diffuse terms of mb lanes, given their normals.
  KOKKOS_INLINE_FUNCTION void addLights(int32_t mb, const float* nx, const float* ny, const float* nz,
                                        float* diffuse) const {
    if (p.headlight) return;
    const int nl = int(lights.extent(0));
    for (int l = 0; l < nl; ++l) {
      const float3 L = lights(l).direction;
      const float I = lights(l).intensity;
      for (int32_t j = 0; j < mb; ++j) {
        const float ndl = nx[j] * L.x + ny[j] * L.y + nz[j] * L.z;
        diffuse[j] += I * (ndl > 0.0f ? ndl : 0.0f);
      }
    }
  }

  // Pixels [xa, xa + len) of row Y, of triangle f, as lanes of the batch.
  KOKKOS_INLINE_FUNCTION void addLanes(LaneBatch& L, const TriFrag& f, int32_t xa, int32_t Y, int32_t len) const {
    const bool persp = p.perspective != 0;
    for (int32_t i = 0; i < len; ++i) {
      const int32_t j = L.m++;
      const int32_t X = xa + i;
      L.X[j] = X;
      L.e0[j] = float(double(f.e.eval(0, X, Y)));  // as span(): exact in double, then rounded once
      L.e1[j] = float(double(f.e.eval(1, X, Y)));
      L.e2[j] = float(double(f.e.eval(2, X, Y)));
      L.ia[j] = f.invArea;
      L.iw0[j] = persp ? f.invW[0] : 1.0f;
      L.iw1[j] = persp ? f.invW[1] : 1.0f;
      L.iw2[j] = persp ? f.invW[2] : 1.0f;
      L.t00[j] = f.corner[0][0]; L.t10[j] = f.corner[1][0]; L.t20[j] = f.corner[2][0];
      L.t01[j] = f.corner[0][1]; L.t11[j] = f.corner[1][1]; L.t21[j] = f.corner[2][1];
      for (int c = 0; c < 3; ++c) {
        L.n[3 * c][j] = f.n[c].x; L.n[3 * c + 1][j] = f.n[c].y; L.n[3 * c + 2][j] = f.n[c].z;
        L.q[3 * c][j] = f.pos[c].x; L.q[3 * c + 1][j] = f.pos[c].y; L.q[3 * c + 2][j] = f.pos[c].z;
      }
      L.base[0][j] = f.baseColor.x; L.base[1][j] = f.baseColor.y; L.base[2][j] = f.baseColor.z; L.base[3][j] = f.baseColor.w;
      if (hasColor)
        for (int c = 0; c < 3; ++c) {
          L.col[4 * c][j] = f.col[c].x; L.col[4 * c + 1][j] = f.col[c].y;
          L.col[4 * c + 2][j] = f.col[c].z; L.col[4 * c + 3][j] = f.col[c].w;
        }
    }
  }

  // The batch's pixels of row Y (rowStart: its first pixel's index): as
  // shadeLanes, each lane with its own triangle's constants.
  KOKKOS_INLINE_FUNCTION void shadeBatch(LaneBatch& L, int64_t rowStart, int32_t Y) const {  // empties it
    const int32_t m = L.m;
    const bool wide = m >= kSpanWideMin;
    const int32_t mb = wide ? spanBlocks(m) : m;
    for (int32_t i = m; i < mb; ++i) {  // the last block's spare lanes: lane 0's triangle and pixel
      L.X[i] = L.X[0];
      L.e0[i] = L.e0[0]; L.e1[i] = L.e1[0]; L.e2[i] = L.e2[0];
      L.ia[i] = L.ia[0]; L.iw0[i] = L.iw0[0]; L.iw1[i] = L.iw1[0]; L.iw2[i] = L.iw2[0];
      L.t00[i] = L.t00[0]; L.t10[i] = L.t10[0]; L.t20[i] = L.t20[0];
      L.t01[i] = L.t01[0]; L.t11[i] = L.t11[0]; L.t21[i] = L.t21[0];
      for (int c = 0; c < 9; ++c) {
        L.n[c][i] = L.n[c][0];
        L.q[c][i] = L.q[c][0];
      }
      for (int c = 0; c < 4; ++c) L.base[c][i] = L.base[c][0];
      if (hasColor)
        for (int c = 0; c < 12; ++c) L.col[c][i] = L.col[c][0];
    }
    float b0[kMaxSpanRun], b1[kMaxSpanRun], b2[kMaxSpanRun];
    float nx[kMaxSpanRun], ny[kMaxSpanRun], nz[kMaxSpanRun];
    float diffuse[kMaxSpanRun];
    const float3 eye = p.frame(0).camera.eye;
    const float headI = p.headlight ? 1.0f - p.ambient : 0.0f;
    if (wide) laneLightingWide(L, mb, eye, p.ambient, headI, b0, b1, b2, nx, ny, nz, diffuse);
    else laneLighting(L, mb, eye, p.ambient, headI, b0, b1, b2, nx, ny, nz, diffuse);
    addLights(mb, nx, ny, nz, diffuse);
    float br[kMaxSpanRun], bg[kMaxSpanRun], bb[kMaxSpanRun], ba[kMaxSpanRun];
    for (int32_t j = 0; j < mb; ++j) {
      br[j] = L.base[0][j];
      bg[j] = L.base[1][j];
      bb[j] = L.base[2][j];
      ba[j] = L.base[3][j];
    }
    if (hasColor)
      for (int32_t j = 0; j < mb; ++j) {  // as shadeLanes, with each lane's corner colours
        br[j] = br[j] * (L.col[0][j] * b0[j] + L.col[4][j] * b1[j] + L.col[8][j] * b2[j]);
        bg[j] = bg[j] * (L.col[1][j] * b0[j] + L.col[5][j] * b1[j] + L.col[9][j] * b2[j]);
        bb[j] = bb[j] * (L.col[2][j] * b0[j] + L.col[6][j] * b1[j] + L.col[10][j] * b2[j]);
        ba[j] = ba[j] * (L.col[3][j] * b0[j] + L.col[7][j] * b1[j] + L.col[11][j] * b2[j]);
      }
    if (!p.floatOut) {
      uint32_t px[kMaxSpanRun];
      if (wide) packSpanWide(mb, m, br, bg, bb, ba, diffuse, encodePacked.data(), px);
      else packSpan(mb, m, br, bg, bb, ba, diffuse, encodePacked.data(), px);
      for (int32_t j = 0; j < m; ++j) color(rowStart + L.X[j]) = px[j];
      L.m = 0;
      return;
    }
    for (int32_t j = 0; j < m; ++j) {
      const float d = diffuse[j];
      hdr(rowStart + L.X[j]) = float4{br[j] * d + 0.0f, bg[j] * d + 0.0f, bb[j] * d + 0.0f, ba[j]};
    }
    L.m = 0;
  }

  // Pixels [xa, xa + m) of row Y, all of st's triangle (a raster triangle).
  KOKKOS_INLINE_FUNCTION void span(SpanTri& st, int64_t out, int32_t xa, int32_t Y, int32_t m) const {
    const Edges& e = st.f.e;
    SpanConsts& k = st.k;
    k.s1 = double(e.eval(1, xa, Y));
    k.s2 = double(e.eval(2, xa, Y));
    k.s0 = double(e.eval(0, xa, Y));
    shadeLanes(st, m, out, nullptr, nullptr);
  }

  // m pixels of st's triangle: a row span from pixel `out` on (X null), or
  // any pixels, given by their coordinates (X, Y; whole blocks of them).
  KOKKOS_INLINE_FUNCTION void shadeLanes(SpanTri& st, int32_t m, int64_t out, const int32_t* X,
                                         const int32_t* Y) const {
    const TriFrag& f = st.f;
    float b0[kMaxSpanRun], b1[kMaxSpanRun], b2[kMaxSpanRun];
    float nx[kMaxSpanRun], ny[kMaxSpanRun], nz[kMaxSpanRun];
    float diffuse[kMaxSpanRun];
    float br[kMaxSpanRun], bg[kMaxSpanRun], bb[kMaxSpanRun], ba[kMaxSpanRun];  // base colour
    // Screen-space weights from the exact edge values (as Shade::bary: l0 from
    // edge 1, l1 from edge 2, l2 from edge 0), then the perspective-correct
    // weights in the drawn triangle, the normal, the position and the
    // headlight of every pixel (Shade::bary, shadeFragment): spanLighting.
    const SpanConsts& k = st.k;
    // Lanes computed: a long span's loops (AVX-512 and AVX2 clones) run over whole blocks;
    // a short one's inline loops over its pixels only (one pixel each on
    // scenes of tiny triangles).
    const bool wide = m >= kSpanWideMin;
    const int32_t mb = wide ? spanBlocks(m) : m;
    if (X) {
      if (wide) spanLightingLanesWide(k, mb, X, Y, b0, b1, b2, nx, ny, nz, diffuse);
      else spanLightingLanes(k, mb, X, Y, b0, b1, b2, nx, ny, nz, diffuse);
    } else {
      if (wide) spanLightingWide(k, mb, b0, b1, b2, nx, ny, nz, diffuse);
      else spanLighting(k, mb, b0, b1, b2, nx, ny, nz, diffuse);
    }
    addLights(mb, nx, ny, nz, diffuse);
    // Base colour: material, texture, vertex colour.
    const float4 bc = f.baseColor;
    for (int32_t j = 0; j < mb; ++j) {
      br[j] = bc.x;
      bg[j] = bc.y;
      bb[j] = bc.z;
      ba[j] = bc.w;
    }
    if (f.textured) texture(st, m, mb, b0, b1, b2, br, bg, bb, ba);
    if (hasColor) {
      const float4 c0 = f.col[0], c1 = f.col[1], c2 = f.col[2];
      for (int32_t j = 0; j < mb; ++j) {
        // base * (col0 b0 + col1 b1 + col2 b2), per channel
        br[j] = br[j] * (c0.x * b0[j] + c1.x * b1[j] + c2.x * b2[j]);
        bg[j] = bg[j] * (c0.y * b0[j] + c1.y * b1[j] + c2.y * b2[j]);
        bb[j] = bb[j] * (c0.z * b0[j] + c1.z * b1[j] + c2.z * b2[j]);
        ba[j] = ba[j] * (c0.w * b0[j] + c1.w * b1[j] + c2.w * b2[j]);
      }
    }
    if (!p.floatOut) {
      uint32_t px[kMaxSpanRun];
      uint32_t* dst = X ? px : color.data() + out;
      // The host backends share host memory with their kernels: a plain pointer.
      if (wide) packSpanWide(mb, m, br, bg, bb, ba, diffuse, encodePacked.data(), dst);
      else packSpan(mb, m, br, bg, bb, ba, diffuse, encodePacked.data(), dst);
      if (X)
        for (int32_t j = 0; j < m; ++j) color(int64_t(Y[j]) * width + X[j]) = px[j];
      return;
    }
    for (int32_t j = 0; j < m; ++j) {
      const float d = diffuse[j];
      // rgb * diffuse + spec (0 in Lambert), as shadeFragment adds it
      hdr(X ? int64_t(Y[j]) * width + X[j] : out + j) = float4{br[j] * d + 0.0f, bg[j] * d + 0.0f, bb[j] * d + 0.0f, ba[j]};
    }
  }

  // The base colour times the texture at each pixel of the span (weights b0..b2).
  // m pixels, mb lanes (as in span()).
  KOKKOS_INLINE_FUNCTION void texture(const SpanTri& st, int32_t m, int32_t mb, const float* b0, const float* b1,
                                      const float* b2, float* br, float* bg, float* bb, float* ba) const {
    const TriFrag& f = st.f;
    if (p.filter != TexFilter::Nearest && st.tex.indexable) {
      int32_t i00[kMaxSpanRun], i10[kMaxSpanRun], i01[kMaxSpanRun], i11[kMaxSpanRun];
      float fa[kMaxSpanRun], fb[kMaxSpanRun];
      const bool wide = m >= kSpanWideMin;
      const SpanTex& x = st.tex;
      const int32_t bad = wide ? bilinearSetupWide(x, mb, b0, b1, b2, i00, i10, i01, i11, fa, fb)
                               : bilinearSetup(x, mb, b0, b1, b2, i00, i10, i01, i11, fa, fb);
      if (!bad) {
        if (wide) bilinearBlendWide(x.texels, x.lut, mb, i00, i10, i01, i11, fa, fb, br, bg, bb, ba);
        else bilinearBlend(x.texels, x.lut, mb, i00, i10, i01, i11, fa, fb, br, bg, bb, ba);
        return;
      }
    }
    for (int32_t j = 0; j < m; ++j) {
      const float2 uv = uvAt(f, b0[j], b1[j], b2[j]);
      const float4 tc = p.filter == TexFilter::Nearest ? sampleNearest(f.tex, texels, lut, uv.x, uv.y)
                                                       : sampleBilinear(f.tex, texels, lut, uv.x, uv.y);
      br[j] = br[j] * tc.x;
      bg[j] = bg[j] * tc.y;
      bb[j] = bb[j] * tc.z;
      ba[j] = ba[j] * tc.w;
    }
  }
};

}  // namespace shading
}  // namespace rast
