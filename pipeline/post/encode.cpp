// The film's one encoder: float colour -> RGBA8 (sRGB for light, raw bytes for
// the diagnostic modes), with the same table the direct path uses, so a film
// that no pass changed encodes to the bytes direct shading would have written.
#include "base/color.h"
#include "pipeline/post/chain.h"

namespace rast {

void postEncode(const DView<float4>& hdr, int64_t n, const DView<uint32_t>& color, const DView<uint32_t>& packed, bool raw) {
  Kokkos::parallel_for("rast::post::encode", Range(0, n), KOKKOS_LAMBDA(const int64_t i) {
    color(i) = raw ? packRaw8(hdr(i)) : packSrgb8Packed(hdr(i), packed);
  });
}

}  // namespace rast
