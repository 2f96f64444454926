#include "base/color.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rast {

double srgbDecode(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

double srgbEncode(double c) {
  c = std::min(std::max(c, 0.0), 1.0);
  return c <= 0.0031308 ? c * 12.92 : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
}

uint32_t srgbEncodeByte(double linear) { return uint32_t(srgbEncode(linear) * 255.0 + 0.5); }

std::vector<float> srgbDecodeTable() {
  std::vector<float> lut(256);
  for (int i = 0; i < 256; ++i) lut[i] = float(srgbDecode(i / 255.0));
  return lut;
}

std::vector<float> srgbEncodeThresholds() {
  std::vector<float> thr(kSrgbEncodeTableSize);
  thr[0] = -std::numeric_limits<float>::infinity();
  for (int b = 1; b < 256; ++b) {
    // The linear value whose exact sRGB encoding is (b - 0.5) / 255, rounded up
    // to a float so that "t(b) <= c" reproduces round-to-nearest.
    const double lin = srgbDecode((b - 0.5) / 255.0);
    float f = float(lin);
    if (double(f) < lin) f = std::nextafter(f, 2.0f);
    thr[b] = f;
  }
  thr[256] = std::numeric_limits<float>::infinity();  // t(b + 1) for b = 255
  // Each bucket's starting byte: the largest b with t(b) <= its lower end.
  for (uint32_t k = 0; k < kSrgbBuckets; ++k) {
    const float lower = bitsFloat((kSrgbBucketFirst + k) << kSrgbBucketShift);
    uint32_t b = 0;
    while (b < 255 && thr[b + 1] <= lower) ++b;
    thr[kSrgbBucketBase + k] = float(b);
  }
  return thr;
}

std::vector<uint32_t> srgbEncodePacked() {
  const std::vector<float> thr = srgbEncodeThresholds();
  std::vector<uint32_t> packed(kSrgbBuckets);
  for (uint32_t k = 0; k < kSrgbBuckets; ++k) {
    const uint32_t b = uint32_t(thr[kSrgbBucketBase + k]);
    const uint32_t t = floatBits(thr[b + 1]);  // t(256) = +inf lies in no bucket
    const uint32_t low = (t >> kSrgbBucketShift) == kSrgbBucketFirst + k ? (t & 0xffffu) : 0x10000u;
    packed[k] = b << 17 | low;
  }
  return packed;
}

}  // namespace rast
