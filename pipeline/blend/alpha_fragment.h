// What the MASK and BLEND passes share (docs/transparency.md): a fragment's
// alpha (baseColorFactor.a x baseColorTexture.a x COLOR_0.a, clamped to
// [0, 1], NaN as 0), and the walk over the work items of one alpha class: the
// 8x8 blocks of the boxes of its raster triangles (marked by the setup,
// markAlphaClass), found by a binary search over each triangle's first item,
// so that a few large layers spread over the whole machine as well as many
// small triangles do. Every sample a triangle covers is visited once, with
// the exact edge values and depth the raster methods use.
#pragma once

#include "backends/flatten.h"
#include "pipeline/data/device_scene.h"
#include "pipeline/data/frame_buffers.h"
#include "pipeline/rules/alpha_items.h"
#include "pipeline/rules/raster_rules.h"
#include "pipeline/shade/texture_sampling.h"
#include "host/settings/render_settings.h"

namespace rast {
namespace blending {

constexpr int32_t kItemShift = kBlendBlockShift;  // work items are 8x8 pixel blocks

// glTF's alpha, made total: [0, 1], NaN as 0 (the fragment is then dropped).
KOKKOS_INLINE_FUNCTION float cleanAlpha(float a) { return a > 0.0f ? (a < 1.0f ? a : 1.0f) : 0.0f; }

// The per-triangle part of a fragment's alpha.
struct AlphaTri {
  uint32_t index = ~0u;
  float invArea = 0.0f, invW[3] = {0.0f, 0.0f, 0.0f}, corner[3][2] = {{0.0f, 0.0f}, {0.0f, 0.0f}, {0.0f, 0.0f}};
  float alpha = 1.0f;  // baseColorFactor.a
  float cutoff = 0.5f;
  uint32_t draw = 0;
  int32_t textured = 0;
  TextureGPU tex{};
  float2 uv[3] = {{0.0f, 0.0f}, {0.0f, 0.0f}, {0.0f, 0.0f}};
  float colA[3] = {1.0f, 1.0f, 1.0f};
};

struct AlphaScene {
  DView<RasterTri> tris;
  DView<DrawGPU> draws;
  DView<uint32_t> drawTriStart, indices;
  DView<DrawIndex> triDraw;
  DView<float2> uvs;
  DView<float4> colors;
  DView<MaterialGPU> materials;
  DView<TextureGPU> textures;
  DView<uint32_t> texels;
  DView<float> lut;
  DView<AlphaDraw> alphaDraws;
  uint32_t numDraws = 0;
  int32_t hasUV = 0, hasColor = 0, perspective = 1, nearest = 0;  // nearest: 0 bilinear, 1 nearest, 2 per sampler

  RAST_GPU_INLINE void prepare(uint32_t index, AlphaTri& a) const {
    a.index = index;
    const RasterTri& t = tris(index);
    a.invArea = t.invArea;
    for (int k = 0; k < 3; ++k) {
      a.invW[k] = t.invW[k];
      a.corner[k][0] = t.bary[k][0];
      a.corner[k][1] = t.bary[k][1];
    }
    a.draw = drawOf(triDraw, drawTriStart, numDraws, t.prim);
    const DrawGPU& dr = draws(a.draw);
    a.cutoff = alphaDraws(a.draw).cutoff;
    const uint32_t base = 3 * (dr.srcTri + (t.prim - dr.dstTri));
    const uint32_t s[3] = {dr.srcVertex + indices(base), dr.srcVertex + indices(base + 1), dr.srcVertex + indices(base + 2)};
    a.alpha = 1.0f;
    a.textured = 0;
    if (dr.material >= 0) {
      const MaterialGPU m = materials(dr.material);
      a.alpha = m.baseColor.w;
      if (m.texture >= 0 && hasUV) {
        a.textured = 1;
        a.tex = textures(m.texture);
        for (int k = 0; k < 3; ++k) a.uv[k] = uvs(s[k]);
      }
    }
    for (int k = 0; k < 3; ++k) a.colA[k] = hasColor ? colors(s[k]).w : 1.0f;
  }

  // The alpha at a point whose exact edge values are E0, E1, E2: the shade
  // stage's perspective-correct barycentrics (drawnBarycentrics, one function
  // for both), the texture sampled nearest or bilinear (level 0): as --filter
  // says, or under --filter auto (nearest == 2) as the texture's glTF sampler
  // magnifies (a MASK texture filtered nearest cuts along its texels).
  // (A material's constant alpha skips the barycentrics: the BLEND resolve
  // takes a fragment's alpha as often as its colour.)
  KOKKOS_INLINE_FUNCTION float alphaAt(const AlphaTri& a, int64_t E0, int64_t E1, int64_t E2) const {
    float alpha = a.alpha;
    if (!a.textured && !hasColor) return cleanAlpha(alpha);
    float b1, b2;
    drawnBarycentrics(E0, E1, E2, a.invArea, a.invW, a.corner, perspective != 0, b1, b2);
    return alphaFrom(a, 1.0f - b1 - b2, b1, b2);
  }
  // The same from the barycentrics (b0 = 1 - b1 - b2, as above): the BLEND
  // resolve's specialised shading (frag_shade.h) has them already, the same
  // bits (the triangle's terms and the perspective flag are the shade stage's).
  RAST_GPU_INLINE float alphaFrom(const AlphaTri& a, float b0, float b1, float b2) const {
    float alpha = a.alpha;
    if (!a.textured && !hasColor) return cleanAlpha(alpha);
    if (a.textured) {
      const float u = a.uv[0].x * b0 + a.uv[1].x * b1 + a.uv[2].x * b2;
      const float v = a.uv[0].y * b0 + a.uv[1].y * b1 + a.uv[2].y * b2;
      const bool nn = nearest == 2 ? a.tex.magFilter == 9728 : nearest != 0;
      alpha *= (nn ? sampleNearest(a.tex, texels, lut, u, v) : sampleBilinear(a.tex, texels, lut, u, v)).w;
    }
    if (hasColor) alpha *= a.colA[0] * b0 + a.colA[1] * b1 + a.colA[2] * b2;
    return cleanAlpha(alpha);
  }

