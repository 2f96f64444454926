// Image quality metrics (core/image_metrics.h): RMSE/PSNR in linear light,
// SSIM, threshold counts and the edge masks, on small synthetic images whose
// expected values are computed by hand.
#include <catch2/catch.hpp>

#include "host/image/image_metrics.h"

#include <cmath>
#include <stdexcept>
#include <string>

using namespace rast;

namespace {

uint32_t rgb(uint32_t r, uint32_t g, uint32_t b) { return r | g << 8 | b << 16 | 0xffu << 24; }
uint32_t grey(uint32_t v) { return rgb(v, v, v); }

// A smooth pattern with some structure, so SSIM windows see variance.
std::vector<uint32_t> pattern(int W, int H) {
  std::vector<uint32_t> p(size_t(W) * H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const double v = 128 + 60 * std::sin(x * 0.31) * std::cos(y * 0.23) + ((x / 8 + y / 8) % 2 ? 40 : -40);
      const uint32_t c = uint32_t(std::lround(std::fmin(255.0, std::fmax(0.0, v))));
      p[size_t(y) * W + x] = rgb(c, 255 - c, (c * 3) & 0xff);
    }
  return p;
}

// Deterministic noise of amplitude +-amp on every channel (clamped to 0..255).
std::vector<uint32_t> addNoise(const std::vector<uint32_t>& img, int amp, uint32_t seed) {
  std::vector<uint32_t> o(img.size());
  uint32_t s = seed;
  for (size_t i = 0; i < img.size(); ++i) {
    uint32_t px = 0xffu << 24;
    for (int c = 0; c < 3; ++c) {
      s = s * 1664525u + 1013904223u;
      const int n = int((s >> 8) % uint32_t(2 * amp + 1)) - amp;
      const int v = std::max(0, std::min(255, int((img[i] >> (8 * c)) & 0xff) + n));
      px |= uint32_t(v) << (8 * c);
    }
    o[i] = px;
  }
  return o;
}

std::string maskString(const std::vector<uint8_t>& m, int W, int H) {
  std::string s;
  for (int y = 0; y < H; ++y) {
    for (int x = 0; x < W; ++x) s += m[size_t(y) * W + x] ? '#' : '.';
    s += '\n';
  }
  return s;
}

}  // namespace

TEST_CASE("sRGB decoding is the exact piecewise curve", "[metrics]") {
  CHECK(srgbByteToLinear(0) == 0.0);
  CHECK(srgbByteToLinear(255) == Approx(1.0).epsilon(1e-15));
  CHECK(srgbByteToLinear(10) == Approx(10.0 / 255.0 / 12.92).epsilon(1e-15));  // linear segment (<= 0.04045)
  CHECK(srgbByteToLinear(11) == Approx(0.003346535763899161).epsilon(1e-12));  // first byte on the power segment
  CHECK(srgbByteToLinear(128) == Approx(0.21586050011389926).epsilon(1e-12));
}

TEST_CASE("identical images: zero error, infinite PSNR, SSIM 1, no counted pixels", "[metrics]") {
  const int W = 40, H = 30;
  const auto a = pattern(W, H);
  for (bool withIds : {false, true}) {
    std::vector<uint32_t> ids(a.size());
    for (size_t i = 0; i < ids.size(); ++i) ids[i] = uint32_t(i % W < 20 ? 1 : 2);
    const ImageMetrics m = compareImages(a, a, W, H, withIds ? &ids : nullptr);
    CHECK(m.width == W);
    CHECK(m.height == H);
    CHECK(m.pixels == uint64_t(W * H));
    CHECK(m.rmseLinear == 0.0);
    CHECK(std::isinf(m.psnrLinear));
    CHECK(m.psnrLinear > 0);
    CHECK(m.ssim == 1.0);
    CHECK(m.ssimWindow == 11);
    CHECK(m.countGt1 == 0);
    CHECK(m.countGt8 == 0);
    CHECK(m.fracGt1 == 0.0);
    CHECK(m.fracGt8 == 0.0);
    CHECK(m.maxChannelDiff == 0);
    CHECK(m.edgeRmseLinear == 0.0);
    CHECK(m.edgesFromIds == withIds);
    CHECK(m.edgePixels > 0);
  }
}

