// SSAO: hemisphere ray marching in view space from the depth and normals that
// shading wrote for every pixel (PostBuffers::geom), interleaved (each pixel
// marches a quarter of the directions, see ssaoSlot), then a separable
// depth-aware (bilateral) blur that gathers the block's directions and removes
// the 4x4 rotation pattern, then the film is multiplied by the result. Fixed
// sample kernel, rotation and interleave patterns: the same result on every
// backend and every run.
//
// Why interleaved: the march's cost is its scattered depth taps (each a cache
// sector of its own once the radius spans tens of pixels). Marching all N
// directions at every pixel and then averaging 25 neighbours spends N x 25
// rays on each output; marching N/4 per pixel and averaging the same
// neighbourhood still sees every direction in every block, at a quarter of the
// taps.
#include "pipeline/post/ssao.h"

#include "pipeline/post/chain.h"

#include <cmath>

namespace rast {
namespace {

constexpr int kSteps = 4;     // march steps per sample direction
constexpr int kBlurRadius = 2;  // the separable blur's half-width: spans the 2x2 interleave block and the 4x4 rotation
// The blur's tile per team: 64x16 outputs, with the apron 68x20 of depth and
// raw AO plus 64x20 row results in team scratch (16 KiB, under
// kFastScratchBytes); wide rows keep the loads coalesced.
constexpr int kBlurTileW = 64, kBlurTileH = 16;

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

// Bilateral weight of a neighbour at depth dj for a pixel at depth d: falls off
// with the depth difference relative to 5% of the depth, so occlusion does not
// bleed across silhouettes. invTol = 1 / (0.05 d), computed once per pixel: on
// a GPU the blur is arithmetic-bound, and a division per tap costs more than
// the tap (IEEE division, since the CUDA build compiles with --fmad=false).
KOKKOS_INLINE_FUNCTION float depthWeight(float d, float dj, float invTol) {
  const float dd = (dj - d) * invTol;
  return 1.0f / (1.0f + dd * dd);
}

// cos and sin of the 16 rotation angles (ssaoBayer sixteenths of a turn),
// rounded once on the host from double: every backend uses the same floats,
// and no kernel evaluates a transcendental per pixel.
struct RotationTable {
  float c[16], s[16];
};
RotationTable rotationTable() {
  RotationTable t;
  for (int k = 0; k < 16; ++k) {
    const double a = 2.0 * 3.14159265358979323846 * k / 16.0;
    t.c[k] = float(std::cos(a));
    t.s[k] = float(std::sin(a));
  }
  return t;
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
  // The march writes ao, the blur reads it and writes aoBlur (what the `ao`
  // AOV reads): separate buffers, since the blur's teams read each other's
  // aprons.
  auto raw = b.ao;
  auto kernel = b.samples;
  const int ns = s.ssaoSamples;
  const float radius = v.ssaoRadius, tanX = v.tanX, tanY = v.tanY;
  // A sample counts as occluded when the surface seen through it is this far in
  // front of it: keeps a flat plane from occluding itself through the depth
  // quantisation of sampling it at pixel centres.
  const float bias = 0.03f * radius;
  // Window x of a view-space point S: (S.x / (-S.z tanX) * 0.5 + 0.5) w, as
  // S.x * (1 / -S.z) * sx + cx: one division per tap instead of two.
  const float sx = 0.5f * float(w) / tanX, sy = 0.5f * float(h) / tanY, cx = 0.5f * float(w), cy = 0.5f * float(h);
  const RotationTable rot = rotationTable();
  // Pixel indices fit 32 bits (kMaxFramebufferSide^2 < 2^31); 64-bit division
  // and remainder are emulated on GPUs, 32-bit ones are several times cheaper.
  Kokkos::parallel_for("rast::post::ssao", Range(0, n), KOKKOS_LAMBDA(const int64_t i64) {
    const int i = int(i64);
    const float4 g = geom(i);
    if (!(g.w > 0.0f)) {
      raw(i) = 1.0f;
      return;
    }
    const int y = i / w, x = i - y * w;
    const float3 P = viewPos(x, y, g.w, w, h, tanX, tanY);
    const float3 N{g.x, g.y, g.z};
    // Tangent frame rotated per pixel by a 4x4 ordered (Bayer) pattern of angles.
    const int rk = ssaoBayer(x, y);
    const float3 a = (N.x < 0.9f && N.x > -0.9f) ? float3{1.0f, 0.0f, 0.0f} : float3{0.0f, 1.0f, 0.0f};
    const float3 T0 = normalize(cross(a, N)), B0 = cross(N, T0);
    const float ca = rot.c[rk], sa = rot.s[rk];
    const float3 T = T0 * ca + B0 * sa, B = cross(N, T);
    // Each sample is a ray (cosine-weighted direction) marched in kSteps
    // steps out to the radius, the first step offset per pixel by the same
    // pattern: occluded when a step lies behind the depth buffer's surface by
    // no more than the radius (surfaces are assumed that thick). This pixel
    // marches only its slot's share of the directions (ssaoSlot).
    const float jitter = (float(ssaoBayer(y, x)) + 0.5f) / 16.0f;
    const int stride = ssaoInterleave(ns);
    float occluded = 0.0f, marched = 0.0f;
    for (int k = ssaoSlot(x, y, ns); k < ns; k += stride) {
      const float4 q = kernel(k);
      const float3 dir = T * q.x + B * q.y + N * q.z;
      marched += 1.0f;
      for (int j = 0; j < kSteps; ++j) {
        const float3 S = P + dir * (radius * (float(j) + jitter) / float(kSteps));
        const float sd = -S.z;
        if (!(sd > 0.0f)) break;
        const float inv = 1.0f / sd;
        const int px = int(::floorf(S.x * inv * sx + cx));
        const int py = int(::floorf(S.y * inv * sy + cy));
        if (px < 0 || py < 0 || px >= w || py >= h) break;
        const float od = depth(py * w + px);
        if (od > 0.0f && od < sd - bias && sd - od < radius) {
          occluded += 1.0f;
          break;
        }
      }
    }
    raw(i) = 1.0f - occluded / marched;
  });

  // Separable bilateral blur, kBlurRadius each way: horizontal, then vertical
  // (which also darkens the film). 2 x 5 taps instead of a 5x5 square's 25;
  // the product of the two 1D weights approximates the square's. Both passes
  // run in one kernel: a team loads its tile of depth and raw AO with a
  // kBlurRadius apron into team scratch, blurs the rows (apron rows included)
  // into scratch, then the columns. The same taps in the same order as two
  // separate passes, so the result is bit-identical to them, without the
  // intermediate image's round trip through memory or a second launch.
  auto out = b.aoBlur;
  auto hdr = b.hdr;
  constexpr int R = kBlurRadius, TW = kBlurTileW, TH = kBlurTileH, SW = TW + 2 * R, SH = TH + 2 * R;
  static_assert((2 * SW * SH + TW * SH) * sizeof(float) + 256 <= kFastScratchBytes, "the blur's tile must fit fast scratch");
  const int tilesX = (w + TW - 1) / TW, tilesY = (h + TH - 1) / TH;
  using ScratchF = Kokkos::View<float*, Exec::scratch_memory_space, Kokkos::MemoryTraits<Kokkos::Unmanaged>>;
  TeamPolicy policy(tilesX * tilesY, kTeamSize);
  policy.set_scratch_size(0, Kokkos::PerTeam(2 * ScratchF::shmem_size(SW * SH) + ScratchF::shmem_size(TW * SH)));
  Kokkos::parallel_for("rast::post::ssao::blur", policy, KOKKOS_LAMBDA(const TeamMember& t) {
    const int x0 = (t.league_rank() % tilesX) * TW, y0 = (t.league_rank() / tilesX) * TH;
    ScratchF sd(t.team_scratch(0), SW * SH), sa(t.team_scratch(0), SW * SH), sm(t.team_scratch(0), TW * SH);
    // Depth 0 outside the image: such taps are skipped, as no surface.
    Kokkos::parallel_for(Kokkos::TeamThreadRange(t, SW * SH), [&](const int k) {
      const int gx = x0 - R + k % SW, gy = y0 - R + k / SW;
      const bool in = gx >= 0 && gy >= 0 && gx < w && gy < h;
      sd(k) = in ? depth(gy * w + gx) : 0.0f;
      sa(k) = in ? raw(gy * w + gx) : 1.0f;
    });
    t.team_barrier();
    // Rows: every row of the apron'd tile, the tile's columns.
    Kokkos::parallel_for(Kokkos::TeamThreadRange(t, TW * SH), [&](const int k) {
      const int r = k / TW, c = k % TW;
      const float d = sd(r * SW + c + R);
      if (!(d > 0.0f)) {
        sm(k) = 1.0f;
        return;
      }
      const float invTol = 1.0f / (0.05f * d);
      float sum = 0.0f, wsum = 0.0f;
      for (int dx = -R; dx <= R; ++dx) {
        const float dj = sd(r * SW + c + R + dx);
        if (!(dj > 0.0f)) continue;
        const float wt = depthWeight(d, dj, invTol);
        sum += sa(r * SW + c + R + dx) * wt;
        wsum += wt;
      }
      sm(k) = sum / wsum;
    });
    t.team_barrier();
    // Columns, then the film.
    Kokkos::parallel_for(Kokkos::TeamThreadRange(t, TW * TH), [&](const int k) {
      const int r = k / TW, c = k % TW, gx = x0 + c, gy = y0 + r;
      if (gx >= w || gy >= h) return;
      const int i = gy * w + gx;
      const float d = sd((r + R) * SW + c + R);
      if (!(d > 0.0f)) {
        out(i) = 1.0f;
        return;
      }
      const float invTol = 1.0f / (0.05f * d);
      float sum = 0.0f, wsum = 0.0f;
      for (int dy = -R; dy <= R; ++dy) {
        const float dj = sd((r + R + dy) * SW + c + R);
        if (!(dj > 0.0f)) continue;
        const float wt = depthWeight(d, dj, invTol);
        sum += sm((r + R + dy) * TW + c) * wt;
        wsum += wt;
      }
      const float o = sum / wsum;
      out(i) = o;
      const float4 cl = hdr(i);
      hdr(i) = float4{cl.x * o, cl.y * o, cl.z * o, cl.w};
    });
  });
}

}  // namespace rast
