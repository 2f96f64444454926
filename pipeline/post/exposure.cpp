// Exposure: linear colour times 2^EV (alpha untouched).
#include "pipeline/post/chain.h"

#include <cmath>

namespace rast {

void postExposure(PostBuffers& b, const PostView& v, const PostSettings& s) {
  const float scale = float(std::exp2(double(s.exposure)));
  auto hdr = b.hdr;
  Kokkos::parallel_for("rast::post::exposure", Range(0, int64_t(v.width) * v.height), KOKKOS_LAMBDA(const int64_t i) {
    const float4 c = hdr(i);
    hdr(i) = float4{c.x * scale, c.y * scale, c.z * scale, c.w};
  });
}

}  // namespace rast
