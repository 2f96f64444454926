// Image quality against a ground truth: error metrics between two RGBA8 sRGB
// images of the same size (host code, plain C++17).
//
// `a` is the REFERENCE (ground truth), `b` the image under test. Every metric
// reads the R, G and B channels only (alpha is ignored: rast writes opaque
// images). The definitions, exactly:
//
// * rmseLinear: sRGB bytes are decoded exactly to linear light in [0,1]
//     (c = v/255; c <= 0.04045 ? c/12.92 : ((c+0.055)/1.055)^2.4, in double);
//     RMSE = sqrt( sum over pixels and R,G,B of (lin(a)-lin(b))^2 / (3 W H) ).
// * psnrLinear = 20 log10(1 / rmseLinear) dB (peak 1.0, linear light);
//     +infinity when the images are identical (rmseLinear == 0).
// * ssim: mean SSIM of Wang, Bovik, Sheikh, Simoncelli (2004) on luma
//     Y' = 0.2126 R' + 0.7152 G' + 0.0722 B' of the sRGB-ENCODED values in [0,1]
//     (SSIM is defined on display-referred values, as in the paper), with an
//     11x11 Gaussian window, sigma 1.5 (normalised to sum 1), L = 1,
//     C1 = (0.01 L)^2, C2 = (0.03 L)^2, over the window positions that lie fully
//     inside the image ("valid", as the authors' reference code). An image
//     smaller than 11 pixels on a side uses the largest odd window that fits
//     (renormalised Gaussian, same sigma).
// * countGt1 / countGt8: pixels whose largest |a-b| over R,G,B, in 8-bit sRGB
//     units, is > 1 (i.e. > 1/255) and > 8 (> 8/255); frac* = count / (W H).
// * edgeRmseLinear: rmseLinear restricted to the edge mask (0 when the mask is
//     empty; edgePixels says how many pixels it holds).
//     With a primitive-id image of the reference (top row first): a pixel is an
//     edge when one of its 4 neighbours inside the image has a different id
//     (both sides of every boundary, including boundaries between two
//     triangles of one mesh and between geometry and background, id 0).
//     Without ids: a pixel is an edge when the Sobel gradient magnitude of the
//     reference's luma Y' (replicated border), divided by 4 so that a full
//     0->1 step gives 1, exceeds kSobelEdgeThreshold.
#pragma once

#include <cstdint>
#include <vector>

namespace rast {

constexpr int kSsimWindow = 11;
constexpr double kSsimSigma = 1.5;
constexpr double kSsimC1 = 0.01 * 0.01;
constexpr double kSsimC2 = 0.03 * 0.03;
constexpr double kSobelEdgeThreshold = 0.1;

struct ImageMetrics {
  int width = 0, height = 0;
  uint64_t pixels = 0;
  double rmseLinear = 0.0;
  double psnrLinear = 0.0;  // dB; +infinity for identical images
  double ssim = 1.0;
  int ssimWindow = kSsimWindow;  // the window actually used (smaller for tiny images)
  uint64_t countGt1 = 0, countGt8 = 0;
  double fracGt1 = 0.0, fracGt8 = 0.0;
  int maxChannelDiff = 0;  // largest |a-b| over all pixels and R,G,B, 8-bit sRGB units
  double edgeRmseLinear = 0.0;
  uint64_t edgePixels = 0;
  bool edgesFromIds = false;  // true: mask from the id image; false: Sobel on the reference
};

// a: reference, b: test; RGBA8 sRGB, R in the low byte, W*H each, any row order
// (both the same). refIdsTopDown (optional): the reference's primitive ids, W*H,
// top row first (as readIdsBin returns them) in the same row order as a and b.
// Throws std::invalid_argument when sizes do not match W*H or W, H < 1.
ImageMetrics compareImages(const std::vector<uint32_t>& a, const std::vector<uint32_t>& b, int W, int H,
                           const std::vector<uint32_t>* refIdsTopDown = nullptr);

// The pieces, for tests and tools.
double srgbByteToLinear(uint32_t v);  // exact decode of one 8-bit sRGB value
// Mean SSIM as above on two single-channel images with values in [0,1].
double ssimLuma(const std::vector<double>& x, const std::vector<double>& y, int W, int H, int* windowUsed = nullptr);
std::vector<double> lumaOf(const std::vector<uint32_t>& rgba);  // Y' of the encoded values, [0,1]
// Edge masks (1 = edge), W*H in the input's row order.
std::vector<uint8_t> edgeMaskFromIds(const std::vector<uint32_t>& ids, int W, int H);
std::vector<uint8_t> edgeMaskFromSobel(const std::vector<uint32_t>& rgba, int W, int H,
                                       double threshold = kSobelEdgeThreshold);

}  // namespace rast