TEST_CASE("RMSE and PSNR in linear light, computed by hand", "[metrics]") {
  SECTION("one black pixel turned white in a 2x2 image") {
    // Squared error 1 on three channels of one pixel: sqrt(3 / (3*4)) = 0.5;
    // PSNR = 20 log10(1/0.5) = 6.0206 dB.
    const std::vector<uint32_t> a(4, grey(0));
    std::vector<uint32_t> b = a;
    b[2] = grey(255);
    const ImageMetrics m = compareImages(a, b, 2, 2);
    CHECK(m.rmseLinear == Approx(0.5).epsilon(1e-12));
    CHECK(m.psnrLinear == Approx(20.0 * std::log10(2.0)).epsilon(1e-12));
    CHECK(m.countGt1 == 1);
    CHECK(m.countGt8 == 1);
    CHECK(m.maxChannelDiff == 255);
  }
  SECTION("one channel of one pixel of a grey 16x16 image: 128 -> 200") {
    // lin(200) - lin(128) = 0.5775804404296506 - 0.2158605001138993 = 0.3617199403157513,
    // over 3 * 256 channel values: RMSE = 0.3617199403 / sqrt(768) = 0.01305244405703465.
    const std::vector<uint32_t> a(256, grey(128));
    std::vector<uint32_t> b = a;
    b[5 * 16 + 7] = rgb(200, 128, 128);
    const ImageMetrics m = compareImages(a, b, 16, 16);
    CHECK(m.rmseLinear == Approx(0.01305244405703465).epsilon(1e-10));
    CHECK(m.psnrLinear == Approx(-20.0 * std::log10(0.01305244405703465)).epsilon(1e-10));
    CHECK(m.countGt1 == 1);
    CHECK(m.fracGt1 == Approx(1.0 / 256));
    CHECK(m.maxChannelDiff == 72);
    // The same difference the other way round gives the same RMSE.
    CHECK(compareImages(b, a, 16, 16).rmseLinear == m.rmseLinear);
  }
  SECTION("alpha is ignored") {
    const std::vector<uint32_t> a(9, grey(50));
    std::vector<uint32_t> b = a;
    b[4] = b[4] & 0x00ffffffu;
    const ImageMetrics m = compareImages(a, b, 3, 3);
    CHECK(m.rmseLinear == 0.0);
    CHECK(m.countGt1 == 0);
  }
}

TEST_CASE("threshold counts: max channel difference > 1/255 and > 8/255, exactly", "[metrics]") {
  // Ten pixels on one row; differences (in 8-bit sRGB units) per pixel, in
  // various channels and both directions.
  const int W = 10, H = 1;
  std::vector<uint32_t> a(W, grey(100)), b = a;
  b[0] = grey(100);            // 0
  b[1] = rgb(101, 100, 100);   // 1: not > 1
  b[2] = rgb(100, 99, 100);    // 1 (negative): not > 1
  b[3] = rgb(100, 100, 102);   // 2: > 1
  b[4] = rgb(92, 100, 100);    // 8: > 1, not > 8
  b[5] = rgb(100, 108, 101);   // max 8: > 1, not > 8
  b[6] = rgb(100, 100, 109);   // 9: > 1 and > 8
  b[7] = rgb(91, 91, 91);      // 9 everywhere: > 1 and > 8
  b[8] = rgb(101, 99, 101);    // all 1: not > 1
  b[9] = rgb(100, 100, 100) & 0x00ffffffu;  // alpha only: 0
  const ImageMetrics m = compareImages(a, b, W, H);
  CHECK(m.countGt1 == 5);  // pixels 3, 4, 5, 6, 7
  CHECK(m.countGt8 == 2);  // pixels 6, 7
  CHECK(m.fracGt1 == Approx(0.5));
  CHECK(m.fracGt8 == Approx(0.2));
  CHECK(m.maxChannelDiff == 9);
}

TEST_CASE("SSIM: 1 for equal images, decreasing with noise, symmetric", "[metrics]") {
  const int W = 64, H = 48;
  const auto a = pattern(W, H);
  double prev = compareImages(a, a, W, H).ssim;
  CHECK(prev == 1.0);
  for (int amp : {2, 8, 24, 64}) {
    const auto b = addNoise(a, amp, 12345u + amp);
    const ImageMetrics ab = compareImages(a, b, W, H), ba = compareImages(b, a, W, H);
    INFO("noise amplitude " << amp << ": SSIM " << ab.ssim);
    CHECK(ab.ssim < prev);
    CHECK(ab.ssim > -1.0);
    CHECK(ab.ssim == ba.ssim);  // bit-identical either way round
    CHECK(ab.rmseLinear == ba.rmseLinear);
    CHECK(ab.countGt1 == ba.countGt1);
    prev = ab.ssim;
  }
  CHECK(prev < 0.5);
}

TEST_CASE("SSIM of two flat images is the luminance term (2xy + C1) / (x^2 + y^2 + C1)", "[metrics]") {
  // No variance anywhere: the contrast-structure term is C2 / C2 = 1.
  const int W = 20, H = 16;
  const std::vector<uint32_t> black(W * H, grey(0)), white(W * H, grey(255)), mid(W * H, grey(102));
  CHECK(compareImages(black, white, W, H).ssim == Approx(kSsimC1 / (1.0 + kSsimC1)).epsilon(1e-6));
  const double y = 102.0 / 255.0;  // luma of the encoded value (0.2126 + 0.7152 + 0.0722 = 1)
  CHECK(compareImages(mid, white, W, H).ssim == Approx((2 * y + kSsimC1) / (y * y + 1 + kSsimC1)).epsilon(1e-9));
}

