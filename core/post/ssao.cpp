// SSAO: hemisphere ray marching in view space from the depth and normals that
// shading wrote for every pixel (PostBuffers::geom), then a depth-aware
// (bilateral) blur that removes the 4x4 rotation pattern, then the film is
// multiplied by the result. Fixed sample kernel and rotation pattern: the same
// result on every backend and every run.
#include "ssao.h"

#include "chain.h"

#include <cmath>

namespace rast {
namespace {

constexpr float kPi = 3.14159265358979f;
constexpr int kSteps = 4;  // march steps per sample direction

double radicalInverse(uint32_t k, uint32_t base) {
  double inv = 1.0 / base, f = inv, r = 0.0;
  for (; k; k /= base, f *= inv) r += f * (k % base);
  return r;
}

// View-space position of pixel (x, y) (bottom-up rows) at view depth d.
KOKKOS_INLINE_FUNCTION float3 viewPos(int x, int y, float d, int w, int h, float tanX, float tanY) {
  const float nx = 2.0f * (float(x) + 0.5f) / float(w) - 1.0f, ny = 2.0f * (float(y) + 0.5f) / float(h) - 1.0f;
  return float3{nx * tanX * d, ny * tanY * d, -d};
}

}  // namespace

std::vector<float4> ssaoKernel(int n) {
  std::vector<float4> k(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    const double u1 = (i + 0.5) / n, u2 = radicalInverse(uint32_t(i), 2);
    const double z = std::sqrt(u1), r = std::sqrt(1.0 - u1), phi = 2.0 * 3.14159265358979 * u2;
    k[size_t(i)] = float4{float(r * std::cos(phi)), float(r * std::sin(phi)), float(z), 1.0f};
  }
  return k;
}

float ssaoRadiusFor(const PostSettings& s, double eyeTargetDistance) {
  return s.ssaoRadius > 0.0f ? s.ssaoRadius : float(0.05 * eyeTargetDistance);
}

void postSsao(PostBuffers& b, const PostView& v, const PostSettings& s) {
  const int w = v.width, h = v.height;
  const int64_t n = int64_t(w) * h;
  ensureCapacity(b.ao, "post.ssao.ao", size_t(n));
  ensureCapacity(b.aoBlur, "post.ssao.blur", size_t(n));
  if (b.sampleCount != s.ssaoSamples) {
    const std::vector<float4> k = ssaoKernel(s.ssaoSamples);
    b.samples = allocUninit<float4>("post.ssao.kernel", k.size());
    Kokkos::View<const float4*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>> hv(k.data(), k.size());
    Kokkos::deep_copy(b.samples, hv);
    b.sampleCount = s.ssaoSamples;
  }
  auto geom = b.geom;
  auto depth = b.depth;
  auto ao = b.ao;
  auto kernel = b.samples;
  const int ns = s.ssaoSamples;
  const float radius = v.ssaoRadius, tanX = v.tanX, tanY = v.tanY;
  // A sample counts as occluded when the surface seen through it is this far in
  // front of it: keeps a flat plane from occluding itself through the depth
  // quantisation of sampling it at pixel centres.
  const float bias = 0.03f * radius;
  Kokkos::parallel_for("rast::post::ssao", Range(0, n), KOKKOS_LAMBDA(const int64_t i) {
    const float4 g = geom(i);
    if (!(g.w > 0.0f)) {
      ao(i) = 1.0f;
      return;
    }
    const int x = int(i % w), y = int(i / w);
    const float3 P = viewPos(x, y, g.w, w, h, tanX, tanY);
    const float3 N{g.x, g.y, g.z};
    // Tangent frame rotated per pixel by a 4x4 ordered (Bayer) pattern of angles.
    const int bayer[16] = {0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5};
    const float ang = 2.0f * kPi * float(bayer[(x & 3) + 4 * (y & 3)]) / 16.0f;
    const float3 a = (N.x < 0.9f && N.x > -0.9f) ? float3{1.0f, 0.0f, 0.0f} : float3{0.0f, 1.0f, 0.0f};
    const float3 T0 = normalize(cross(a, N)), B0 = cross(N, T0);
    const float ca = ::cosf(ang), sa = ::sinf(ang);
    const float3 T = T0 * ca + B0 * sa, B = cross(N, T);
    // Each sample is a ray (cosine-weighted direction) marched in kSteps
    // steps out to the radius, the first step offset per pixel by the same
    // pattern: occluded when a step lies behind the depth buffer's surface by
    // no more than the radius (surfaces are assumed that thick).
    const float jitter = (float(bayer[(y & 3) + 4 * (x & 3)]) + 0.5f) / 16.0f;
    float occluded = 0.0f;
    for (int k = 0; k < ns; ++k) {
      const float4 q = kernel(k);
      const float3 dir = T * q.x + B * q.y + N * q.z;
      for (int j = 0; j < kSteps; ++j) {
        const float3 S = P + dir * (radius * (float(j) + jitter) / float(kSteps));
        const float sd = -S.z;
        if (!(sd > 0.0f)) break;
        const int px = int(::floorf((S.x / (sd * tanX) * 0.5f + 0.5f) * float(w)));
        const int py = int(::floorf((S.y / (sd * tanY) * 0.5f + 0.5f) * float(h)));
        if (px < 0 || py < 0 || px >= w || py >= h) break;
        const float od = depth(int64_t(py) * w + px);
        if (od > 0.0f && od < sd - bias && sd - od < radius) {
          occluded += 1.0f;
          break;
        }
      }
    }
    ao(i) = 1.0f - occluded / float(ns);
  });

  // Bilateral 5x5 blur: neighbours at a similar depth only, so occlusion does
  // not bleed across silhouettes. Then the film is darkened.
  auto blur = b.aoBlur;
  auto hdr = b.hdr;
  Kokkos::parallel_for("rast::post::ssao::blur", Range(0, n), KOKKOS_LAMBDA(const int64_t i) {
    const float d = depth(i);
    if (!(d > 0.0f)) {
      blur(i) = 1.0f;
      return;
    }
    const int x = int(i % w), y = int(i / w);
    const float tol = 0.05f * d;
    float sum = 0.0f, wsum = 0.0f;
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx) {
        const int xx = x + dx, yy = y + dy;
        if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
        const int64_t j = int64_t(yy) * w + xx;
        const float dj = depth(j);
        if (!(dj > 0.0f)) continue;
        const float dd = (dj - d) / tol;
        const float wt = 1.0f / (1.0f + dd * dd);
        sum += ao(j) * wt;
        wsum += wt;
      }
    const float o = sum / wsum;
    blur(i) = o;
    const float4 c = hdr(i);
    hdr(i) = float4{c.x * o, c.y * o, c.z * o, c.w};
  });
}

}  // namespace rast
