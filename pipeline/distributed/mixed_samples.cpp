// Mixed MSAA pixels of a sort-last frame (sort_last.h): pixels whose samples
// were won by triangles of several ranks. A single device shades such a pixel
// once per distinct triangle among its samples and sums colour x samples in
// the order of each triangle's first sample (shade_fragment.h, shadePixel);
// here each owner shades its triangles of the pixel the same way into the
// slot of that first sample, and rank 0 sums the merged slots in sample
// order, adds the background's share and resolves: the same operations in the
// same order, so the same bits. Compiled with the shade stage's flags
// (CMakeLists.txt) so that the fragment maths round the same way.
#include "pipeline/distributed/sort_last.h"

#include "pipeline/shade/shade_fragment.h"

namespace rast {

uint32_t countMixed(const DView<uint8_t>& flag, MixedSamples& m, size_t pixels) {
  ensureCapacity(m.at, "composite.mixedAt", pixels);
  const DView<uint32_t> at = m.at;
  uint32_t total = 0;
  Kokkos::parallel_scan(
      "rast::composite::mixed_index", Range(0, int64_t(pixels)),
      KOKKOS_LAMBDA(const int64_t i, uint32_t& sum, const bool final) {
        if (final) at(i) = sum;
        sum += flag(i) == 2 ? 1u : 0u;
      },
      total);
  m.pixels = total;
  return total;
}

void shadeMixed(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights,
                const DView<uint8_t>& flag, MixedSamples& m) {
  const int S = f.vp.samples.count;
  const size_t slots = size_t(m.pixels) * size_t(S);
  ensureCapacity(m.colour, "composite.mixedColour", slots);
  ensureCapacity(m.count, "composite.mixedCount", slots);
  const shading::Shade k = makeShade(s, f, p, lights);
  const DView<uint32_t> at = m.at, count = m.count;
  const DView<float4> colour = m.colour;
  const DView<uint64_t> vis = f.vis;
  const int32_t width = f.vp.width;
  const int64_t n = int64_t(f.vp.width) * f.vp.height;
  Kokkos::parallel_for("rast::composite::mixed_shade", Range(0, n), KOKKOS_LAMBDA(const int64_t i) {
    if (flag(i) != 2) return;
    const size_t base = size_t(at(i)) * size_t(S);
    const int32_t X = int32_t(i % width), Y = int32_t(i / width);
    for (int q = 0; q < S; ++q) {
      colour(base + q) = float4{0.0f, 0.0f, 0.0f, 0.0f};
      count(base + q) = 0;
    }
    shading::TriFrag fr;
    // This rank's keys hold only the samples it won (the rest are clear).
    for (int q = 0; q < S; ++q) {
      const uint64_t key = vis(i * S + q);
      const uint32_t idx = uint32_t(key & 0xffffffffu);
      if (idx == 0) continue;
      bool seen = false;
      for (int r = 0; r < q; ++r) seen |= uint32_t(vis(i * S + r) & 0xffffffffu) == idx;
      if (seen) continue;
      int cnt = 1, sx = k.samples.ox[q], sy = k.samples.oy[q];
      for (int r = q + 1; r < S; ++r)
        if (uint32_t(vis(i * S + r) & 0xffffffffu) == idx) {
          ++cnt;
          sx += k.samples.ox[r];
          sy += k.samples.oy[r];
        }
      float3 nn{0.0f, 0.0f, 0.0f}, pp{0.0f, 0.0f, 0.0f};
      k.use(idx - 1, fr);
      colour(base + q) = k.shadeFragment(fr, X, Y, sx / cnt, sy / cnt, bitsFloat(uint32_t(key >> 32)), &nn, &pp);
      count(base + q) = uint32_t(cnt);
    }
  });
}

void resolveMixed(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights,
                  const DView<uint8_t>& flag, const DView<uint64_t>& global, MixedSamples& m) {
  const int S = f.vp.samples.count;
  const shading::Shade k = makeShade(s, f, p, lights);
  const DView<uint32_t> at = m.at, count = m.count, color = f.color;
  const DView<float4> colour = m.colour, hdr = f.post.hdr;
  const int64_t n = int64_t(f.vp.width) * f.vp.height;
  const bool raw = isRawShading(p.mode);
  const float4 bg = raw ? float4{0.0f, 0.0f, 0.0f, 1.0f} : p.background;
  const int floatOut = p.floatOut;
  Kokkos::parallel_for("rast::composite::mixed_resolve", Range(0, n), KOKKOS_LAMBDA(const int64_t i) {
    if (flag(i) != 2) return;
    const size_t base = size_t(at(i)) * size_t(S);
    float4 acc{0.0f, 0.0f, 0.0f, 0.0f};
    int background = 0;
    for (int q = 0; q < S; ++q) {
      if ((global(i * S + q) & 0xffffffffu) == 0) ++background;
      const uint32_t c = count(base + q);
      if (c) acc = acc + colour(base + q) * float(c);
    }
    acc = (acc + bg * float(background)) * (1.0f / float(S));
    if (floatOut) hdr(i) = acc;
    else color(i) = k.display(acc);
  });
}

}  // namespace rast
