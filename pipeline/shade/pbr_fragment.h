// The glTF shading of a fragment (`--shading pbr`): the members of
// shading::Shade that read a material's textures, normal maps and lights
// (included at the end of shade_fragment.h, which declares them), and the
// kernel specialised for it, ShadePbr, which the shade stage launches for the
// glTF shading at one sample a pixel on every backend (shade_stage.cpp).
//
// Why a kernel of its own: the general kernel carries every shading mode and
// every feature a fragment may need, and read its material per pixel. The
// specialised one is compiled per set of scene features (PbrFeature: texture
// coordinates, environment, punctual lights), chosen on the host per frame,
// so that a scene without one carries none of its code, and it looks up a
// triangle's material, texture and face normal once per triangle (PbrTri).
// Both evaluate the same expressions in the same order (shadePbr<kFeat>, one
// template), so a frame gets the same bits from either.
#pragma once

#include "backends/flatten.h"
#include "pipeline/shade/shade_fragment.h"

namespace rast {
namespace shading {

KOKKOS_INLINE_FUNCTION float2 lerp3(float2 a, float2 b, float2 c, float b0, float b1, float b2) {
  return {a.x * b0 + b.x * b1 + c.x * b2, a.y * b0 + b.y * b1 + c.y * b2};
}

// A texture at uv, filtered as the frame asks; `decode` is the sRGB table for
// colour textures, the unorm one for data.
RAST_GPU_INLINE float4 Shade::sampleTexture(const TextureGPU& tex, float2 uv, DecodeTable decode, float2 dx,
                                            float2 dy) const {
  const TexelTable tx{texels.data()};
  if (p.filter == TexFilter::Auto) return sampleSampler(tex, tx, decode, uv.x, uv.y, dx, dy, p.anisotropy);
  if (p.filter == TexFilter::Trilinear)
    return sampleTrilinear(tex, tx, decode, uv.x, uv.y, textureLod(dx.x, dx.y, dy.x, dy.y, tex.width, tex.height));
  if (p.filter == TexFilter::Nearest) return sampleNearest(tex, tx, decode, uv.x, uv.y);
  return sampleBilinear(tex, tx, decode, uv.x, uv.y);
}

// The material's textures at a fragment. One loop over the slots, kept a
// loop on GPUs: with a sampler call per texture, inlined or not, nvcc either
// left the textured kernel's body out of line (the functor copied to every
// thread's stack) or saved the registers around five calls to the filter;
// here the filter is one copy of code, inlined.
RAST_GPU_INLINE void Shade::materialTexels(const TriFrag& f, const MaterialGPU& m, uint32_t on1, const UvSet& c0,
                                           const UvSet& c1, float4 (&tx)[kTextureSlots]) const {
  const bool emits = m.emissive.x > 0.0f || m.emissive.y > 0.0f || m.emissive.z > 0.0f;
#if defined(__CUDA_ARCH__) || defined(__HIP_DEVICE_COMPILE__)
#pragma unroll 1
#endif
  for (int k = 0; k < kTextureSlots; ++k) {
    const int32_t index = k == SlotBaseColor    ? m.texture
                          : k == SlotMetalRough ? m.mrTexture
                          : k == SlotNormal     ? m.normalTexture
                          : k == SlotOcclusion  ? m.occlusionTexture
                          : emits               ? m.emissiveTexture
                                                : -1;
    if (index < 0) continue;
    // The base colour's coordinates are always the first set; colour
    // textures are decoded from sRGB, data textures as unorm.
    const UvSet& c = k != SlotBaseColor && (on1 >> k & 1u) ? c1 : c0;
    const bool srgb = k == SlotBaseColor || k == SlotEmissive;
    // The base colour's texture is the triangle's (TriFrag::tex, loaded by prepare).
    const TextureGPU tex = k == SlotBaseColor ? f.tex : textures(index);
    tx[k] = sampleTexture(tex, c.uv, DecodeTable{srgb ? lut.data() : unorm.data()}, c.dx, c.dy);
  }
}

// The same loop over the base's slots and the clear coat's (all linear data).
RAST_TEXELS_INLINE void Shade::coatTexels(const TriFrag& f, const MaterialGPU& m, const ClearcoatGPU& cc,
                                          uint32_t on1, const UvSet& c0, const UvSet& c1,
                                          float4 (&tx)[kCoatSlots]) const {
  const bool emits = m.emissive.x > 0.0f || m.emissive.y > 0.0f || m.emissive.z > 0.0f;
#if defined(__CUDA_ARCH__) || defined(__HIP_DEVICE_COMPILE__)
#pragma unroll 1
#endif
  for (int k = 0; k < kCoatSlots; ++k) {
    const int32_t index = k == SlotBaseColor            ? m.texture
                          : k == SlotMetalRough         ? m.mrTexture
                          : k == SlotNormal             ? m.normalTexture
                          : k == SlotOcclusion          ? m.occlusionTexture
                          : k == SlotEmissive           ? (emits ? m.emissiveTexture : -1)
                          : k == SlotClearcoat          ? cc.texture
                          : k == SlotClearcoatRoughness ? cc.roughnessTexture
                                                        : cc.normalTexture;
    if (index < 0) continue;
    const UvSet& c = k != SlotBaseColor && (on1 >> k & 1u) ? c1 : c0;
    const bool srgb = k == SlotBaseColor || k == SlotEmissive;
    const TextureGPU tex = k == SlotBaseColor ? f.tex : textures(index);
    tx[k] = sampleTexture(tex, c.uv, DecodeTable{srgb ? lut.data() : unorm.data()}, c.dx, c.dy);
  }
}

KOKKOS_INLINE_FUNCTION Shade::UvSet Shade::uvSet(float2 t0, float2 t1, float2 t2, const float b[3], const float bx[3],
                                                 const float by[3], bool derivatives) {
  UvSet c;
  c.t0 = t0;
  c.t1 = t1;
  c.t2 = t2;
  c.uv = lerp3(t0, t1, t2, b[0], b[1], b[2]);
  if (derivatives) {
    const float2 ux = lerp3(t0, t1, t2, bx[0], bx[1], bx[2]), uy = lerp3(t0, t1, t2, by[0], by[1], by[2]);
    c.dx = float2{ux.x - c.uv.x, ux.y - c.uv.y};
    c.dy = float2{uy.x - c.uv.x, uy.y - c.uv.y};
  }
  return c;
}

// The normal-mapped normal at a fragment whose interpolated normal is N
// (turned towards the viewer when `back`). The tangent frame: the
// primitive's tangents (the file's TANGENT or generated at load,
// Scene::tangents) interpolated and moved to the world by the draw's
// matrix, else the triangle's dP/du (skinned draws, whose tangents the
// vertex stage does not pose, and primitives without tangents); made
// orthogonal to N, the bitangent w N x T (w: the tangents' handedness,
// turned by a mirroring matrix so that it stays the file's bitangent).
// A back face turns all three, as the Khronos renderer does.
RAST_GPU_INLINE float3 Shade::normalMapped(const TriFrag& f, const MaterialGPU& m, float b0, float b1, float b2,
                                           float3 N, bool back, const UvSet& c, const float4& nt) const {
  float3 T, B, Ng;
  if (!tangentFrame(f, b0, b1, b2, N, back, c, T, B, Ng)) return Ng;
  return pbr::perturbNormal(float3{nt.x, nt.y, nt.z}, m.normalScale, T, B, Ng);
}

RAST_GPU_INLINE bool Shade::tangentFrame(const TriFrag& f, float b0, float b1, float b2, float3 N, bool back,
                                         const UvSet& c, float3& Tout, float3& B, float3& Ng) const {
  float3 T{0.0f, 0.0f, 0.0f};
  float w = 1.0f;
  if (hasTangent) {
    const DrawGPU& dr = draws(f.draw);
    const float4 t0 = tangents(f.s0), t1 = tangents(f.s1), t2 = tangents(f.s2);
    const float tw = t0.w * b0 + t1.w * b1 + t2.w * b2;
    if (dr.skinJoint < 0 && tw != 0.0f) {
      const float3 to{t0.x * b0 + t1.x * b1 + t2.x * b2, t0.y * b0 + t1.y * b1 + t2.y * b2,
                      t0.z * b0 + t1.z * b1 + t2.z * b2};
      const float* M = dr.modelF.m;
      T = float3{M[0] * to.x + M[4] * to.y + M[8] * to.z, M[1] * to.x + M[5] * to.y + M[9] * to.z,
                 M[2] * to.x + M[6] * to.y + M[10] * to.z};
      T = T - N * dot(N, T);
      w = (tw < 0.0f) != (f.mirrored != 0) ? -1.0f : 1.0f;
    }
  }
  if (!(dot(T, T) > 1e-12f)) {
    // dP/du of the triangle (position and uv are both linear over it).
    const float3 e1 = f.pos[1] - f.pos[0], e2 = f.pos[2] - f.pos[0];
    const float du1 = c.t1.x - c.t0.x, dv1 = c.t1.y - c.t0.y;
    const float du2 = c.t2.x - c.t0.x, dv2 = c.t2.y - c.t0.y;
    const float det = du1 * dv2 - du2 * dv1;
    T = det != 0.0f ? (e1 * dv2 - e2 * dv1) * (1.0f / det) : e1;
    T = T - N * dot(N, T);
    w = 1.0f;
  }
  const float s = back ? -1.0f : 1.0f;
  Ng = N * s;
  if (!(dot(T, T) > 0.0f)) return false;
  T = normalize(T);
  B = cross(N, T) * (w * s);
  Tout = T * s;
  return true;
}

// The glTF shading's part of triangle f (prepared): its material, or the
// specification's default material without one.
RAST_GPU_INLINE PbrTri Shade::pbrTri(const TriFrag& f) const {
  PbrTri t;
  MaterialGPU& m = t.m;
  m = MaterialGPU{};
  m.baseColor = float4{1.0f, 1.0f, 1.0f, 1.0f};
  m.texture = m.mrTexture = m.normalTexture = m.occlusionTexture = m.emissiveTexture = -1;
  m.metallic = m.roughness = m.normalScale = m.occlusionStrength = 1.0f;  // the spec's default material
  if (f.material >= 0) m = materials(f.material);
  t.textured = pbrTextured(m);
  // The material's coordinates: the first set, and the second where some
  // of its textures sample another set or transform (uv1Slots).
  t.on1 = hasUV1 ? uint32_t(m.flags) >> kMaterialUv1Shift : 0u;
  t.face = cross(f.pos[1] - f.pos[0], f.pos[2] - f.pos[0]);
  if (!kOnDevice && p.useEnv) keepIbl(t.ibl, p.env, clamp01(m.roughness));
  return t;
}

// The glTF 2.0 metallic-roughness model (pbr_shading.h) at a fragment of
// triangle f (its PbrTri t) with barycentrics b and interpolated normal N,
// position P: the material's factors times its textures, the file's
// punctual lights (else --light, or a headlight when there is no environment
// either), emission, and the environment's image-based light
// (ibl_shading.h), or without one an ambient term; both scaled by the
// occlusion texture; and a KHR_materials_clearcoat layer over all of it
// (pbr::Coat). Linear light. kFeat: the scene's features (PbrFeature) known
// at compile time, or kPbrAny. surface(N, P) gives the normal and position,
// asked for only past the unlit materials' return: the BLEND resolve
// interpolates them there (an unlit layer's fragment skips a normalisation
// and two interpolations: a third of its instructions, a tenth of the
// resolve's time for 8 unlit layers on the H100).
template <int kFeat, class Surface>
RAST_GPU_INLINE float4 Shade::shadePbrWith(const TriFrag& f, const PbrTri& t, int32_t X, int32_t Y, int32_t ox,
                                           int32_t oy, float b0, float b1, float b2, const Surface& surface) const {
  constexpr bool kAny = kFeat == kPbrAny;
  // The clear coat's code: its instance and the general kernel (kPbrAny has every bit).
  constexpr bool kCoat = (kFeat & kPbrClearcoat) != 0;
  constexpr bool kRunTime = kAny || kCoat;  // the other features read at run time
  // Only base colour textures in the scene: that one sampled at its own call site.
  constexpr bool kBaseOnly = !kRunTime && (kFeat & kPbrBaseTexture) != 0;
  const bool useEnv = kRunTime ? p.useEnv != 0 : (kFeat & kPbrEnv) != 0;
  const bool anyPunctual = kRunTime ? numPunctual > 0 : (kFeat & kPbrPunctual) != 0;
  const MaterialGPU& m = t.m;
  const bool textured = (kRunTime || (kFeat & kPbrTextured)) && t.textured;
  const bool coat = kCoat && (m.flags & kMaterialClearcoat);
  ClearcoatGPU cc{0.0f, 0.0f, 1.0f, -1, -1, -1};
  if (coat) cc = clearcoats(f.material);
  const uint32_t on1 = kBaseOnly ? 0u : t.on1;  // (the base colour always takes the first set)
  UvSet c0, c1;
  if (textured) {
    const float b[3] = {b0, b1, b2};
    float bx[3] = {0.0f, 0.0f, 0.0f}, by[3] = {0.0f, 0.0f, 0.0f};
    const bool derivatives = p.filter == TexFilter::Trilinear || p.filter == TexFilter::Auto;
    if (derivatives) {  // analytic derivatives, as the other modes take them (bary(), its edges evaluated once)
      const Edges& e = f.e;
      const int64_t E0 = e.eval(0, X, Y), E1 = e.eval(1, X, Y), E2 = e.eval(2, X, Y);
      baryFrom(f, e.atSample(0, E0, ox + kSubOne, oy), e.atSample(1, E1, ox + kSubOne, oy),
               e.atSample(2, E2, ox + kSubOne, oy), bx[0], bx[1], bx[2]);
      baryFrom(f, e.atSample(0, E0, ox, oy + kSubOne), e.atSample(1, E1, ox, oy + kSubOne),
               e.atSample(2, E2, ox, oy + kSubOne), by[0], by[1], by[2]);
    }
    c0 = uvSet(f.uv[0], f.uv[1], f.uv[2], b, bx, by, derivatives);
    if (on1) c1 = uvSet(uvs1(f.s0), uvs1(f.s1), uvs1(f.s2), b, bx, by, derivatives);
  }
  float4 tx[kCoat ? kCoatSlots : kTextureSlots] = {};
  if (textured) {
    if constexpr (kCoat) coatTexels(f, m, cc, on1, c0, c1, tx);
    else if constexpr (kBaseOnly) {  // materialTexels' base colour slot, alone
      if (m.texture >= 0) tx[SlotBaseColor] = sampleTexture(f.tex, c0.uv, DecodeTable{lut.data()}, c0.dx, c0.dy);
    } else materialTexels(f, m, on1, c0, c1, tx);
  }
  float4 base = m.baseColor;
  if (textured && m.texture >= 0) base = base * tx[SlotBaseColor];
  if (hasColor) base = base * (f.col[0] * b0 + f.col[1] * b1 + f.col[2] * b2);
  const float alpha = (m.flags & kMaterialOpaque) || f.material < 0 ? 1.0f : base.w;
  const float3 baseRgb{base.x, base.y, base.z};
  // The debug views (--shading basecolor, ...) take the general kernel
  // (kAny) only: the glTF shading's own kernel carries none of them.
  if ((kAny && p.mode == ShadingMode::BaseColor) || ((m.flags & kMaterialUnlit) && (!kAny || p.mode == ShadingMode::Pbr)))
    return float4{baseRgb.x, baseRgb.y, baseRgb.z, alpha};
  float3 N, P;
  surface(N, P);

  pbr::Surface s{baseRgb, clamp01(m.metallic), clamp01(m.roughness)};
  if (textured && m.mrTexture >= 0) {
    const float4& mr = tx[SlotMetalRough];
    s.roughness = clamp01(s.roughness * mr.y);
    s.metallic = clamp01(s.metallic * mr.z);
  }
  // Laid out as glTF's metallicRoughness texture: G roughness, B metal.
  if (kAny && p.mode == ShadingMode::MetalRough) return float4{0.0f, s.roughness, s.metallic, alpha};
  const float3 V = normalize(f.eye - P);
  // Back faces (drawn when the material is double-sided) turn their
  // normal towards the viewer, as the specification says.
  const bool back = (dot(t.face, V) < 0.0f) != (f.mirrored != 0);
  const float3 Ng = back ? N * -1.0f : N;
  // The coat (KHR_materials_clearcoat): factor x texture R, roughness x
  // texture G, its own normal map or the geometry's normal (not the base's
  // normal map), its Fresnel weight towards the viewer.
  pbr::Coat cl;
  if constexpr (kCoat) {
    if (coat) {
      cl.factor = cc.factor;
      cl.roughness = cc.roughness;
      if (textured && cc.texture >= 0) cl.factor = cl.factor * tx[SlotClearcoat].x;
      if (textured && cc.roughnessTexture >= 0) cl.roughness = cl.roughness * tx[SlotClearcoatRoughness].y;
      cl.roughness = clamp01(cl.roughness);
      cl.n = Ng;
      if (textured && cc.normalTexture >= 0) {
        float3 T, B, G;
        if (tangentFrame(f, b0, b1, b2, N, back, on1 >> SlotClearcoatNormal & 1u ? c1 : c0, T, B, G))
          cl.n = pbr::coatNormal(tx[SlotClearcoatNormal], cc.normalScale, T, B, G);
      }
      cl.weight = cl.factor * pbr::coatFresnel(clamp01(dot(cl.n, V)));
    }
  }
  if (textured && m.normalTexture >= 0)
    N = normalMapped(f, m, b0, b1, b2, N, back, on1 >> SlotNormal & 1u ? c1 : c0, tx[SlotNormal]);
  else N = Ng;
  if (kAny && p.mode == ShadingMode::ShadingNormals)  // encoded as the normals view encodes
    return float4{N.x * 0.5f + 0.5f, N.y * 0.5f + 0.5f, N.z * 0.5f + 0.5f, alpha};
  if (kAny && p.mode == ShadingMode::Occlusion) {
    const float ao = occlusionAt(m, textured, tx[SlotOcclusion]);
    return float4{ao, ao, ao, alpha};
  }
  if (kAny && p.mode == ShadingMode::Emissive) {
    const float3 e = emissionAt(m, textured, tx[SlotEmissive]);
    return float4{e.x, e.y, e.z, alpha};
  }

  float3 color{0.0f, 0.0f, 0.0f};
  // Each light's part goes under the coat where there is one (pbr::coated).
  if (anyPunctual) {
    for (int k = 0; k < numPunctual; ++k) {
      float3 L;
      const float3 E = pbr::incidentLight(punctual(k), P, L);
      float3 c = pbr::shadeLight(s, N, V, L, E);
      if constexpr (kCoat) c = coat ? pbr::coated(cl, c, V, L, E) : c;
      color = color + c;
    }
  } else if (p.headlight) {
    // Scaled by pi: a white Lambertian surface facing it reflects what
    // the Lambert shading's headlight gives it. With an environment, that
    // lights a file without lights of its own instead.
    const float I = (1.0f - p.ambient) * pbr::kPi;
    if (!useEnv) {
      color = pbr::shadeLight(s, N, V, V, float3{I, I, I});
      if constexpr (kCoat) color = coat ? pbr::coated(cl, color, V, V, float3{I, I, I}) : color;
    }
  } else {
    for (int k = 0; k < int(lights.extent(0)); ++k) {
      const float I = lights(k).intensity * pbr::kPi;
      float3 c = pbr::shadeLight(s, N, V, lights(k).direction, float3{I, I, I});
      if constexpr (kCoat) c = coat ? pbr::coated(cl, c, V, lights(k).direction, float3{I, I, I}) : c;
      color = color + c;
    }
  }
  // Indirect light (the environment's, else an ambient term on the
  // diffuse part), darkened by the occlusion texture: only it.
  const float ao = occlusionAt(m, textured, tx[SlotOcclusion]);
  if (useEnv) {
    // s.roughness is clamp01(m.roughness), what pbrTri found t.ibl for,
    // unless the metal/rough texture scaled it.
    const bool perTri = !kOnDevice && !(textured && m.mrTexture >= 0);
    bool coated = false;
    if constexpr (kCoat) {
      if (coat) {  // the coat's prefiltered radiance at its roughness, mixed in before the occlusion
        const float3 base = iblLight(p.env, N, V, s.base, s.metallic, iblOf(t.ibl, p.env, s.roughness, perTri));
        const float3 ibl = pbr::mix(base, iblSpecular(p.env, cl.n, V, cl.roughness), cl.weight);
        color = color + ibl * (1.0f + (ao - 1.0f));
        coated = true;
      }
    }
    if (!coated)
      color = color + iblShade(p.env, N, V, s.base, s.metallic, iblOf(t.ibl, p.env, s.roughness, perTri), ao);
  }
  else if (!anyPunctual)
    color = color + s.base * (p.ambient * (1.0f - s.metallic) * ao);
  const float3 emission = emissionAt(m, textured, tx[SlotEmissive]);
  if constexpr (kCoat) {
    if (coat) {  // the coat dims the emission under it by its Fresnel weight, as the Sample Renderer does
      color = color + emission * (1.0f - cl.weight);
      return float4{color.x, color.y, color.z, alpha};
    }
  }
  color = color + emission;
  return float4{color.x, color.y, color.z, alpha};
}

RAST_GPU_INLINE float Shade::occlusionAt(const MaterialGPU& m, bool textured, const float4& texel) {
  if (!textured || m.occlusionTexture < 0) return 1.0f;
  return 1.0f + m.occlusionStrength * (texel.x - 1.0f);
}

// Emitted light: the factor (times KHR_materials_emissive_strength) times the texture.
RAST_GPU_INLINE float3 Shade::emissionAt(const MaterialGPU& m, bool textured, const float4& texel) {
  float3 emissive = m.emissive;
  if (textured && m.emissiveTexture >= 0 && (emissive.x > 0.0f || emissive.y > 0.0f || emissive.z > 0.0f))
    emissive = emissive * float3{texel.x, texel.y, texel.z};
  return emissive;
}

// The glTF shading's kernel (rast::shade::pbr): one sample a pixel, the
// general kernel's layouts (runs along rows on CPUs, interleaved columns on
// GPUs: kInterleaved), a triangle's lookups (TriFrag and PbrTri) kept from
// pixel to pixel. The same outputs, in the same bits, as Shade::shadeSingle.
struct PbrFrag {
  TriFrag f;
  PbrTri t;
};

// kBlend: the pixels may take BLEND layers' composite (Shade::blendFilm;
// BlendPlan::shadeComposite). A GPU builds the opaque frames' instances
// without it: its check a column cost their shading 1 us of 36 (H200, 1080p).
template <int kFeat, bool kInterleaved, bool kBlend>
struct ShadePbr {
  Shade k;

