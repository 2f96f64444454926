// Texture sampling on the device: glTF wrap modes, nearest and bilinear
// filtering of sRGB RGBA8 texels, filtered in linear light as OpenGL does for
// sRGB textures.
#pragma once

#include "backends/fast_floor.h"
#include "backends/flatten.h"
#include "base/color.h"
#include "pipeline/data/gpu_types.h"
#include "host/scene/scene.h"

namespace rast {

KOKKOS_INLINE_FUNCTION int32_t wrapIndex(int32_t i, int32_t n, int32_t mode) {
  if (i >= 0 && i < n) return i;  // inside: every mode keeps it (and no division)
  if (mode == WrapClamp) return i < 0 ? 0 : (i >= n ? n - 1 : i);
  if (mode == WrapMirror) {
    const int32_t period = 2 * n;
    int32_t m = i % period;
    if (m < 0) m += period;
    return m < n ? m : period - 1 - m;
  }
  int32_t m = i % n;
  return m < 0 ? m + n : m;
}

// Brings a texture coordinate into a range where integer texel indices cannot
// overflow, without changing what any wrap mode samples (the mirror period is
// 2, a multiple of the repeat period 1). NaN samples the origin.
KOKKOS_INLINE_FUNCTION float reduceCoord(float u, int32_t mode) {
  if (!isFinite(u)) return 0.0f;
  if (mode == WrapClamp) return u < -1.0f ? -1.0f : (u > 2.0f ? 2.0f : u);
  return u - 2.0f * floorTexel(u * 0.5f);
}

// The texels and a decode table (the sRGB one for colour textures, the unorm
// one for data) by their addresses, passed by value. Passed as references to
// a kernel functor's views, the glTF shading's calls for the two tables were
// merged behind a pointer to either member, which takes the address of the
// functor, and a GPU then copies it (2.4 KB for the glTF shading's) from the
// kernel's parameters to every thread's stack first.
struct TexelTable {
  const uint32_t* t;
  KOKKOS_INLINE_FUNCTION uint32_t operator()(uint32_t i) const { return t[i]; }
};
struct DecodeTable {
  const float* t;
  KOKKOS_INLINE_FUNCTION float operator()(uint32_t i) const { return t[i]; }
};

template <class Texels, class Lut>
KOKKOS_INLINE_FUNCTION float4 fetchTexel(const TextureGPU& t, const Texels& texels, const Lut& lut, int32_t x,
                                         int32_t y) {
  return unpackSrgb8(texels(t.offset + uint32_t(y) * uint32_t(t.width) + uint32_t(x)), lut);
}

// uv (0,0) is the top-left corner of the image (glTF), whose first stored row is
// the top one: row index = v * height.
// The ...At forms take coordinates already brought into range (reduceCoord
// with the texture's wrap modes, which every level of a chain shares), so that
// a filter reading two levels reduces each coordinate once.
template <class Texels, class Lut>
KOKKOS_INLINE_FUNCTION float4 sampleNearestAt(const TextureGPU& t, const Texels& texels, const Lut& lut, float ru,
                                              float rv) {
  const float fu = ru * float(t.width), fv = rv * float(t.height);
  const int32_t x = wrapIndex(floorIndex(fu), t.width, t.wrapS);
  const int32_t y = wrapIndex(floorIndex(fv), t.height, t.wrapT);
  return fetchTexel(t, texels, lut, x, y);
}

template <class Texels, class Lut>
KOKKOS_INLINE_FUNCTION float4 sampleNearest(const TextureGPU& t, const Texels& texels, const Lut& lut, float u,
                                            float v) {
  return sampleNearestAt(t, texels, lut, reduceCoord(u, t.wrapS), reduceCoord(v, t.wrapT));
}

template <class Texels, class Lut>
RAST_HOST_FORCEINLINE float4 sampleBilinearAt(const TextureGPU& t, const Texels& texels, const Lut& lut, float ru,
                                               float rv) {
  const float fu = ru * float(t.width) - 0.5f;
  const float fv = rv * float(t.height) - 0.5f;
  const int32_t x0 = floorIndex(fu), y0 = floorIndex(fv);  // |fu|, |fv| <= 2 side - 0.5
  const float a = fu - float(x0), b = fv - float(y0);
  const int32_t xa = wrapIndex(x0, t.width, t.wrapS), xb = wrapIndex(x0 + 1, t.width, t.wrapS);
  const int32_t ya = wrapIndex(y0, t.height, t.wrapT), yb = wrapIndex(y0 + 1, t.height, t.wrapT);
  const float4 c00 = fetchTexel(t, texels, lut, xa, ya), c10 = fetchTexel(t, texels, lut, xb, ya);
  const float4 c01 = fetchTexel(t, texels, lut, xa, yb), c11 = fetchTexel(t, texels, lut, xb, yb);
  return (c00 * ((1.0f - a) * (1.0f - b)) + c10 * (a * (1.0f - b))) + (c01 * ((1.0f - a) * b) + c11 * (a * b));
}

template <class Texels, class Lut>
KOKKOS_INLINE_FUNCTION float4 sampleBilinear(const TextureGPU& t, const Texels& texels, const Lut& lut, float u,
                                             float v) {
  return sampleBilinearAt(t, texels, lut, reduceCoord(u, t.wrapS), reduceCoord(v, t.wrapT));
}

// The mipmap level after level l (levels follow each other in the texel
// buffer, each half the size of the previous, at least 1). Sides are
// positive: halved by a shift.
KOKKOS_INLINE_FUNCTION TextureGPU nextMip(TextureGPU l) {
  l.offset += uint32_t(l.width) * uint32_t(l.height);
  l.width = l.width > 1 ? int32_t(uint32_t(l.width) >> 1) : 1;
  l.height = l.height > 1 ? int32_t(uint32_t(l.height) >> 1) : 1;
  return l;
}

// Mipmap level k of a texture, as a texture of its own.
KOKKOS_INLINE_FUNCTION TextureGPU mipLevel(const TextureGPU& t, int k) {
  TextureGPU l = t;
  for (int i = 0; i < k; ++i) l = nextMip(l);
  return l;
}

// Level of detail from the screen-space derivatives of the texture coordinates
// (OpenGL 4.6 section 8.14: lambda = log2 of the larger footprint side, in texels).
KOKKOS_INLINE_FUNCTION float textureLod(float dudx, float dvdx, float dudy, float dvdy, int32_t w, int32_t h) {
  const float ax = dudx * float(w), bx = dvdx * float(h), ay = dudy * float(w), by = dvdy * float(h);
  const float rx = ax * ax + bx * bx, ry = ay * ay + by * by;
  const float rho2 = rx > ry ? rx : ry;
  if (!(rho2 > 0.0f)) return 0.0f;
  return 0.5f * ::log2f(rho2);
}

// Trilinear filtering: bilinear in the two levels around lod, blended.
template <class Texels, class Lut>
KOKKOS_INLINE_FUNCTION float4 sampleTrilinear(const TextureGPU& t, const Texels& texels, const Lut& lut, float u, float v,
                                              float lod) {
  const float maxLod = float(t.levels - 1);
  lod = lod < 0.0f ? 0.0f : (lod > maxLod ? maxLod : lod);
  const int k = int(::floorf(lod));
  const float f = lod - float(k);
  const float ru = reduceCoord(u, t.wrapS), rv = reduceCoord(v, t.wrapT);
  const TextureGPU lk = mipLevel(t, k);
  const float4 a = sampleBilinearAt(lk, texels, lut, ru, rv);
  if (f <= 0.0f || k + 1 >= t.levels) return a;
  const float4 b = sampleBilinearAt(nextMip(lk), texels, lut, ru, rv);
  return a * (1.0f - f) + b * f;
}

// The minification filter of a glTF sampler at level of detail lod > 0.
template <class Texels, class Lut>
KOKKOS_INLINE_FUNCTION float4 sampleSamplerAt(const TextureGPU& t, const Texels& texels, const Lut& lut, float u, float v,
                                              float lod) {
  constexpr int32_t kNearest = 9728, kNearestMipNearest = 9984, kLinearMipNearest = 9985, kNearestMipLinear = 9986;
  const int32_t m = t.minFilter;
  const bool nearestTexel = m == kNearest || m == kNearestMipNearest || m == kNearestMipLinear;
  const float ru = reduceCoord(u, t.wrapS), rv = reduceCoord(v, t.wrapT);  // once for both levels
  auto sample = [&](const TextureGPU& l) {
    return nearestTexel ? sampleNearestAt(l, texels, lut, ru, rv) : sampleBilinearAt(l, texels, lut, ru, rv);
  };
  if (m == kNearest || m == 9729 || t.levels <= 1) return sample(t);
  const float maxLod = float(t.levels - 1);
  const float l = lod > maxLod ? maxLod : lod;
  // The nearest level: ceil(lambda + 1/2) - 1 (OpenGL 4.6, section 8.14.3), level 0 up to lambda = 1/2.
  if (m == kNearestMipNearest || m == kLinearMipNearest) return sample(mipLevel(t, int(::ceilf(l + 0.5f)) - 1));
  const int k = int(::floorf(l));
  const float f = l - float(k);
  const TextureGPU lk = mipLevel(t, k);
  const float4 a = sample(lk);
  if (f <= 0.0f || k + 1 >= t.levels) return a;
  return a * (1.0f - f) + sample(nextMip(lk)) * f;
}

// The anisotropic footprint of EXT_texture_filter_anisotropic (core in OpenGL
// 4.6, section 8.14): rx and ry the squared lengths, in texels, of the
// footprint's sides (the coordinates' screen derivatives), Pmax and Pmin the
// longer and the shorter: N = min(ceil(Pmax / Pmin), maxAniso) taps along the
// longer side, at level of detail lambda' = log2(Pmax / N). lambda', not the
// isotropic log2(Pmax), then tells magnification (lambda' <= 0) from
// minification. A degenerate shorter side takes maxAniso taps.
struct AnisoFootprint {
  int32_t taps;
  float lod;
};

KOKKOS_INLINE_FUNCTION AnisoFootprint anisoFootprint(float rx, float ry, int32_t maxAniso) {
  const float rmax2 = rx > ry ? rx : ry, rmin2 = rx > ry ? ry : rx;
  const float ratio = rmin2 > 0.0f ? ::sqrtf(rmax2 / rmin2) : float(maxAniso);
  const int32_t n = ratio >= float(maxAniso) ? maxAniso : int32_t(::ceilf(ratio));
  return {n, 0.5f * ::log2f(rmax2) - ::log2f(float(n))};
}

// A glTF sampler's filtering (TextureGPU::magFilter, minFilter, GL enums) for
// a pixel whose texture coordinates change by (dx, dy) per pixel: the
// magnification filter where the footprint is under a texel, else the
// minification filter with its mipmap rule when the texture has levels
// (nearest level: ceil(lambda + 1/2) - 1; linear: the two levels around
// lambda), lambda = log2 of the footprint's longer side in texels.
// maxAniso > 1: anisotropic filtering where the sampler filters linearly
// between levels (as the Khronos Sample Renderer asks WebGL for, 16x):
// anisoFootprint's taps, spread evenly along the footprint's longer side,
// averaged; where lambda' <= 0 they are magnified, and take the
// magnification filter (LINEAR: anisotropy is asked only with it) at level 0.
// Where the whole footprint is under a texel (lambda <= 0) one tap stands for
// the taps (the spec's taps would all lie within about one texel of it).
template <class Texels, class Lut>
KOKKOS_INLINE_FUNCTION float4 sampleSampler(const TextureGPU& t, const Texels& texels, const Lut& lut, float u, float v,
                                            float2 dx, float2 dy, int32_t maxAniso) {
  constexpr int32_t kNearest = 9728, kNearestMipLinear = 9986;
  const float ax = dx.x * float(t.width), bx = dx.y * float(t.height), ay = dy.x * float(t.width), by = dy.y * float(t.height);
  const float rx = ax * ax + bx * bx, ry = ay * ay + by * by;
  const float rho2 = rx > ry ? rx : ry;
  const float lod = rho2 > 0.0f ? 0.5f * ::log2f(rho2) : 0.0f;
  if (!(lod > 0.0f)) return t.magFilter == kNearest ? sampleNearest(t, texels, lut, u, v) : sampleBilinear(t, texels, lut, u, v);
  const int32_t m0 = t.minFilter;
  if (maxAniso > 1 && t.levels > 1 && t.magFilter != kNearest && (m0 == kNearestMipLinear || m0 == 9987)) {
    const AnisoFootprint f = anisoFootprint(rx, ry, maxAniso);
    if (f.taps > 1) {
      const float2 axis = rx > ry ? dx : dy;  // the longer side, in uv per pixel
      const bool magnified = !(f.lod > 0.0f);
      float4 acc{0.0f, 0.0f, 0.0f, 0.0f};
      for (int32_t i = 0; i < f.taps; ++i) {
        const float s = (float(i) + 0.5f) / float(f.taps) - 0.5f;
        const float tu = u + axis.x * s, tv = v + axis.y * s;
        acc = acc + (magnified ? sampleBilinear(t, texels, lut, tu, tv) : sampleSamplerAt(t, texels, lut, tu, tv, f.lod));
      }
      return acc * (1.0f / float(f.taps));
    }
  }
  return sampleSamplerAt(t, texels, lut, u, v, lod);
}

}  // namespace rast
