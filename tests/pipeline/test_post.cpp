// Post-processing passes (core/post/): the blur kernel and its spread, the
// bright pass, the tone curves, SSAO on a concave corner and on an open plane,
// and the determinism of the whole chain.
#include "base/color.h"
#include "host/image/image_metrics.h"
#include "pipeline/post/bloom.h"
#include "pipeline/post/ssao.h"
#include "pipeline/post/tonemap.h"
#include "tests/support/test_support.h"

#include <catch2/catch.hpp>
#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>

using namespace rast;
using test::download;

namespace {

template <class T>
DView<T> upload(const std::vector<T>& v) {
  DView<T> d("test", v.size());
  Kokkos::View<const T*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>> h(v.data(), v.size());
  Kokkos::deep_copy(d, h);
  return d;
}

// Two quads: a floor (y = 0) and, when `wall`, a back wall (z = -1) meeting it
// in a concave corner along x.
Scene cornerScene(bool wall) {
  std::vector<rast::float3> p = {{-2, 0, -1}, {2, 0, -1}, {2, 0, 2}, {-2, 0, 2}};
  std::vector<uint32_t> idx = {0, 2, 1, 0, 3, 2};
  if (wall) {
    const std::vector<rast::float3> w = {{-2, 0, -1}, {2, 0, -1}, {2, 2, -1}, {-2, 2, -1}};
    p.insert(p.end(), w.begin(), w.end());
    for (uint32_t k : {4u, 5u, 6u, 4u, 6u, 7u}) idx.push_back(k);
  }
  return test::trianglesScene(p, idx);
}

Camera cornerCamera() {
  Camera c;
  c.eye = {0.0, 1.2, 2.0};
  c.target = {0.0, 0.2, -0.8};
  c.up = {0.0, 1.0, 0.0};
  c.znear = 0.05;
  c.zfar = 50.0;
  return c;
}

// Pixel (column, row from the top) where a world point appears.
std::pair<int, int> project(const Camera& c, int w, int h, glm::dvec3 p) {
  const glm::dvec4 q = c.viewProjection(w, h) * glm::dvec4(p, 1.0);
  const double x = (q.x / q.w * 0.5 + 0.5) * w, y = (q.y / q.w * 0.5 + 0.5) * h;
  return {int(x), h - 1 - int(y)};
}

double linearGreen(uint32_t c) { return srgbByteToLinear((c >> 8) & 0xff); }

}  // namespace

TEST_CASE("bloom: the Gaussian kernel sums to one and an isolated pixel spreads over exactly its radius",
          "[post][bloom]") {
  for (int r : {1, 3, 8, 16, 32}) {
    const std::vector<float> w = gaussianWeights(r);
    double sum = w[0];
    for (int k = 1; k <= r; ++k) {
      sum += 2.0 * w[size_t(k)];
      REQUIRE(w[size_t(k)] < w[size_t(k) - 1]);  // falls off from the centre
      REQUIRE(w[size_t(k)] > 0.0f);
    }
    REQUIRE(sum == Approx(1.0).margin(1e-6));
  }
  const int W = 41, H = 37, r = 6, cx = 20, cy = 18;
  std::vector<rast::float4> img(size_t(W) * H, rast::float4{0, 0, 0, 0});
  img[size_t(cy) * W + cx] = rast::float4{1.0f, 2.0f, 4.0f, 0.0f};
  const std::vector<float> wts = gaussianWeights(r);
  DView<rast::float4> d = upload(img), tmp("tmp", img.size());
  blurSeparable(d, tmp, W, H, upload(wts), r);
  const std::vector<rast::float4> out = download(d);
  double total = 0.0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const rast::float4 v = out[size_t(y) * W + x];
      const int dx = std::abs(x - cx), dy = std::abs(y - cy);
      total += v.x;
      if (dx <= r && dy <= r) {
        // Separable: the product of the 1-D weights, per channel.
        REQUIRE(v.x == Approx(wts[size_t(dx)] * wts[size_t(dy)]).epsilon(1e-5));
        REQUIRE(v.z == Approx(4.0 * wts[size_t(dx)] * wts[size_t(dy)]).epsilon(1e-5));
      } else {
        REQUIRE(v.x == 0.0f);
        REQUIRE(v.y == 0.0f);
      }
    }
  REQUIRE(total == Approx(1.0).margin(1e-5));  // energy kept
}

