// Fragment shading from the visibility buffer: one work item per pixel
// recomputes the barycentrics of the winning raster triangle at the pixel
// centre, makes them perspective-correct, maps them into the drawn triangle
// (clipping moved the vertices) and interpolates the attributes from there.
#include "raster_common.h"
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
  ShadeParams p;

  KOKKOS_INLINE_FUNCTION uint32_t pack(float4 c) const {
    return encodeSrgb8(c.x, encode) | encodeSrgb8(c.y, encode) << 8 | encodeSrgb8(c.z, encode) << 16 |
           uint32_t(clamp01(c.w) * 255.0f + 0.5f) << 24;
  }

  KOKKOS_INLINE_FUNCTION float eyeDepth(float d) const {
    const float zn = 2.0f * d - 1.0f;
    return 2.0f * p.znear * p.zfar / ((p.zfar + p.znear) - zn * (p.zfar - p.znear));
  }

  KOKKOS_INLINE_FUNCTION void operator()(const int64_t i) const {
    const uint64_t key = vis(i);
    const uint32_t idx = uint32_t(key & 0xffffffffu);
    if (idx == 0) {
      color(i) = p.backgroundPacked;
      if (p.wantDepth) depthOut(i) = 1.0f;
      if (p.wantPrimId) primOut(i) = 0;
      if (p.wantNormals) normalOut(i) = float3{0.0f, 0.0f, 0.0f};
      return;
    }
    const RasterTri& t = tris(idx - 1);
    const float depth = bitsFloat(uint32_t(key >> 32));
    if (p.wantDepth) depthOut(i) = depth;
    if (p.wantPrimId) primOut(i) = t.prim + 1;

    // Screen-space weights at the pixel centre, then perspective correction:
    // attributes vary linearly in clip space, i.e. with weight l_k / w_k.
    const int32_t X = int32_t(i % width), Y = int32_t(i / width);
    const Edges e(t);
    const float l0 = float(e.eval(1, X, Y)) * t.invArea;
    const float l1 = float(e.eval(2, X, Y)) * t.invArea;
    const float l2 = float(e.eval(0, X, Y)) * t.invArea;
    float w0 = l0 * t.invW[0], w1 = l1 * t.invW[1], w2 = l2 * t.invW[2];
    const float sum = w0 + w1 + w2;
    if (sum > 0.0f) {
      const float inv = 1.0f / sum;
      w0 *= inv; w1 *= inv; w2 *= inv;
    } else {
      w0 = w1 = w2 = 1.0f / 3.0f;
    }
    const float b1 = w0 * t.bary[0][0] + w1 * t.bary[1][0] + w2 * t.bary[2][0];
    const float b2 = w0 * t.bary[0][1] + w1 * t.bary[1][1] + w2 * t.bary[2][1];
    const float b0 = 1.0f - b1 - b2;

    const uint32_t d = findRange(drawTriStart, numDraws, t.prim);
    const DrawGPU& dr = draws(d);
    const uint32_t base = 3 * (dr.srcTri + (t.prim - dr.dstTri));
    const uint32_t i0 = indices(base), i1 = indices(base + 1), i2 = indices(base + 2);

    if (p.mode == ShadingMode::Depth) {
      const float lo = depthRange().min_val, hi = depthRange().max_val;
      const float g = hi > lo ? 1.0f - (eyeDepth(depth) - lo) / (hi - lo) : 1.0f;
      color(i) = pack(float4{g, g, g, 1.0f});
      return;
    }

    if (p.mode == ShadingMode::TexCoord) {
      // Texture coordinates as raw red/green bytes (fractional part), for
      // inspecting interpolation; black where the scene has none.
      float u = 0.0f, v = 0.0f;
      if (hasUV) {
        const uint32_t s0 = dr.srcVertex + i0, s1 = dr.srcVertex + i1, s2 = dr.srcVertex + i2;
        u = uvs(s0).x * b0 + uvs(s1).x * b1 + uvs(s2).x * b2;
        v = uvs(s0).y * b0 + uvs(s1).y * b1 + uvs(s2).y * b2;
        u -= ::floorf(u);
        v -= ::floorf(v);
      }
      color(i) = uint32_t(clamp01(u) * 255.0f + 0.5f) | uint32_t(clamp01(v) * 255.0f + 0.5f) << 8 | 0xff000000u;
      return;
    }

    const bool needN = true;
    float3 N{0.0f, 0.0f, 0.0f}, P{0.0f, 0.0f, 0.0f};
    if (needN) {
      const uint32_t v0 = dr.dstVertex + i0, v1 = dr.dstVertex + i1, v2 = dr.dstVertex + i2;
      N = normalize(worldNormal(v0) * b0 + worldNormal(v1) * b1 + worldNormal(v2) * b2);
      P = worldPos(v0) * b0 + worldPos(v1) * b1 + worldPos(v2) * b2;
    }
    if (p.wantNormals) normalOut(i) = N;
    if (p.mode == ShadingMode::Normals) {
      // Encoded directly (no sRGB curve), as normal maps are.
      const uint32_t r = uint32_t(clamp01(N.x * 0.5f + 0.5f) * 255.0f + 0.5f);
      const uint32_t g = uint32_t(clamp01(N.y * 0.5f + 0.5f) * 255.0f + 0.5f);
      const uint32_t b = uint32_t(clamp01(N.z * 0.5f + 0.5f) * 255.0f + 0.5f);
      color(i) = r | g << 8 | b << 16 | 0xff000000u;
      return;
    }

    float4 base4{1.0f, 1.0f, 1.0f, 1.0f};
    if (dr.material >= 0) {
      const MaterialGPU m = materials(dr.material);
      base4 = m.baseColor;
      if (m.texture >= 0 && hasUV) {
        const uint32_t s0 = dr.srcVertex + i0, s1 = dr.srcVertex + i1, s2 = dr.srcVertex + i2;
        const float u = uvs(s0).x * b0 + uvs(s1).x * b1 + uvs(s2).x * b2;
        const float v = uvs(s0).y * b0 + uvs(s1).y * b1 + uvs(s2).y * b2;
        const TextureGPU tex = textures(m.texture);
        const float4 tc = p.filter == TexFilter::Nearest ? sampleNearest(tex, texels, lut, u, v)
                                                         : sampleBilinear(tex, texels, lut, u, v);
        base4 = base4 * tc;
      }
    }
    if (hasColor) {
      const uint32_t s0 = dr.srcVertex + i0, s1 = dr.srcVertex + i1, s2 = dr.srcVertex + i2;
      base4 = base4 * (colors(s0) * b0 + colors(s1) * b1 + colors(s2) * b2);
    }

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
    color(i) = pack(float4{rgb.x, rgb.y, rgb.z, base4.w});
  }
};

// Eye-space depth range of the covered pixels, reduced on the device (depth mode).
struct DepthRange {
  DView<uint64_t> vis;
  float znear, zfar;
  KOKKOS_INLINE_FUNCTION void operator()(const int64_t i, Kokkos::MinMaxScalar<float>& v) const {
    const uint64_t key = vis(i);
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
    Kokkos::parallel_reduce("rast::shade::depth_range", Range(0, n), DepthRange{f.vis, p.znear, p.zfar},
                            Kokkos::MinMax<float, Mem>(f.depthRange));
  }
  Shade k{s.draws, s.drawTriStart, s.indices, s.uvs, s.colors, s.materials, s.textures, s.texels, s.srgbToLinear, s.srgbEncode,
          s.numDraws, s.hasUV ? 1 : 0, s.hasColor ? 1 : 0, f.tris, f.vis, f.worldPos, f.worldNormal, f.color,
          f.depth, f.primId, f.normal, lights, f.depthRange, f.vp.width, p};
  Kokkos::parallel_for("rast::shade", Range(0, n), k);
}

}  // namespace rast
