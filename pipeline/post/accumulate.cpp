// Supersampling over whole frames: each pass's float film accumulated in
// linear light, and the average put back in the film (SSAA and the reference
// mode). The post chain then runs on the average and encodes it once.
#include "pipeline/post/accumulate.h"

namespace rast {

void accumulateColor(FrameBuffers& f, bool first) {
  const int64_t n = int64_t(f.vp.width) * f.vp.height;
  ensureCapacity(f.accum, "frame.accum", size_t(n));
  auto hdr = f.post.hdr;
  auto accum = f.accum;
  Kokkos::parallel_for("rast::post::accumulate", Range(0, n), KOKKOS_LAMBDA(const int64_t i) {
    accum(i) = first ? hdr(i) : accum(i) + hdr(i);
  });
}

void resolveAccumulated(FrameBuffers& f, int passes) {
  const int64_t n = int64_t(f.vp.width) * f.vp.height;
  auto hdr = f.post.hdr;
  auto accum = f.accum;
  const float inv = 1.0f / float(passes);
  Kokkos::parallel_for("rast::post::resolve", Range(0, n), KOKKOS_LAMBDA(const int64_t i) { hdr(i) = accum(i) * inv; });
}

}  // namespace rast
