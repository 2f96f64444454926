// Post-processing over whole frames: accumulation of supersampled passes in
// linear light and their resolve (SSAA and the reference mode).
#include "stages.h"
#include "texture_sampling.h"

namespace rast {

void accumulateColor(const DeviceScene& s, FrameBuffers& f, bool raw, bool first) {
  const int64_t n = int64_t(f.vp.width) * f.vp.height;
  ensureCapacity(f.accum, "frame.accum", size_t(n));
  auto color = f.color;
  auto accum = f.accum;
  auto lut = s.srgbToLinear;
  Kokkos::parallel_for("rast::post::accumulate", Range(0, n), KOKKOS_LAMBDA(const int64_t i) {
    const uint32_t c = color(i);
    const float4 v = raw ? float4{(c & 0xff) / 255.0f, ((c >> 8) & 0xff) / 255.0f, ((c >> 16) & 0xff) / 255.0f, 1.0f}
                         : float4{lut(c & 0xff), lut((c >> 8) & 0xff), lut((c >> 16) & 0xff), (c >> 24) / 255.0f};
    accum(i) = first ? v : accum(i) + v;
  });
}

void resolveAccumulated(const DeviceScene& s, FrameBuffers& f, int passes, bool raw) {
  const int64_t n = int64_t(f.vp.width) * f.vp.height;
  auto color = f.color;
  auto accum = f.accum;
  auto enc = s.srgbEncode;
  const float inv = 1.0f / float(passes);
  Kokkos::parallel_for("rast::post::resolve", Range(0, n), KOKKOS_LAMBDA(const int64_t i) {
    const float4 v = accum(i) * inv;
    if (raw)
      color(i) = uint32_t(clamp01(v.x) * 255.0f + 0.5f) | uint32_t(clamp01(v.y) * 255.0f + 0.5f) << 8 |
                 uint32_t(clamp01(v.z) * 255.0f + 0.5f) << 16 | 0xff000000u;
    else
      color(i) = encodeSrgb8(v.x, enc) | encodeSrgb8(v.y, enc) << 8 | encodeSrgb8(v.z, enc) << 16 |
                 uint32_t(clamp01(v.w) * 255.0f + 0.5f) << 24;
  });
}

}  // namespace rast
