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

#include "../backends/cpu_clones.h"
#include "shade_fragment.h"

namespace rast {
namespace shading {

constexpr int kMaxSpanRun = 64;  // longest run a ShadeSpans work item takes

// What spanLighting needs of a span's triangle, the camera and the light.
struct SpanConsts {
  double s0, s1, s2, a0, a1, a2;  // edge values at the span's first pixel, steps per pixel
  float ia, iw0, iw1, iw2;        // 1 / area, per-vertex 1/w (1 when affine)
  float t00, t10, t20, t01, t11, t21;  // raster vertices' barycentrics in the drawn triangle
  float3 n0, n1, n2, q0, q1, q2;  // drawn vertices' world normals and positions
  float3 eye;
  float ambient, headI;           // headI: the headlight's intensity, 0 without it
};

// The arithmetic of a span, as loops over its pixels that the compiler
// vectorizes (also for AVX2: cpu_clones.h).
KOKKOS_INLINE_FUNCTION void spanLighting(const SpanConsts& k, int32_t m, float* __restrict__ b0, float* __restrict__ b1, float* __restrict__ b2, float* __restrict__ nx,
                                     float* __restrict__ ny, float* __restrict__ nz, float* __restrict__ diffuse) {
  // The edge values step in double, exactly (integers below 2^53), and
  // float(double(e)) rounds as float(e) does, so the weights are
  // bit-identical; unlike int64 -> float, double -> float conversion vectorizes.
  for (int32_t j = 0; j < m; ++j) {
    b0[j] = float(k.s1 + k.a1 * double(j)) * k.ia;
    b1[j] = float(k.s2 + k.a2 * double(j)) * k.ia;
    b2[j] = float(k.s0 + k.a0 * double(j)) * k.ia;
  }
  const float iw0 = k.iw0, iw1 = k.iw1, iw2 = k.iw2;
  const float t00 = k.t00, t10 = k.t10, t20 = k.t20, t01 = k.t01, t11 = k.t11, t21 = k.t21;
  const float3 n0 = k.n0, n1 = k.n1, n2 = k.n2, q0 = k.q0, q1 = k.q1, q2 = k.q2, eye = k.eye;
  const float ambient = k.ambient, headI = k.headI, third = 1.0f / 3.0f;
    for (int32_t j = 0; j < m; ++j) {
      float w0 = b0[j] * iw0, w1 = b1[j] * iw1, w2 = b2[j] * iw2;
      const float sum = w0 + w1 + w2;
      const bool ok = (sum != 0.0f) & (sum - sum == 0.0f);  // nonzero and finite (isFinite); no branch
      const float inv = 1.0f / sum;
      w0 = ok ? w0 * inv : third;
      w1 = ok ? w1 * inv : third;
      w2 = ok ? w2 * inv : third;
      const float c1 = w0 * t00 + w1 * t10 + w2 * t20;
      const float c2 = w0 * t01 + w1 * t11 + w2 * t21;
      const float c0 = 1.0f - c1 - c2;
      b0[j] = c0;
      b1[j] = c1;
      b2[j] = c2;
      // normalize() of the interpolated normal
      float x = n0.x * c0 + n1.x * c1 + n2.x * c2, y = n0.y * c0 + n1.y * c1 + n2.y * c2,
            z = n0.z * c0 + n1.z * c1 + n2.z * c2;
      float l2 = x * x + y * y + z * z;
      float s = 1.0f / ::sqrtf(l2 > 0.0f ? l2 : 1.0f);
      x = l2 > 0.0f ? x * s : 0.0f;
      y = l2 > 0.0f ? y * s : 0.0f;
      z = l2 > 0.0f ? z * s : 0.0f;
      nx[j] = x;
      ny[j] = y;
      nz[j] = z;
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
      diffuse[j] = ambient + headI * (ndl > 0.0f ? ndl : 0.0f);  // exactly ambient without the headlight
    }
}
// The same, built also for AVX2; worth its indirect call on longer spans.
RAST_CPU_CLONES void spanLightingWide(const SpanConsts& k, int32_t m, float* __restrict__ b0, float* __restrict__ b1,
                                      float* __restrict__ b2, float* __restrict__ nx, float* __restrict__ ny,
                                      float* __restrict__ nz, float* __restrict__ diffuse) {
  spanLighting(k, m, b0, b1, b2, nx, ny, nz, diffuse);
}

// A span's colours, lit and packed as sRGB RGBA8 (Shade::display of
// shadeFragment's rgb * diffuse + spec, spec being 0 in Lambert).
KOKKOS_INLINE_FUNCTION void packSpan(int32_t m, const float4* __restrict__ base, const float* __restrict__ diffuse,
                                     const float* __restrict__ table, uint32_t* __restrict__ dst) {
  for (int32_t j = 0; j < m; ++j) {
    const float d = diffuse[j];
    const float a = clamp01(base[j].w) * 255.0f + 0.5f;  // unorm8, in [0.5, 255.5]: int conversion is exact
    dst[j] = encodeSrgb8Flat(base[j].x * d + 0.0f, table) | encodeSrgb8Flat(base[j].y * d + 0.0f, table) << 8 |
             encodeSrgb8Flat(base[j].z * d + 0.0f, table) << 16 | uint32_t(int32_t(a)) << 24;
  }
}
RAST_CPU_CLONES void packSpanWide(int32_t m, const float4* __restrict__ base, const float* __restrict__ diffuse,
                                  const float* __restrict__ table, uint32_t* __restrict__ dst) {
  packSpan(m, base, diffuse, table, dst);
}

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
    shadeRow(x0, Y, n, idx, depthBits);
  }

