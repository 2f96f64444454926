// Bilinear texturing over a span for the CPU's span kernel (shade_spans.h):
// branch-free forms of the host's texture addressing (floorTexel,
// reduceCoord, wrapIndex), the texel indices and weights of every pixel, and
// the fetches and blend, as loops the compiler vectorizes (the fetches become
// AVX2 gathers).
//
// It exists on its own because it is a separate contract: for every input the
// flat forms must give the values of the branching ones, and the result
// sampleBilinear's bits (tests/pipeline/test_cpu_paths.cpp checks both), and
// its gather loops follow their own AVX-512 policy (RAST_CPU_CLONES_GATHER,
// cpu_clones.h). A span it does not cover (indices past what the flat wrap
// handles, textures of 2^31 texels or more) is sampled per pixel by the kernel.
#pragma once

#include "backends/cpu_clones.h"
#include "pipeline/shade/shade_fragment.h"

namespace rast {
namespace shading {

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

}  // namespace shading
}  // namespace rast
