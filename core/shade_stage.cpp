// Fragment shading from the visibility buffer: one work item per pixel
// recomputes the barycentrics of the winning raster triangle at the pixel
// centre, makes them perspective-correct, maps them into the drawn triangle
// (clipping moved the vertices) and interpolates the attributes from there.
#include "raster_common.h"
#include "raster_lines.h"
#include "stages.h"
#include "texture_sampling.h"

namespace rast {
namespace {

struct Shade {
  // scene
  DView<DrawGPU> draws;
  DView<uint32_t> drawTriStart, indices;
  DView<float2> uvs;
  DView<float4> colors;
  DView<MaterialGPU> materials;
  DView<TextureGPU> textures;
  DView<uint32_t> texels;
  DView<float> lut, encode;
  uint32_t numDraws;
  int32_t hasUV, hasColor;
  // frame
  DView<RasterTri> tris;
  DView<uint64_t> vis;
  DView<float3> worldPos, worldNormal;
  DView<uint32_t> color;
  DView<float> depthOut;
  DView<uint32_t> primOut;
  DView<float3> normalOut;
  DView<LightGPU> lights;
  Kokkos::View<Kokkos::MinMaxScalar<float>, Mem> depthRange;  // eye depth of covered pixels (depth mode)
  int32_t width;
  SamplePattern samples;
  ShadeParams p;
  LineShade lineShade;  // fragments of points and lines (raster_lines.h)

  KOKKOS_INLINE_FUNCTION uint32_t pack(float4 c) const {
    return encodeSrgb8(c.x, encode) | encodeSrgb8(c.y, encode) << 8 | encodeSrgb8(c.z, encode) << 16 |
           uint32_t(clamp01(c.w) * 255.0f + 0.5f) << 24;
  }

  KOKKOS_INLINE_FUNCTION float eyeDepth(float d) const {
    const float zn = 2.0f * d - 1.0f;
    return 2.0f * p.znear * p.zfar / ((p.zfar + p.znear) - zn * (p.zfar - p.znear));
  }

  // Barycentrics in the drawn triangle at a point (ox, oy) (1/256 pixel) from
  // the centre of pixel (X, Y): screen-space weights from the exact edge values,
  // made perspective-correct (attributes vary linearly in clip space, i.e. with
  // weight l_k / w_k), then mapped through the raster triangle's vertices
  // (clipping moved them). Points outside the triangle extrapolate the plane,
  // which is what the derivatives need.
  KOKKOS_INLINE_FUNCTION void bary(const RasterTri& t, const Edges& e, int32_t X, int32_t Y, int32_t ox, int32_t oy,
                                   float& b0, float& b1, float& b2) const {
    const float l0 = float(e.atSample(1, e.eval(1, X, Y), ox, oy)) * t.invArea;
    const float l1 = float(e.atSample(2, e.eval(2, X, Y), ox, oy)) * t.invArea;
    const float l2 = float(e.atSample(0, e.eval(0, X, Y), ox, oy)) * t.invArea;
    float w0 = l0, w1 = l1, w2 = l2;
    if (p.perspective) {
      w0 *= t.invW[0];
      w1 *= t.invW[1];
      w2 *= t.invW[2];
    }
    const float sum = w0 + w1 + w2;
    if (sum != 0.0f && isFinite(sum)) {
      const float inv = 1.0f / sum;
      w0 *= inv; w1 *= inv; w2 *= inv;
    } else {
      w0 = w1 = w2 = 1.0f / 3.0f;
    }
    b1 = w0 * t.bary[0][0] + w1 * t.bary[1][0] + w2 * t.bary[2][0];
    b2 = w0 * t.bary[0][1] + w1 * t.bary[1][1] + w2 * t.bary[2][1];
    b0 = 1.0f - b1 - b2;
  }

  KOKKOS_INLINE_FUNCTION float2 uvAt(uint32_t s0, uint32_t s1, uint32_t s2, float b0, float b1, float b2) const {
    return {uvs(s0).x * b0 + uvs(s1).x * b1 + uvs(s2).x * b2, uvs(s0).y * b0 + uvs(s1).y * b1 + uvs(s2).y * b2};
  }