TEST_CASE("SSIM window: 11x11 when it fits, else the largest odd size that does", "[metrics]") {
  int n = 0;
  const std::vector<double> x(11 * 11, 0.5);
  CHECK(ssimLuma(x, x, 11, 11, &n) == Approx(1.0));
  CHECK(n == 11);
  const std::vector<double> y(8 * 5, 0.25);
  CHECK(ssimLuma(y, y, 8, 5, &n) == Approx(1.0));
  CHECK(n == 5);
  const std::vector<double> z(4 * 40, 0.25);
  ssimLuma(z, z, 40, 4, &n);
  CHECK(n == 3);
  const std::vector<double> one(1, 0.25);
  CHECK(ssimLuma(one, one, 1, 1, &n) == Approx(1.0));
  CHECK(n == 1);
}

TEST_CASE("edge mask from ids marks exactly the pixels on id boundaries", "[metrics]") {
  SECTION("two regions split vertically") {
    const int W = 8, H = 4;
    std::vector<uint32_t> ids(W * H);
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) ids[y * W + x] = x < 3 ? 1 : 2;
    CHECK(maskString(edgeMaskFromIds(ids, W, H), W, H) ==
          "..##....\n"
          "..##....\n"
          "..##....\n"
          "..##....\n");
  }
  SECTION("a rectangle on background: both sides, 4-neighbourhood (no diagonal corners)") {
    const int W = 8, H = 7;
    std::vector<uint32_t> ids(W * H, 0);
    for (int y = 2; y <= 4; ++y)
      for (int x = 2; x <= 5; ++x) ids[y * W + x] = 7;
    CHECK(maskString(edgeMaskFromIds(ids, W, H), W, H) ==
          "........\n"
          "..####..\n"
          ".######.\n"
          ".##..##.\n"
          ".######.\n"
          "..####..\n"
          "........\n");
  }
  SECTION("edge RMSE counts only masked pixels") {
    const int W = 8, H = 4;
    std::vector<uint32_t> ids(W * H);
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) ids[y * W + x] = x < 3 ? 1 : 2;
    const std::vector<uint32_t> a(W * H, grey(0));
    std::vector<uint32_t> interior = a, edge = a;
    interior[1 * W + 6] = grey(255);  // column 6: not an edge
    edge[1 * W + 2] = grey(255);      // column 2: an edge (8 edge pixels in all)
    const ImageMetrics mi = compareImages(a, interior, W, H, &ids);
    CHECK(mi.edgesFromIds);
    CHECK(mi.edgePixels == 8);
    CHECK(mi.edgeRmseLinear == 0.0);
    CHECK(mi.rmseLinear == Approx(std::sqrt(1.0 / 32)));
    const ImageMetrics me = compareImages(a, edge, W, H, &ids);
    CHECK(me.edgeRmseLinear == Approx(std::sqrt(1.0 / 8)));
    CHECK(me.rmseLinear == Approx(std::sqrt(1.0 / 32)));
  }
}

TEST_CASE("edge mask without ids: Sobel of the reference's luma", "[metrics]") {
  // Black | white step between columns 3 and 4: the Sobel response (normalised
  // to 1 for a full step) is 1 on columns 3 and 4 and 0 elsewhere.
  const int W = 10, H = 6;
  std::vector<uint32_t> ref(W * H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) ref[y * W + x] = grey(x < 4 ? 0 : 255);
  const std::string expect =
      "...##.....\n"
      "...##.....\n"
      "...##.....\n"
      "...##.....\n"
      "...##.....\n"
      "...##.....\n";
  CHECK(maskString(edgeMaskFromSobel(ref, W, H), W, H) == expect);
  // A weak step (10/255 of luma: response 0.039) stays under the threshold 0.1.
  std::vector<uint32_t> weak(W * H);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) weak[y * W + x] = grey(x < 4 ? 100 : 110);
  std::string none;
  for (int y = 0; y < H; ++y) none += "..........\n";
  CHECK(maskString(edgeMaskFromSobel(weak, W, H), W, H) == none);
  // compareImages uses the REFERENCE (first image) for the mask.
  const std::vector<uint32_t> flat(W * H, grey(0));
  CHECK(compareImages(ref, flat, W, H).edgePixels == 12);
  CHECK(compareImages(flat, ref, W, H).edgePixels == 0);
  CHECK_FALSE(compareImages(ref, flat, W, H).edgesFromIds);
}

TEST_CASE("compareImages rejects mismatched sizes", "[metrics]") {
  const std::vector<uint32_t> a(12, grey(1)), b(11, grey(1));
  CHECK_THROWS_AS(compareImages(a, b, 4, 3), std::invalid_argument);
  CHECK_THROWS_AS(compareImages(a, a, 3, 3), std::invalid_argument);
  CHECK_THROWS_AS(compareImages(a, a, 0, 0), std::invalid_argument);
  const std::vector<uint32_t> ids(10, 1);
  CHECK_THROWS_AS(compareImages(a, a, 4, 3, &ids), std::invalid_argument);
}
