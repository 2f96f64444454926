#include "pipeline/post/chain.h"

#include "backends/stage_timer.h"

namespace rast {
namespace {

// Order: occlusion darkens the shaded light; exposure scales it; bloom picks
// what is bright after exposure; tone mapping compresses the result last.
const PostPass kPasses[] = {
    {"ssao", [](const PostSettings& s) { return s.ssao; }, postSsao},
    {"exposure", [](const PostSettings& s) { return s.exposure != 0.0f; }, postExposure},
    {"bloom", [](const PostSettings& s) { return s.bloom; }, postBloom},
    {"tonemap", [](const PostSettings& s) { return s.tonemap != ToneMap::None; }, postToneMap},
};

}  // namespace

const PostPass* postPasses(int& count) {
  count = int(sizeof(kPasses) / sizeof(kPasses[0]));
  return kPasses;
}

void runPostChain(PostBuffers& b, const PostView& v, const PostSettings& s, const DView<uint32_t>& color,
                  const DView<uint32_t>& packed, bool raw, StageTimer* timer, bool straight) {
  for (const PostPass& p : kPasses) {
    if (!p.enabled(s)) continue;
    Kokkos::Profiling::pushRegion(std::string("rast::post::") + p.name);
    p.run(b, v, s);
    Kokkos::Profiling::popRegion();
    if (timer) timer->mark(p.name);
  }
  postEncode(b.hdr, int64_t(v.width) * v.height, color, packed, raw, straight);
  if (timer) timer->mark("encode");
}

}  // namespace rast
