// Bloom: bright pass to half resolution, separable Gaussian blur there (rows:
// each team stages its line segment plus the apron in team scratch; columns: a
// coalesced gather, see blurColumns), then the blurred light is added back
// with a bilinear upsample. Gathers only: every output is one thread's fixed
// sum, the same on every backend.
#include "pipeline/post/bloom.h"

#include "pipeline/post/chain.h"

#include <cmath>

namespace rast {
namespace {

constexpr int kSegment = 256;  // outputs per team

using Scratch4 = Kokkos::View<float4*, Exec::scratch_memory_space, Kokkos::MemoryTraits<Kokkos::Unmanaged>>;

// One 1-D pass along lines of `len` elements spaced `lineStride` apart, with
// elements `step` apart within a line: rows (step 1) or columns (step w).
void blurLines(const char* label, const DView<float4>& in, const DView<float4>& out, int lines, int len,
               int64_t lineStride, int64_t step, const DView<float>& weights, int r) {
  const int segs = (len + kSegment - 1) / kSegment;
  const int span = kSegment + 2 * r;
  TeamPolicy policy(lines * segs, kTeamSize);
  policy.set_scratch_size(0, Kokkos::PerTeam(Scratch4::shmem_size(span)));
  Kokkos::parallel_for(label, policy, KOKKOS_LAMBDA(const TeamMember& t) {
    const int line = t.league_rank() / segs, first = (t.league_rank() % segs) * kSegment;
    const int64_t base = int64_t(line) * lineStride;
    Scratch4 sh(t.team_scratch(0), span);
    Kokkos::parallel_for(Kokkos::TeamThreadRange(t, span), [&](const int k) {
      const int j = imin(imax(first - r + k, 0), len - 1);  // clamp to edge
      sh(k) = in(base + j * step);
    });
    t.team_barrier();
    const int n = imin(kSegment, len - first);
    Kokkos::parallel_for(Kokkos::TeamThreadRange(t, n), [&](const int k) {
      float4 acc = sh(k + r) * weights(0);
      for (int d = 1; d <= r; ++d) acc = acc + (sh(k + r - d) + sh(k + r + d)) * weights(d);
      out(base + int64_t(first + k) * step) = acc;
    });
  });
}

// The vertical pass as a plain gather: neighbouring threads take neighbouring
// columns of one row, so every tap is a coalesced read (the line version above
// would walk down columns, one cache line per element, on a GPU), and the
// rows a thread re-reads stay in cache. Same taps in the same order as
// blurLines, so the result is bit-identical to it.
void blurColumns(const char* label, const DView<float4>& in, const DView<float4>& out, int w, int h,
                 const DView<float>& weights, int r) {
  Kokkos::parallel_for(label, Range(0, int64_t(w) * h), KOKKOS_LAMBDA(const int64_t i) {
    const int x = int(i % w), y = int(i / w);
    float4 acc = in(i) * weights(0);
    for (int d = 1; d <= r; ++d) {
      const int ya = imax(y - d, 0), yb = imin(y + d, h - 1);  // clamp to edge
      acc = acc + (in(int64_t(ya) * w + x) + in(int64_t(yb) * w + x)) * weights(d);
    }
    out(i) = acc;
  });
}

}  // namespace

std::vector<float> gaussianWeights(int radius) {
  std::vector<double> w(size_t(radius) + 1);
  const double sigma = radius / 3.0;
  double sum = 0.0;
  for (int k = 0; k <= radius; ++k) {
    w[k] = std::exp(-double(k) * k / (2.0 * sigma * sigma));
    sum += k ? 2.0 * w[k] : w[k];
  }
  std::vector<float> out(w.size());
  for (size_t k = 0; k < w.size(); ++k) out[k] = float(w[k] / sum);
  return out;
}

void bloomBrightPass(const DView<float4>& full, int w, int h, const DView<float4>& half, float threshold) {
  const int hw = (w + 1) / 2, hh = (h + 1) / 2;
  Kokkos::parallel_for("rast::post::bloom::bright", Range(0, int64_t(hw) * hh), KOKKOS_LAMBDA(const int64_t i) {
    const int x = int(i % hw), y = int(i / hw);
    const int x0 = 2 * x, y0 = 2 * y, x1 = imin(x0 + 1, w - 1), y1 = imin(y0 + 1, h - 1);
    const float4 s = brightPart(full(int64_t(y0) * w + x0), threshold) + brightPart(full(int64_t(y0) * w + x1), threshold) +
                     brightPart(full(int64_t(y1) * w + x0), threshold) + brightPart(full(int64_t(y1) * w + x1), threshold);
    half(i) = s * 0.25f;
  });
}

void blurSeparable(const DView<float4>& img, const DView<float4>& tmp, int w, int h, const DView<float>& weights,
                   int radius) {
  blurLines("rast::post::bloom::blur_x", img, tmp, h, w, w, 1, weights, radius);
  blurColumns("rast::post::bloom::blur_y", tmp, img, w, h, weights, radius);
}

void postBloom(PostBuffers& b, const PostView& v, const PostSettings& s) {
  const int w = v.width, h = v.height, hw = (w + 1) / 2, hh = (h + 1) / 2;
  const size_t hn = size_t(hw) * hh;
  ensureCapacity(b.half0, "post.bloom.half0", hn);
  ensureCapacity(b.half1, "post.bloom.half1", hn);
  const int r = s.bloomRadius / 2 > 1 ? s.bloomRadius / 2 : 1;  // at half resolution
  if (b.kernelRadius != r) {
    const std::vector<float> wts = gaussianWeights(r);
    b.kernel = allocUninit<float>("post.bloom.kernel", wts.size());
    Kokkos::View<const float*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>> hv(wts.data(), wts.size());
    Kokkos::deep_copy(b.kernel, hv);
    b.kernelRadius = r;
  }
  bloomBrightPass(b.hdr, w, h, b.half0, s.bloomThreshold);
  blurSeparable(b.half0, b.half1, hw, hh, b.kernel, r);
  auto hdr = b.hdr;
  auto half = b.half0;
  const float strength = s.bloomStrength;
  Kokkos::parallel_for("rast::post::bloom::composite", Range(0, int64_t(w) * h), KOKKOS_LAMBDA(const int64_t i) {
    const int x = int(i % w), y = int(i / w);
    // Full-resolution pixel centre in half-resolution texel coordinates.
    const float fx = (float(x) + 0.5f) * 0.5f - 0.5f, fy = (float(y) + 0.5f) * 0.5f - 0.5f;
    const float flx = ::floorf(fx), fly = ::floorf(fy);
    const float a = fx - flx, c = fy - fly;
    const int x0 = imax(int(flx), 0), y0 = imax(int(fly), 0);
    const int x1 = imin(int(flx) + 1, hw - 1), y1 = imin(int(fly) + 1, hh - 1);
    const float4 top = half(int64_t(y0) * hw + x0) * (1.0f - a) + half(int64_t(y0) * hw + x1) * a;
    const float4 bot = half(int64_t(y1) * hw + x0) * (1.0f - a) + half(int64_t(y1) * hw + x1) * a;
    const float4 g = top * (1.0f - c) + bot * c;
    const float4 o = hdr(i);
    hdr(i) = float4{o.x + strength * g.x, o.y + strength * g.y, o.z + strength * g.z, o.w};
  });
}

}  // namespace rast