  // Colour of raster triangle `index` at a sample of pixel (X, Y), for display:
  // linear light for the lit and depth modes (sRGB-encoded later), raw values
  // for the diagnostic modes (normals, uv, mip level).
  KOKKOS_INLINE_FUNCTION float4 shadeFragment(uint32_t index, int32_t X, int32_t Y, int32_t ox, int32_t oy, float depth,
                                              float3* normalOutV) const {
    const RasterTri& t = tris(index & kLineFlag ? 0 : index);
    if (p.mode == ShadingMode::Depth) {
      const float lo = depthRange().min_val, hi = depthRange().max_val;
      const float g = hi > lo ? 1.0f - (eyeDepth(depth) - lo) / (hi - lo) : 1.0f;
      return float4{g, g, g, 1.0f};
    }
    if (index & kLineFlag) return lineShade.color(index & ~kLineFlag);
    const Edges e(t);
    float b0, b1, b2;
    bary(t, e, X, Y, ox, oy, b0, b1, b2);
    const uint32_t d = findRange(drawTriStart, numDraws, t.prim);
    const DrawGPU& dr = draws(d);
    const uint32_t base = 3 * (dr.srcTri + (t.prim - dr.dstTri));
    const uint32_t i0 = indices(base), i1 = indices(base + 1), i2 = indices(base + 2);
    const uint32_t s0 = dr.srcVertex + i0, s1 = dr.srcVertex + i1, s2 = dr.srcVertex + i2;

    if (p.mode == ShadingMode::TexCoord) {
      // Texture coordinates as raw red/green (fractional part); black without any.
      if (!hasUV) return float4{0.0f, 0.0f, 0.0f, 1.0f};
      const float2 uv = uvAt(s0, s1, s2, b0, b1, b2);
      return float4{uv.x - ::floorf(uv.x), uv.y - ::floorf(uv.y), 0.0f, 1.0f};
    }

    const uint32_t v0 = dr.dstVertex + i0, v1 = dr.dstVertex + i1, v2 = dr.dstVertex + i2;
    const float3 N = normalize(worldNormal(v0) * b0 + worldNormal(v1) * b1 + worldNormal(v2) * b2);
    const float3 P = worldPos(v0) * b0 + worldPos(v1) * b1 + worldPos(v2) * b2;
    if (normalOutV) *normalOutV = N;
    if (p.mode == ShadingMode::Normals)  // encoded directly (no sRGB curve), as normal maps are
      return float4{N.x * 0.5f + 0.5f, N.y * 0.5f + 0.5f, N.z * 0.5f + 0.5f, 1.0f};

    float4 base4{1.0f, 1.0f, 1.0f, 1.0f};
    float lod = 0.0f;
    if (dr.material >= 0) {
      const MaterialGPU m = materials(dr.material);
      base4 = m.baseColor;
      if (m.texture >= 0 && hasUV) {
        const float2 uv = uvAt(s0, s1, s2, b0, b1, b2);
        const TextureGPU tex = textures(m.texture);
        float4 tc;
        if (p.filter == TexFilter::Trilinear || p.mode == ShadingMode::MipLevel) {
          // Analytic derivatives: the same plane one pixel to the right and up.
          float c0, c1, c2;
          bary(t, e, X, Y, ox + kSubOne, oy, c0, c1, c2);
          const float2 ux = uvAt(s0, s1, s2, c0, c1, c2);
          bary(t, e, X, Y, ox, oy + kSubOne, c0, c1, c2);
          const float2 uy = uvAt(s0, s1, s2, c0, c1, c2);
          lod = textureLod(ux.x - uv.x, ux.y - uv.y, uy.x - uv.x, uy.y - uv.y, tex.width, tex.height);
          tc = sampleTrilinear(tex, texels, lut, uv.x, uv.y, lod);
        } else if (p.filter == TexFilter::Nearest) {
          tc = sampleNearest(tex, texels, lut, uv.x, uv.y);
        } else {
          tc = sampleBilinear(tex, texels, lut, uv.x, uv.y);
        }
        base4 = base4 * tc;
      }
    }
    if (p.mode == ShadingMode::MipLevel) {
      const float l = lod / 8.0f;  // level 0 black, level 8 full red
      return float4{l, 0.0f, 0.0f, 1.0f};
    }
    if (hasColor) base4 = base4 * (colors(s0) * b0 + colors(s1) * b1 + colors(s2) * b2);

    const float3 V = normalize(p.eye - P);
    float diffuse = p.ambient, spec = 0.0f;
    const int nl = p.headlight ? 1 : int(lights.extent(0));
    for (int k = 0; k < nl; ++k) {
      const float3 L = p.headlight ? V : lights(k).direction;
      const float I = p.headlight ? 1.0f - p.ambient : lights(k).intensity;
      const float ndl = dot(N, L);
      diffuse += I * (ndl > 0.0f ? ndl : 0.0f);
      if (p.mode == ShadingMode::BlinnPhong && ndl > 0.0f) {
        const float ndh = dot(N, normalize(L + V));
        spec += I * p.specular * (ndh > 0.0f ? ::powf(ndh, p.shininess) : 0.0f);
      }
    }
    const float3 rgb = float3{base4.x, base4.y, base4.z} * diffuse + float3{spec, spec, spec};
    return float4{rgb.x, rgb.y, rgb.z, base4.w};
  }

  KOKKOS_INLINE_FUNCTION uint32_t display(float4 c) const {
    if (isRawShading(p.mode))
      return uint32_t(clamp01(c.x) * 255.0f + 0.5f) | uint32_t(clamp01(c.y) * 255.0f + 0.5f) << 8 |
             uint32_t(clamp01(c.z) * 255.0f + 0.5f) << 16 | 0xff000000u;
    return pack(c);
  }

