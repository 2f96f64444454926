// Tone mapping of the film in place (alpha untouched).
#include "pipeline/post/tonemap.h"

#include "pipeline/post/chain.h"

namespace rast {

void postToneMap(PostBuffers& b, const PostView& v, const PostSettings& s) {
  auto hdr = b.hdr;
  const int aces = s.tonemap == ToneMap::Aces ? 1 : 0;
  Kokkos::parallel_for("rast::post::tonemap", Range(0, int64_t(v.width) * v.height), KOKKOS_LAMBDA(const int64_t i) {
    const float4 c = hdr(i);
    hdr(i) = aces ? float4{toneAces(c.x), toneAces(c.y), toneAces(c.z), c.w}
                  : float4{toneReinhard(c.x), toneReinhard(c.y), toneReinhard(c.z), c.w};
  });
}

}  // namespace rast
