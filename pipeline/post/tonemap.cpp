// Tone mapping of the film in place (alpha untouched).
#include "pipeline/post/tonemap.h"

#include "pipeline/post/chain.h"

namespace rast {

void postToneMap(PostBuffers& b, const PostView& v, const PostSettings& s) {
  auto hdr = b.hdr;
  const int curve = int(s.tonemap);
  Kokkos::parallel_for("rast::post::tonemap", Range(0, int64_t(v.width) * v.height), KOKKOS_LAMBDA(const int64_t i) {
    const float4 c = hdr(i);
    if (curve == int(ToneMap::Aces)) {
      hdr(i) = float4{toneAces(c.x), toneAces(c.y), toneAces(c.z), c.w};
    } else if (curve == int(ToneMap::Neutral)) {
      const float3 t = tonePbrNeutral(float3{c.x, c.y, c.z});
      hdr(i) = float4{t.x, t.y, t.z, c.w};
    } else {
      hdr(i) = float4{toneReinhard(c.x), toneReinhard(c.y), toneReinhard(c.z), c.w};
    }
  });
}

}  // namespace rast