  // Alpha-to-coverage (MASK under MSAA): the share of pixel (X, Y)'s samples
  // that triangle t keeps, from the alpha at the pixel's centre, sharpened so
  // that it goes from 0 to 1 over one pixel around the cutoff (the alpha's
  // change one pixel right plus one pixel up sets the width; points outside
  // the triangle extrapolate its plane): the cut-out edge lands where the
  // cutoff puts it, anti-aliased, and an alpha that does not change across the
  // pixel keeps all or none.
  KOKKOS_INLINE_FUNCTION float coverageAt(const AlphaTri& a, const RasterTri& t, int32_t X, int32_t Y) const {
    const Edges e(t);
    const int64_t c0 = e.eval(0, X, Y), c1 = e.eval(1, X, Y), c2 = e.eval(2, X, Y);
    const float al = alphaAt(a, c0, c1, c2);
    const float ax = alphaAt(a, e.atSample(0, c0, kSubOne, 0), e.atSample(1, c1, kSubOne, 0), e.atSample(2, c2, kSubOne, 0));
    const float ay = alphaAt(a, e.atSample(0, c0, 0, kSubOne), e.atSample(1, c1, 0, kSubOne), e.atSample(2, c2, 0, kSubOne));
    const float w = ::fabsf(ax - al) + ::fabsf(ay - al);
    if (!(w > 1e-6f)) return al >= a.cutoff ? 1.0f : 0.0f;
    const float c = (al - a.cutoff) / w + 0.5f;
    return c > 0.0f ? (c < 1.0f ? c : 1.0f) : 0.0f;
  }
};

// Alpha-to-coverage's threshold for sample s of `count` at pixel (X, Y): the
// sample's rank, rotated by the pixel's place in a 4x4 ordered (Bayer)
// pattern, as a fraction: a coverage c keeps the samples whose threshold is
// below c, about c x count of them, a different choice of samples from pixel
// to pixel (a dither, integer arithmetic: the same on every backend).
KOKKOS_INLINE_FUNCTION float coverageThreshold(int s, int count, int32_t X, int32_t Y) {
  const uint32_t x = uint32_t(X) & 3u, y = uint32_t(Y) & 3u, d = x ^ y;
  const uint32_t bayer = (d & 1u) << 3 | (y & 1u) << 2 | (d >> 1) << 1 | y >> 1;  // 0..15, each once a 4x4 tile
  const int rank = int((uint32_t(s) + bayer) % uint32_t(count));
  return (float(rank) + 0.5f) / float(count);
}

AlphaScene makeAlphaScene(const DeviceScene& s, const FrameBuffers& f, TexFilter filter, bool perspective);

// Raster triangle owning work item w: the last i < n with start(i) <= w
// (triangles of other classes own no item and share the next one's start).
KOKKOS_INLINE_FUNCTION uint32_t itemOwner(const DView<uint64_t>& start, uint32_t n, uint64_t w) {
  uint32_t lo = 0, hi = n;
  while (hi - lo > 1) {
    const uint32_t mid = lo + (hi - lo) / 2;
    if (start(mid) <= w) lo = mid; else hi = mid;
  }
  return lo;
}

// Visits every sample that raster triangle `index` covers in work item
// `local` of its box: op(sample, X, Y, s, E0, E1, E2, depth), sample being
// the index into per-sample buffers (pixel * samples + s).
template <class Op>
KOKKOS_INLINE_FUNCTION void forItemSamples(const RasterTri& t, const Viewport& vp, uint32_t local, Op&& op) {
  const ItemBox b = itemBox(t, vp);
  const int32_t bx = b.bx0 + int32_t(local % uint32_t(b.bw)), by = b.by0 + int32_t(local / uint32_t(b.bw));
  const int32_t x0 = b.minX > (bx << kItemShift) ? b.minX : (bx << kItemShift);
  const int32_t x1 = b.maxX < ((bx + 1) << kItemShift) - 1 ? b.maxX : ((bx + 1) << kItemShift) - 1;
  const int32_t y0 = b.minY > (by << kItemShift) ? b.minY : (by << kItemShift);
  const int32_t y1 = b.maxY < ((by + 1) << kItemShift) - 1 ? b.maxY : ((by + 1) << kItemShift) - 1;
  const Edges e(t);
  const DepthTerms dz(t);
  const SamplePattern& sp = vp.samples;
  for (int32_t y = y0; y <= y1; ++y)
    for (int32_t x = x0; x <= x1; ++x) {
      const int64_t c0 = e.eval(0, x, y), c1 = e.eval(1, x, y), c2 = e.eval(2, x, y);
      for (int s = 0; s < sp.count; ++s) {
        const int64_t s0 = e.atSample(0, c0, sp.ox[s], sp.oy[s]), s1 = e.atSample(1, c1, sp.ox[s], sp.oy[s]),
                      s2 = e.atSample(2, c2, sp.ox[s], sp.oy[s]);
        if (!e.inside(s0, s1, s2)) continue;
        op((int64_t(y) * vp.width + x) * sp.count + s, x, y, s, s0, s1, s2, dz.at(s0, s2));
      }
    }
}

}  // namespace blending
}  // namespace rast