  KOKKOS_FORCEINLINE_FUNCTION Shade::BlendAt blendAt(const int32_t X, const int32_t Y) const {
    if constexpr (kBlend) return k.blendAt(X, Y);
    return Shade::BlendAt{float4{0.0f, 0.0f, 0.0f, 0.0f}, 0};
  }
  // The film's pixel i shaded c (Shade::blendFilm).
  KOKKOS_FORCEINLINE_FUNCTION void film(const int64_t i, const Shade::BlendAt& bl, const float4 c) const {
    if constexpr (kBlend) k.blendFilm(i, bl, c);
    else k.hdr(i) = c;
  }

  KOKKOS_FORCEINLINE_FUNCTION void use(uint32_t index, PbrFrag& q) const {
    if (index == q.f.index) return;
    k.prepare(index, q.f);
    if (!(index & kLineFlag)) q.t = k.pbrTri(q.f);
  }

  // Shade::shadeFragment's path for the glTF shading at a pixel centre.
  // The normal and position are interpolated before the shading where the
  // normals or geometry outputs read them (n0, p0), else only where the
  // material is lit (shadePbrWith asks past its unlit return): an unlit
  // material's pixel is then its base colour without a square root. The
  // same bits either way on CPUs; a GPU build's contraction of multiplies
  // and adds follows the code's shape, so its lit pixels may round otherwise.
  KOKKOS_FORCEINLINE_FUNCTION float4 fragment(const PbrFrag& q, int32_t X, int32_t Y, float3& n0, float3* p0) const {
    const TriFrag& f = q.f;
    if (f.index & kLineFlag) return k.lineShade.color(f.index & ~kLineFlag);
    float b0, b1, b2;
    k.bary(f, f.e, X, Y, 0, 0, b0, b1, b2);
    const auto surface = [&](float3& N, float3& P) {
      N = normalize(f.n[0] * b0 + f.n[1] * b1 + f.n[2] * b2);
      P = f.pos[0] * b0 + f.pos[1] * b1 + f.pos[2] * b2;
    };
    if (!k.p.wantNormals && !k.p.wantGeom) return k.template shadePbrWith<kFeat>(f, q.t, X, Y, 0, 0, b0, b1, b2, surface);
    float3 N, P;
    surface(N, P);
    n0 = N;
    if (p0) *p0 = P;
    return k.template shadePbr<kFeat>(f, q.t, X, Y, 0, 0, b0, b1, b2, N, P);
  }

