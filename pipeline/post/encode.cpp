// The film's one encoder: float colour -> RGBA8 (sRGB for light, raw bytes for
// the diagnostic modes), with the same table the direct path uses, so a film
// that no pass changed encodes to the bytes direct shading would have written.
// straight: the film is premultiplied by its alpha (a transparent background,
// docs/transparency.md) and the bytes are straight alpha, as PNG stores them.
#include "base/color.h"
#include "pipeline/post/chain.h"

namespace rast {

void postEncode(const DView<float4>& hdr, int64_t n, const DView<uint32_t>& color, const DView<uint32_t>& packed, bool raw,
                bool straight) {
  if (straight) {
    Kokkos::parallel_for("rast::post::encode_straight", Range(0, n), KOKKOS_LAMBDA(const int64_t i) {
      float4 c = hdr(i);
      const float a = c.w > 0.0f ? (c.w < 1.0f ? c.w : 1.0f) : 0.0f;  // NaN: 0
      if (a > 0.0f && a < 1.0f) c = float4{c.x / a, c.y / a, c.z / a, a};
      c.w = a;
      const uint32_t rgb = raw ? packRaw8(c) & 0xffffffu : packSrgb8Packed(c, packed) & 0xffffffu;
      color(i) = rgb | unorm8(a) << 24;
    });
    return;
  }
  Kokkos::parallel_for("rast::post::encode", Range(0, n), KOKKOS_LAMBDA(const int64_t i) {
    color(i) = raw ? packRaw8(hdr(i)) : packSrgb8Packed(hdr(i), packed);
  });
}

}  // namespace rast
