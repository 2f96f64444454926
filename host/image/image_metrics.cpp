#include "host/image/image_metrics.h"

#include "base/color.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <stdexcept>

namespace rast {
namespace {

const std::array<double, 256>& srgbTable() {
  static const std::array<double, 256> t = [] {
    std::array<double, 256> r{};
    for (int v = 0; v < 256; ++v) r[v] = srgbDecode(v / 255.0);
    return r;
  }();
  return t;
}

inline uint32_t channel(uint32_t p, int c) { return (p >> (8 * c)) & 0xffu; }

void checkSize(size_t n, int W, int H, const char* what) {
  if (W < 1 || H < 1) throw std::invalid_argument("compareImages: image size must be at least 1x1");
  if (n != size_t(W) * size_t(H))
    throw std::invalid_argument(std::string("compareImages: ") + what + " does not hold W*H pixels");
}

}  // namespace

double srgbByteToLinear(uint32_t v) { return srgbTable()[v & 0xffu]; }

std::vector<double> lumaOf(const std::vector<uint32_t>& rgba) {
  std::vector<double> y(rgba.size());
  for (size_t i = 0; i < rgba.size(); ++i)
    y[i] = (0.2126 * channel(rgba[i], 0) + 0.7152 * channel(rgba[i], 1) + 0.0722 * channel(rgba[i], 2)) / 255.0;
  return y;
}

double ssimLuma(const std::vector<double>& x, const std::vector<double>& y, int W, int H, int* windowUsed) {
  checkSize(x.size(), W, H, "first image");
  checkSize(y.size(), W, H, "second image");
  int n = std::min({kSsimWindow, W, H});
  if (n % 2 == 0) --n;
  if (windowUsed) *windowUsed = n;
  // Normalised 1-D Gaussian; the 2-D window is its outer product (also sum 1).
  std::vector<double> g(n);
  double gs = 0.0;
  for (int k = 0; k < n; ++k) {
    const double d = k - (n - 1) / 2.0;
    g[k] = std::exp(-d * d / (2.0 * kSsimSigma * kSsimSigma));
    gs += g[k];
  }
  for (double& v : g) v /= gs;

  // Horizontal pass over every row, "valid" columns only, for the five
  // moments; then the vertical pass computes SSIM per window position.
  const int Wo = W - n + 1, Ho = H - n + 1;
  const size_t m = size_t(H) * Wo;
  std::vector<double> hx(m), hy(m), hxx(m), hyy(m), hxy(m);
  for (int r = 0; r < H; ++r) {
    const double* xr = x.data() + size_t(r) * W;
    const double* yr = y.data() + size_t(r) * W;
    for (int c = 0; c < Wo; ++c) {
      double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
      for (int k = 0; k < n; ++k) {
        const double a = xr[c + k], b = yr[c + k], w = g[k];
        sx += w * a;
        sy += w * b;
        sxx += w * (a * a);
        syy += w * (b * b);
        sxy += w * (a * b);
      }
      const size_t i = size_t(r) * Wo + c;
      hx[i] = sx, hy[i] = sy, hxx[i] = sxx, hyy[i] = syy, hxy[i] = sxy;
    }
  }
  double total = 0.0;
  for (int r = 0; r < Ho; ++r) {
    for (int c = 0; c < Wo; ++c) {
      double mx = 0, my = 0, exx = 0, eyy = 0, exy = 0;
      for (int k = 0; k < n; ++k) {
        const size_t i = size_t(r + k) * Wo + c;
        const double w = g[k];
        mx += w * hx[i];
        my += w * hy[i];
        exx += w * hxx[i];
        eyy += w * hyy[i];
        exy += w * hxy[i];
      }
      // Written so that swapping x and y gives bit-identical results.
      const double vx = exx - mx * mx, vy = eyy - my * my, cxy = exy - mx * my;
      total += ((2.0 * (mx * my) + kSsimC1) * (2.0 * cxy + kSsimC2)) /
               ((mx * mx + my * my + kSsimC1) * (vx + vy + kSsimC2));
    }
  }
  return total / (double(Wo) * Ho);
}

std::vector<uint8_t> edgeMaskFromIds(const std::vector<uint32_t>& ids, int W, int H) {
  checkSize(ids.size(), W, H, "id image");
  std::vector<uint8_t> m(ids.size(), 0);
  for (int r = 0; r < H; ++r)
    for (int c = 0; c < W; ++c) {
      const size_t i = size_t(r) * W + c;
      const uint32_t id = ids[i];
      m[i] = (c > 0 && ids[i - 1] != id) || (c + 1 < W && ids[i + 1] != id) || (r > 0 && ids[i - W] != id) ||
             (r + 1 < H && ids[i + W] != id);
    }
  return m;
}

std::vector<uint8_t> edgeMaskFromSobel(const std::vector<uint32_t>& rgba, int W, int H, double threshold) {
  checkSize(rgba.size(), W, H, "reference image");
  const std::vector<double> y = lumaOf(rgba);
  auto at = [&](int r, int c) {
    r = std::clamp(r, 0, H - 1);
    c = std::clamp(c, 0, W - 1);
    return y[size_t(r) * W + c];
  };
  std::vector<uint8_t> m(rgba.size(), 0);
  for (int r = 0; r < H; ++r)
    for (int c = 0; c < W; ++c) {
      const double gx = (at(r - 1, c + 1) + 2.0 * at(r, c + 1) + at(r + 1, c + 1)) -
                        (at(r - 1, c - 1) + 2.0 * at(r, c - 1) + at(r + 1, c - 1));
      const double gy = (at(r + 1, c - 1) + 2.0 * at(r + 1, c) + at(r + 1, c + 1)) -
                        (at(r - 1, c - 1) + 2.0 * at(r - 1, c) + at(r - 1, c + 1));
      m[size_t(r) * W + c] = std::sqrt(gx * gx + gy * gy) / 4.0 > threshold;
    }
  return m;
}

ImageMetrics compareImages(const std::vector<uint32_t>& a, const std::vector<uint32_t>& b, int W, int H,
                           const std::vector<uint32_t>* refIdsTopDown) {
  checkSize(a.size(), W, H, "reference image");
  checkSize(b.size(), W, H, "test image");
  if (refIdsTopDown) checkSize(refIdsTopDown->size(), W, H, "id image");
  const auto& lin = srgbTable();

  ImageMetrics m;
  m.width = W;
  m.height = H;
  m.pixels = uint64_t(W) * uint64_t(H);
  m.edgesFromIds = refIdsTopDown != nullptr;
  const std::vector<uint8_t> edge = refIdsTopDown ? edgeMaskFromIds(*refIdsTopDown, W, H) : edgeMaskFromSobel(a, W, H);

  double sum = 0.0, edgeSum = 0.0;
  for (size_t i = 0; i < a.size(); ++i) {
    double s = 0.0;
    int maxd = 0;
    for (int c = 0; c < 3; ++c) {
      const uint32_t va = channel(a[i], c), vb = channel(b[i], c);
      const double d = lin[va] - lin[vb];
      s += d * d;
      maxd = std::max(maxd, std::abs(int(va) - int(vb)));
    }
    sum += s;
    if (edge[i]) {
      edgeSum += s;
      ++m.edgePixels;
    }
    m.countGt1 += maxd > 1;
    m.countGt8 += maxd > 8;
    m.maxChannelDiff = std::max(m.maxChannelDiff, maxd);
  }
  m.rmseLinear = std::sqrt(sum / (3.0 * double(m.pixels)));
  m.psnrLinear = m.rmseLinear > 0.0 ? 20.0 * std::log10(1.0 / m.rmseLinear) : std::numeric_limits<double>::infinity();
  m.edgeRmseLinear = m.edgePixels ? std::sqrt(edgeSum / (3.0 * double(m.edgePixels))) : 0.0;
  m.fracGt1 = double(m.countGt1) / double(m.pixels);
  m.fracGt8 = double(m.countGt8) / double(m.pixels);
  m.ssim = ssimLuma(lumaOf(a), lumaOf(b), W, H, &m.ssimWindow);
  return m;
}

}  // namespace rast