  // Shade::shadeSingle for the glTF shading; bl: the BLEND layers' composite
  // over the pixel, if any (Shade::blendAt).
  KOKKOS_FORCEINLINE_FUNCTION void single(const int64_t i, const int32_t X, const int32_t Y, PbrFrag& q,
                                          const uint64_t key0, const Shade::BlendAt& bl) const {
    if (k.clearVis && key0 != kClearKey) k.vis(i) = kClearKey;
    // The listed BLEND methods' opaque depth, which only the walked blocks'
    // resolve reads after shading: not where the pixel's block is composited here.
    if (k.opaqueDepth.data() && !bl.over) k.opaqueDepth(i) = uint32_t(key0 >> 32);
    k.resetBlock(X, Y);
    k.writeIds(i, key0);
    const uint32_t idx0 = uint32_t(key0 & 0xffffffffu);
    if (!idx0) {  // background: its outputs without a fragment's (viewGeometry of a zero normal is zero)
      if (k.p.floatOut) film(i, bl, k.p.backgroundFilm);
      else k.color(i) = k.p.backgroundPacked;
      if (k.p.wantNormals) k.normalOut(i) = float3{0.0f, 0.0f, 0.0f};
      if (k.p.wantGeom) k.writeGeometry(i, float4{0.0f, 0.0f, 0.0f, 0.0f});
      return;
    }
    float3 n0{0.0f, 0.0f, 0.0f}, p0{0.0f, 0.0f, 0.0f};
    use(idx0 - 1, q);
    if (k.p.floatOut)
      film(i, bl, fragment(q, X, Y, n0, &p0));
    else
      k.color(i) = k.template display<true>(fragment(q, X, Y, n0, nullptr));
    if (k.p.wantNormals) k.normalOut(i) = n0;
    if (k.p.wantGeom) k.writeGeometry(i, k.viewGeometry(n0, p0));
  }