TEST_CASE("bloom: the bright pass keeps nothing at or under the threshold", "[post][bloom]") {
  const int W = 64, H = 48;
  const float thr = 0.8f;
  std::vector<rast::float4> img(size_t(W) * H);
  uint32_t s = 12345;
  auto rnd = [&s]() { return float((s = s * 1664525u + 1013904223u) >> 8) / 16777216.0f; };
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      // Left half: under the threshold (luminance <= 0.8); right half: bright.
      const float k = x < W / 2 ? 0.8f : 1.5f + 3.0f * rnd();
      img[size_t(y) * W + x] = rast::float4{k * rnd(), k * rnd(), k * rnd(), 1.0f};
      if (x >= W / 2) img[size_t(y) * W + x] = rast::float4{k, k, k, 1.0f};
    }
  img[5] = rast::float4{thr, thr, thr, 1.0f};  // exactly at the threshold
  DView<rast::float4> half("half", size_t(W / 2) * (H / 2));
  bloomBrightPass(upload(img), W, H, half, thr);
  const std::vector<rast::float4> out = download(half);
  for (int y = 0; y < H / 2; ++y)
    for (int x = 0; x < W / 2; ++x) {
      const rast::float4 v = out[size_t(y) * (W / 2) + x];
      if (x < W / 4) {
        REQUIRE(v.x == 0.0f);
        REQUIRE(v.y == 0.0f);
        REQUIRE(v.z == 0.0f);
      } else {
        REQUIRE(v.x > 0.0f);
      }
    }
  REQUIRE(brightPart(rast::float4{thr, thr, thr, 1}, thr).x == 0.0f);
  REQUIRE(brightPart(rast::float4{2.0f * thr, 2.0f * thr, 2.0f * thr, 1}, thr).x == Approx(thr).epsilon(1e-6));
}

TEST_CASE("tone maps are monotonic and hit their analytic values", "[post][tonemap]") {
  REQUIRE(toneReinhard(0.0f) == 0.0f);
  REQUIRE(toneReinhard(1.0f) == Approx(0.5f));
  REQUIRE(toneReinhard(3.0f) == Approx(0.75f));
  REQUIRE(toneAces(0.0f) == 0.0f);
  REQUIRE(toneAces(1.0f) == Approx(2.54 / 3.16).epsilon(1e-6));
  REQUIRE(toneAces(0.18f) == Approx(0.18 * (2.51 * 0.18 + 0.03) / (0.18 * (2.43 * 0.18 + 0.59) + 0.14)).epsilon(1e-6));
  REQUIRE(toneAces(1e6f) == 1.0f);
  float pr = -1.0f, pa = -1.0f;
  for (int i = 0; i <= 64 * 256; ++i) {
    const float x = float(i) / 256.0f;
    const float r = toneReinhard(x), a = toneAces(x);
    REQUIRE(r >= pr);
    REQUIRE(a >= pa);
    REQUIRE(r < 1.0f);
    REQUIRE(a <= 1.0f);
    pr = r;
    pa = a;
  }
}

TEST_CASE("exposure and tone mapping through the film: the background encodes to the analytic value",
          "[post][tonemap]") {
  // A scene whose one triangle is off screen: every pixel is background 0.3.
  const Scene s = test::trianglesScene({{5, 5, 0}, {6, 5, 0}, {5, 6, 0}}, {0, 1, 2});
  RenderSettings rs;
  rs.width = 8;
  rs.height = 8;
  rs.background = rast::float4{0.3f, 0.3f, 0.3f, 1.0f};
  struct Case {
    float ev;
    ToneMap t;
    double expect;
  } cases[] = {{0.0f, ToneMap::None, 0.3}, {1.0f, ToneMap::None, 0.6}, {1.0f, ToneMap::Reinhard, 0.6 / 1.6},
               {2.0f, ToneMap::Aces, 1.2 * (2.51 * 1.2 + 0.03) / (1.2 * (2.43 * 1.2 + 0.59) + 0.14)},
               {-1.0f, ToneMap::Reinhard, 0.15 / 1.15}};
  for (const Case& c : cases) {
    rs.post.exposure = c.ev;
    rs.post.tonemap = c.t;
    Renderer r(s);
    r.render(test::identityCamera(), rs);
    for (uint32_t px : r.colorTopDown()) REQUIRE(((px >> 8) & 0xff) == srgbEncodeByte(c.expect));
  }
}