  // Pixels [x0, x0 + n) of row Y, given the visibility keys' halves: raster
  // index + 1 (0: none) and depth bits. Also called by the fused binned
  // raster (shade_stage.cpp) with a finished tile's rows.
  KOKKOS_INLINE_FUNCTION void shadeRow(int32_t x0, int32_t Y, int32_t n, const uint32_t* idx,
                                       const uint32_t* depthBits) const {
    const int64_t row = int64_t(Y) * width + x0;
    if (p.wantDepth)
      for (int32_t j = 0; j < n; ++j) depthOut(row + j) = bitsFloat(depthBits[j]);
    if (p.wantPrimId)
      for (int32_t j = 0; j < n; ++j) {
        const uint32_t id = idx[j];
        primOut(row + j) = id == 0 ? 0 : (id - 1) & kLineFlag ? lineShade.primId((id - 1) & ~kLineFlag) : tris(id - 1).prim + 1;
      }
    TriFrag f;
    for (int32_t j = 0; j < n;) {
      const uint32_t id = idx[j];
      int32_t k = j + 1;
      while (k < n && idx[k] == id) ++k;
      if (id == 0) {
        if (p.floatOut) {
          for (int32_t m = j; m < k; ++m) hdr(row + m) = p.backgroundFilm;
        } else {
          uint32_t* const dst = color.data() + row;  // a plain fill the compiler vectorizes
          const uint32_t bg = p.backgroundPacked;
          for (int32_t m = j; m < k; ++m) dst[m] = bg;
        }
      } else {
        use(id - 1, f);
        if ((id - 1) & kLineFlag) {
          for (int32_t m = j; m < k; ++m) put(row + m, shadeFragment(f, x0 + m, Y, 0, 0, 0.0f, nullptr));
        } else {
          span(f, row + j, x0 + j, Y, k - j);
        }
      }
      j = k;
    }
  }