  RAST_FLATTEN void operator()(const int64_t item) const {
    if (!kInterleaved) {  // Shade::operator(): pixels [x0, x1) of row Y
      PbrFrag q{};  // (zeroed once per run of pixels: GCC cannot see that a pixel is shaded after use())
      const uint32_t it = uint32_t(item), rows = uint32_t(k.runsPerRow);
      const int32_t Y = int32_t(it / rows);
      const int32_t x0 = int32_t(it - uint32_t(Y) * rows) * k.run;
      const int32_t x1 = x0 + k.run < k.width ? x0 + k.run : k.width;
      const int64_t row = int64_t(Y) * k.width;
      for (int32_t X = x0; X < x1; ++X) single(row + X, X, Y, q, k.vis(row + X), blendAt(X, Y));
      return;
    }
    // Shade::shadeInterleaved: a column of kShadeInterleave pixels, its keys loaded first.
    const uint32_t thisFrame = k.p.blockFrames ? k.p.frame(0).frame : 0u;
    const Shade::Column at = k.column(uint32_t(item));
    if (at.X >= uint32_t(k.width)) return;
    const uint32_t rows = uint32_t(k.height) - at.Y < uint32_t(kShadeInterleave) ? uint32_t(k.height) - at.Y
                                                                                : uint32_t(kShadeInterleave);
    const bool tagged =
        !k.p.blockFrames ||
        k.blockFrame((at.Y >> kVisBlockShift) * uint32_t(k.blocksPerRow) + (at.X >> kVisBlockShift)) == thisFrame;
    static_assert((1 << kBlendBlockShift) % kShadeInterleave == 0, "a work item's column lies in one BLEND block");
    const Shade::BlendAt bl = blendAt(int32_t(at.X), int32_t(at.Y));
    uint64_t keys[kShadeInterleave];
    PbrFrag q;
    for (uint32_t j = 0; j < uint32_t(kShadeInterleave); ++j)
      keys[j] = tagged && j < rows ? k.vis(at.i + j * uint32_t(k.width)) : kClearKey;
    for (uint32_t j = 0; j < rows; ++j) {
      // The textured instances look their triangle up afresh at every pixel
      // (mostly L1 hits: a column's pixels and a warp's neighbours share
      // it). Kept from pixel to pixel, TriFrag and PbrTri stay live through
      // the whole shading, and under kShadeLaunchBounds' 128 registers the
      // shading spilled more: on the H100 (1080p, shade stage, median of 200
      // frames) duck 0.076 -> 0.067 ms, milktruck 0.079 -> 0.071,
      // checkerboard 0.041 -> 0.038. The others keep the cache.
      if constexpr ((kFeat & kPbrTextured) != 0) {
        PbrFrag fresh;
        single(int64_t(at.i + j * uint32_t(k.width)), int32_t(at.X), int32_t(at.Y + j), fresh, keys[0], bl);
      } else {
        single(int64_t(at.i + j * uint32_t(k.width)), int32_t(at.X), int32_t(at.Y + j), q, keys[0], bl);
      }
      for (uint32_t r = 0; r + 1 < uint32_t(kShadeInterleave); ++r) keys[r] = keys[r + 1];
    }
  }
};

}  // namespace shading
}  // namespace rast