TEST_CASE("SSAO darkens the inside of a concave corner and leaves an open plane untouched", "[post][ssao]") {
  const int W = 160, H = 120;
  const Camera cam = cornerCamera();
  RenderSettings rs;
  rs.width = W;
  rs.height = H;
  RenderSettings ao = rs;
  ao.post.ssao = true;
  ao.post.ssaoRadius = 0.4f;
  ao.post.ssaoSamples = 32;
  auto render = [&](const Scene& s, const RenderSettings& st) {
    Renderer r(s);
    r.render(cam, st);
    return r.colorTopDown();
  };
  // Open plane: every covered pixel keeps its light within 3%. (2% until the
  // directions were interleaved: a pixel now marches a quarter of them, its
  // 2x2 cell the same quarter, so one direction grazing the plane's depth
  // steps weighs more after the blur; measured worst: 2.4%, two pixels of
  // 160x120, the rest within 1.5%.)
  {
    const Scene floor = cornerScene(false);
    const auto a = render(floor, rs), b = render(floor, ao);
    int covered = 0;
    for (size_t i = 0; i < a.size(); ++i) {
      if (linearGreen(a[i]) == 0.0) continue;
      ++covered;
      REQUIRE(linearGreen(b[i]) >= 0.97 * linearGreen(a[i]));
    }
    REQUIRE(covered > W * H / 4);
  }
  // Corner: just above the floor at the wall, and on the wall just above the
  // floor, at least 15% darker; far from the wall, untouched within 2%.
  {
    const Scene corner = cornerScene(true);
    const auto a = render(corner, rs), b = render(corner, ao);
    auto ratio = [&](glm::dvec3 p) {
      const auto [x, y] = project(cam, W, H, p);
      REQUIRE(x >= 0);
      REQUIRE(x < W);
      REQUIRE(y >= 0);
      REQUIRE(y < H);
      const size_t i = size_t(y) * W + x;
      REQUIRE(linearGreen(a[i]) > 0.0);
      return linearGreen(b[i]) / linearGreen(a[i]);
    };
    for (double x : {-0.5, 0.0, 0.5}) {
      REQUIRE(ratio({x, 0.0, -0.95}) < 0.85);
      REQUIRE(ratio({x, 0.05, -1.0}) < 0.85);
      REQUIRE(ratio({x, 0.0, 0.3}) > 0.98);
      REQUIRE(ratio({x, 0.8, -1.0}) > 0.98);
    }
  }
}

TEST_CASE("SSAO's interleave: every 3x3 window marches every direction, each pixel a balanced share, every slot every rotation",
          "[post][ssao]") {
  // The march's loop over directions (core/post/ssao.cpp), for pixel (x, y).
  auto directions = [](int x, int y, int n) {
    std::vector<int> ks;
    for (int k = ssaoSlot(x, y, n); k < n; k += ssaoInterleave(n)) ks.push_back(k);
    return ks;
  };
  for (int n = 1; n <= 256; ++n) {
    // Any 3x3 window (inside the blur's 5x5) sees all n directions.
    for (int y0 = 0; y0 < 8; ++y0)
      for (int x0 = 0; x0 < 8; ++x0) {
        std::vector<int> seen(size_t(n), 0);
        for (int y = y0; y < y0 + 3; ++y)
          for (int x = x0; x < x0 + 3; ++x)
            for (int k : directions(x, y, n)) ++seen[size_t(k)];
        REQUIRE(*std::min_element(seen.begin(), seen.end()) >= 1);
      }
    // A 4x4 tile marches each direction equally often (4 times), and each
    // pixel a quarter of them: the taps fall by 4.
    std::vector<int> times(size_t(n), 0);
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x) {
        const std::vector<int> ks = directions(x, y, n);
        REQUIRE(int(ks.size()) >= std::max(1, n / 4));
        REQUIRE(int(ks.size()) == std::max(1, n / 4) + (n >= 4 && n % 4 > ssaoSlot(x, y, n) ? 1 : 0));
        for (int k : ks) ++times[size_t(k)];
      }
    if (n >= 4)
      for (int t : times) REQUIRE(t == 4);
  }
  // Every slot meets every quarter turn of the rotation pattern in a 4x4 tile
  // (otherwise its directions all lean one way: see ssao.h).
  for (int slot = 0; slot < 4; ++slot) {
    int quarters = 0;
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x)
        if (ssaoSlot(x, y, 8) == slot) quarters |= 1 << (ssaoBayer(x, y) / 4);
    REQUIRE(quarters == 15);
  }
}

TEST_CASE("the post chain is deterministic: repeated frames are identical, and its memory is held only while used", "[post]") {
  const Scene s = cornerScene(true);
  RenderSettings rs;
  rs.width = 96;
  rs.height = 64;
  rs.post.exposure = 1.5f;
  rs.post.tonemap = ToneMap::Aces;
  rs.post.bloom = true;
  rs.post.bloomThreshold = 0.5f;
  rs.post.ssao = true;
  rs.post.ssaoRadius = 0.3f;
  Renderer r(s);
  REQUIRE(r.render(cornerCamera(), rs).filmBytes >= size_t(96 * 64) * (16 + 16 + 4 + 4 + 4));  // film, geometry, AO
  const auto first = r.colorTopDown();
  for (int k = 0; k < 3; ++k) {
    r.render(cornerCamera(), rs);
    REQUIRE(r.colorTopDown() == first);
  }
  // Without any pass, the frame is packed directly: identical to a renderer
  // that never used the film.
  RenderSettings plain = rs;
  plain.post = PostSettings{};
  // The float film costs memory only while it is used.
  REQUIRE(r.render(cornerCamera(), plain).filmBytes == 0);
  Renderer fresh(s);
  fresh.render(cornerCamera(), plain);
  REQUIRE(r.colorTopDown() == fresh.colorTopDown());
}