  KOKKOS_INLINE_FUNCTION void operator()(const int64_t i) const {
    const int32_t X = int32_t(i % width), Y = int32_t(i / width);
    const int S = samples.count;
    const uint64_t key0 = vis(i * S);
    const uint32_t idx0 = uint32_t(key0 & 0xffffffffu);
    // Outputs: ids and depth of the first sample (as OpenGL resolves integer
    // and depth buffers: one sample).
    if (p.wantDepth) depthOut(i) = bitsFloat(uint32_t(key0 >> 32));
    if (p.wantPrimId)
      primOut(i) = idx0 == 0 ? 0 : (idx0 - 1) & kLineFlag ? lineShade.primId((idx0 - 1) & ~kLineFlag) : tris(idx0 - 1).prim + 1;
    float3 n0{0.0f, 0.0f, 0.0f};
    if (S == 1) {
      color(i) = idx0 ? display(shadeFragment(idx0 - 1, X, Y, 0, 0, bitsFloat(uint32_t(key0 >> 32)), &n0))
                      : p.backgroundPacked;
      if (p.wantNormals) normalOut(i) = n0;
      return;
    }
    // Multisampling: shade once per distinct triangle among the samples, at the
    // centroid of the samples it covers (the pixel centre when it covers them
    // all; never outside the triangle, so attributes are not extrapolated),
    // weight by the samples it covers, and resolve in linear light.
    const bool raw = isRawShading(p.mode);
    float4 acc{0.0f, 0.0f, 0.0f, 0.0f};
    int background = 0;
    for (int s = 0; s < S; ++s) {
      const uint64_t key = vis(i * S + s);
      const uint32_t idx = uint32_t(key & 0xffffffffu);
      if (idx == 0) {
        ++background;
        continue;
      }
      bool seen = false;
      for (int r = 0; r < s; ++r) seen |= uint32_t(vis(i * S + r) & 0xffffffffu) == idx;
      if (seen) continue;
      int count = 1, sx = samples.ox[s], sy = samples.oy[s];
      for (int r = s + 1; r < S; ++r)
        if (uint32_t(vis(i * S + r) & 0xffffffffu) == idx) {
          ++count;
          sx += samples.ox[r];
          sy += samples.oy[r];
        }
      float3 n{0.0f, 0.0f, 0.0f};
      const float4 c = shadeFragment(idx - 1, X, Y, sx / count, sy / count, bitsFloat(uint32_t(key >> 32)), &n);
      if (s == 0) n0 = n;
      acc = acc + c * float(count);
    }
    const float4 bg = raw ? float4{0.0f, 0.0f, 0.0f, 1.0f} : p.background;
    acc = (acc + bg * float(background)) * (1.0f / float(S));
    color(i) = display(acc);
    if (p.wantNormals) normalOut(i) = n0;
  }
};

// Eye-space depth range of the covered pixels, reduced on the device (depth mode).
struct DepthRange {
  DView<uint64_t> vis;
  float znear, zfar;
  int samples;
  KOKKOS_INLINE_FUNCTION void operator()(const int64_t i, Kokkos::MinMaxScalar<float>& v) const {
    const uint64_t key = vis(i * samples);
    if ((key & 0xffffffffu) == 0) return;
    const float zn = 2.0f * bitsFloat(uint32_t(key >> 32)) - 1.0f;
    const float ze = 2.0f * znear * zfar / ((zfar + znear) - zn * (zfar - znear));
    v.min_val = ze < v.min_val ? ze : v.min_val;
    v.max_val = ze > v.max_val ? ze : v.max_val;
  }
};

}  // namespace

void shadeStage(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights) {
  const int64_t n = int64_t(f.vp.width) * f.vp.height;
  ensureCapacity(f.color, "frame.color", size_t(n));
  if (p.wantDepth) ensureCapacity(f.depth, "frame.depth", size_t(n));
  if (p.wantPrimId) ensureCapacity(f.primId, "frame.primId", size_t(n));
  if (p.wantNormals) ensureCapacity(f.normal, "frame.normal", size_t(n));
  if (p.mode == ShadingMode::Depth) {
    if (!f.depthRange.data()) f.depthRange = decltype(f.depthRange)("frame.depthRange");
    Kokkos::parallel_reduce("rast::shade::depth_range", Range(0, n), DepthRange{f.vis, p.znear, p.zfar, f.vp.samples.count},
                            Kokkos::MinMax<float, Mem>(f.depthRange));
  }
  Shade k{s.draws, s.drawTriStart, s.indices, s.uvs, s.colors, s.materials, s.textures, s.texels, s.srgbToLinear, s.srgbEncode,
          s.numDraws, s.hasUV ? 1 : 0, s.hasColor ? 1 : 0, f.tris, f.vis, f.worldPos, f.worldNormal, f.color,
          f.depth, f.primId, f.normal, lights, f.depthRange, f.vp.width, f.vp.samples, p, makeLineShade(s, f.lines)};
  Kokkos::parallel_for("rast::shade", lightweight(Range(0, n)), k);
}

}  // namespace rast