  // Pixels [xa, xa + m) of row Y, all of f's triangle (a raster triangle).
  KOKKOS_INLINE_FUNCTION void span(const TriFrag& f, int64_t out, int32_t xa, int32_t Y, int32_t m) const {
    const RasterTri& t = *f.t;
    const Edges& e = f.e;
    float b0[kMaxSpanRun], b1[kMaxSpanRun], b2[kMaxSpanRun];
    float nx[kMaxSpanRun], ny[kMaxSpanRun], nz[kMaxSpanRun];
    float diffuse[kMaxSpanRun];
    float4 base[kMaxSpanRun];
    // Screen-space weights from the exact edge values (as Shade::bary: l0 from
    // edge 1, l1 from edge 2, l2 from edge 0), then the perspective-correct
    // weights in the drawn triangle, the normal, the position and the
    // headlight of every pixel (Shade::bary, shadeFragment): spanLighting.
    SpanConsts k;
    k.s1 = double(e.eval(1, xa, Y));
    k.s2 = double(e.eval(2, xa, Y));
    k.s0 = double(e.eval(0, xa, Y));
    k.a1 = double(e.A[1]);
    k.a2 = double(e.A[2]);
    k.a0 = double(e.A[0]);
    k.ia = t.invArea;
    k.iw0 = p.perspective ? t.invW[0] : 1.0f;
    k.iw1 = p.perspective ? t.invW[1] : 1.0f;
    k.iw2 = p.perspective ? t.invW[2] : 1.0f;
    k.t00 = t.bary[0][0]; k.t10 = t.bary[1][0]; k.t20 = t.bary[2][0];
    k.t01 = t.bary[0][1]; k.t11 = t.bary[1][1]; k.t21 = t.bary[2][1];
    k.n0 = f.n[0]; k.n1 = f.n[1]; k.n2 = f.n[2];
    k.q0 = f.pos[0]; k.q1 = f.pos[1]; k.q2 = f.pos[2];
    k.eye = p.eye;
    k.ambient = p.ambient;
    const int headlight = p.headlight;
    k.headI = headlight ? 1.0f - p.ambient : 0.0f;
    if (m >= kWideSpan) spanLightingWide(k, m, b0, b1, b2, nx, ny, nz, diffuse);
    else spanLighting(k, m, b0, b1, b2, nx, ny, nz, diffuse);
    if (!headlight) {
      const int nl = int(lights.extent(0));
      for (int k = 0; k < nl; ++k) {
        const float3 L = lights(k).direction;
        const float I = lights(k).intensity;
        for (int32_t j = 0; j < m; ++j) {
          const float ndl = nx[j] * L.x + ny[j] * L.y + nz[j] * L.z;
          diffuse[j] += I * (ndl > 0.0f ? ndl : 0.0f);
        }
      }
    }
    // Base colour: material, texture (scalar: texel fetches), vertex colour.
    for (int32_t j = 0; j < m; ++j) base[j] = f.baseColor;
    if (f.textured) {
      for (int32_t j = 0; j < m; ++j) {
        const float2 uv = uvAt(f, b0[j], b1[j], b2[j]);
        const float4 tc = p.filter == TexFilter::Nearest ? sampleNearest(f.tex, texels, lut, uv.x, uv.y)
                                                         : sampleBilinear(f.tex, texels, lut, uv.x, uv.y);
        base[j] = base[j] * tc;
      }
    }
    if (hasColor) {
      for (int32_t j = 0; j < m; ++j)
        base[j] = base[j] * (f.col[0] * b0[j] + f.col[1] * b1[j] + f.col[2] * b2[j]);
    }
    if (!p.floatOut) {
      uint32_t* dst = color.data() + out;
      if (m >= kWideSpan) packSpanWide(m, base, diffuse, encode.data(), dst);
      else packSpan(m, base, diffuse, encode.data(), dst);
      return;
    }
    for (int32_t j = 0; j < m; ++j) {
      const float d = diffuse[j];
      // rgb * diffuse + spec (0 in Lambert), as shadeFragment adds it
      hdr(out + j) = float4{base[j].x * d + 0.0f, base[j].y * d + 0.0f, base[j].z * d + 0.0f, base[j].w};
    }
  }
};

}  // namespace shading
}  // namespace rast
