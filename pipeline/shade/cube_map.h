// Cube maps on the device for image-based light (docs/lighting.md): the face
// and texel of a direction as OpenGL's cube maps have them (the convention the
// Khronos Sample Renderer's filtered maps are made and read in), bilinear and
// trilinear sampling of faces stored with a one-texel border (so that a
// bilinear footprint never leaves its face and no seam shows at face edges,
// as WebGL2's seamless cube maps show none), and the panorama's coordinates of
// a direction. Everything here is +, -, *, / and sqrt on floats, so that the
// maps built from it are the same bits on every backend (an atan2 of the
// device's maths library would not be: docs/determinism.md).
#pragma once

#include "backends/fast_floor.h"
#include "base/vec.h"

namespace rast {

// Texel (x, y) of face `face` of a level of side `size` with its border:
// x, y in -1..size. Faces follow one another, each (size + 2)^2 texels.
KOKKOS_INLINE_FUNCTION uint32_t cubeTexelIndex(uint32_t levelOffset, int32_t size, int32_t face, int32_t x,
                                               int32_t y) {
  const uint32_t side = uint32_t(size + 2);
  return levelOffset + (uint32_t(face) * side + uint32_t(y + 1)) * side + uint32_t(x + 1);
}

// Texels of one level (6 bordered faces).
KOKKOS_INLINE_FUNCTION uint32_t cubeLevelTexels(int32_t size) { return 6u * uint32_t(size + 2) * uint32_t(size + 2); }

// The direction (not normalised) through face coordinates sc, tc in [-1, 1]
// (beyond for border texels): the inverse of OpenGL's table of major axes.
KOKKOS_INLINE_FUNCTION float3 cubeFaceDir(int32_t face, float sc, float tc) {
  switch (face) {
    case 0: return {1.0f, -tc, -sc};
    case 1: return {-1.0f, -tc, sc};
    case 2: return {sc, 1.0f, tc};
    case 3: return {sc, -1.0f, -tc};
    case 4: return {sc, -tc, 1.0f};
    default: return {-sc, -tc, -1.0f};
  }
}

// The direction through the centre of texel (x, y) of a face of side `size`.
KOKKOS_INLINE_FUNCTION float3 cubeTexelDir(int32_t face, int32_t x, int32_t y, int32_t size) {
  const float inv = 2.0f / float(size);
  return cubeFaceDir(face, (float(x) + 0.5f) * inv - 1.0f, (float(y) + 0.5f) * inv - 1.0f);
}

// OpenGL's face selection (the largest magnitude; ties to X, then Y) and the
// face coordinates s, t in [0, 1] of a direction.
struct CubeCoord {
  int32_t face;
  float s, t;
};
KOKKOS_INLINE_FUNCTION CubeCoord cubeCoord(float3 d) {
  // fabsf: one instruction; its +0 for -0 and sign-cleared NaN compare as
  // the negation's did, and a zero or NaN ma returns below either way.
  const float ax = ::fabsf(d.x), ay = ::fabsf(d.y), az = ::fabsf(d.z);
  int32_t face;
  float sc, tc, ma;
  if (ax >= ay && ax >= az) {
    face = d.x >= 0.0f ? 0 : 1;
    sc = d.x >= 0.0f ? -d.z : d.z;
    tc = -d.y;
    ma = ax;
  } else if (ay >= az) {
    face = d.y >= 0.0f ? 2 : 3;
    sc = d.x;
    tc = d.y >= 0.0f ? d.z : -d.z;
    ma = ay;
  } else {
    face = d.z >= 0.0f ? 4 : 5;
    sc = d.z >= 0.0f ? d.x : -d.x;
    tc = -d.y;
    ma = az;
  }
  if (!(ma > 0.0f)) return {0, 0.5f, 0.5f};  // zero or NaN direction: the centre of +X
  const float inv = 0.5f / ma;
  return {face, sc * inv + 0.5f, tc * inv + 0.5f};
}

KOKKOS_INLINE_FUNCTION float4 lerp4(float4 a, float4 b, float t) { return a * (1.0f - t) + b * t; }

// Bilinear sample of one bordered level at face coordinates (s, t): the
// footprint stays inside the face and its border.
template <class Texels>
KOKKOS_INLINE_FUNCTION float4 cubeBilinear(const Texels& tex, uint32_t levelOffset, int32_t size, CubeCoord c) {
  const float fs = float(size);
  float fx = c.s * fs - 0.5f, fy = c.t * fs - 0.5f;
  fx = fx >= -1.0f ? (fx <= fs ? fx : fs) : -1.0f;  // also NaN to -1
  fy = fy >= -1.0f ? (fy <= fs ? fy : fs) : -1.0f;
  int32_t x0 = floorIndex(fx), y0 = floorIndex(fy);  // in [-1, size]
  x0 = x0 < size ? x0 : size - 1;
  y0 = y0 < size ? y0 : size - 1;
  const float a = fx - float(x0), b = fy - float(y0);
  const uint32_t i00 = cubeTexelIndex(levelOffset, size, c.face, x0, y0);
  const uint32_t row = uint32_t(size + 2);
  const float4 t00 = tex(i00), t10 = tex(i00 + 1), t01 = tex(i00 + row), t11 = tex(i00 + row + 1);
  return lerp4(lerp4(t00, t10, a), lerp4(t01, t11, a), b);
}

// Trilinear sample of a chain of bordered levels (level l has side
// size >> l, starts at offsets[l]) at level of detail `lod`, clamped to the
// chain as textureLod clamps it.
// The two levels a trilinear sample at `lod` reads and its blend weight:
// what depends on the level of detail alone, so that a caller whose lod is
// the same for many samples (a triangle's roughness) finds it once.
struct CubeLod {
  uint32_t offset0 = 0, offset1 = 0;
  int32_t size0 = 0, size1 = 0;
  float f = 0.0f;
  int32_t two = 0;  // the second level is read (f > 0 and it exists)
};
KOKKOS_INLINE_FUNCTION CubeLod cubeLod(const uint32_t* offsets, int32_t size, int32_t levels, float lod) {
  const float maxLod = float(levels - 1);
  lod = lod > 0.0f ? (lod < maxLod ? lod : maxLod) : 0.0f;  // also NaN to 0
  const int32_t l0 = floorIndex(lod);
  CubeLod r;
  r.f = lod - float(l0);
  r.offset0 = offsets[l0];
  r.size0 = size >> l0;
  r.two = (r.f > 0.0f) && l0 + 1 < levels;
  if (r.two) {
    r.offset1 = offsets[l0 + 1];
    r.size1 = size >> (l0 + 1);
  }
  return r;
}

template <class Texels>
KOKKOS_INLINE_FUNCTION float4 cubeTrilinearAt(const Texels& tex, const CubeLod& l, CubeCoord c) {
  const float4 a = cubeBilinear(tex, l.offset0, l.size0, c);
  if (!l.two) return a;
  return lerp4(a, cubeBilinear(tex, l.offset1, l.size1, c), l.f);
}

template <class Texels>
KOKKOS_INLINE_FUNCTION float4 cubeTrilinear(const Texels& tex, const uint32_t* offsets, int32_t size, int32_t levels,
                                            float3 dir, float lod) {
  return cubeTrilinearAt(tex, cubeLod(offsets, size, levels, lod), cubeCoord(dir));
}

// atan(x) without the maths library (Cephes' atanf: range reduction at
// tan(3 pi/8) and tan(pi/8), then a degree-9 odd polynomial; relative error
// about 1e-7).
KOKKOS_INLINE_FUNCTION float portableAtan(float x) {
  const float sign = x < 0.0f ? -1.0f : 1.0f;
  float ax = x * sign, base = 0.0f;
  if (ax > 2.414213562373095f) {
    base = 1.5707963267948966f;
    ax = -1.0f / ax;
  } else if (ax > 0.4142135623730950f) {
    base = 0.7853981633974483f;
    ax = (ax - 1.0f) / (ax + 1.0f);
  }
  const float z = ax * ax;
  const float p = (((8.05374449538e-2f * z - 1.38776856032e-1f) * z + 1.99777106478e-1f) * z - 3.33329491539e-1f) * z;
  return sign * (base + (p * ax + ax));
}

KOKKOS_INLINE_FUNCTION float portableAtan2(float y, float x) {
  const float kPi = 3.14159265358979323846f;
  if (x == 0.0f) return y > 0.0f ? 0.5f * kPi : (y < 0.0f ? -0.5f * kPi : 0.0f);
  const float ay = y < 0.0f ? -y : y, axx = x < 0.0f ? -x : x;
  // atan of the smaller ratio, which stays accurate near the axes.
  float r = ay <= axx ? portableAtan(ay / axx) : 0.5f * kPi - portableAtan(axx / ay);
  if (x < 0.0f) r = kPi - r;
  return y < 0.0f ? -r : r;
}

// The panorama coordinates of a unit direction as the Khronos Sample Renderer
// reads them: u = 0.5 + atan2(z, x) / (2 pi), v = acos(y) / pi (v = 0 at +Y,
// the image's first row).
KOKKOS_INLINE_FUNCTION float2 panoramaUV(float3 d) {
  const float kInvPi = 0.318309886183790672f;
  const float y = d.y > 1.0f ? 1.0f : (d.y < -1.0f ? -1.0f : d.y);
  const float acosY = portableAtan2(::sqrtf(1.0f - y * y), y);
  return {0.5f + 0.5f * kInvPi * portableAtan2(d.z, d.x), acosY * kInvPi};
}

}  // namespace rast
