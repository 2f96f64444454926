// The glTF 2.0 metallic-roughness BRDF (specification, Appendix B) and the
// KHR_lights_punctual lights, as device functions of the shade stage
// (`--shading pbr`, shade_fragment.h's shadePbr).
//
// The arithmetic follows the Khronos glTF Sample Renderer's shaders, the
// reference rast is measured against (docs/gltf-support.md): GGX distribution
// with alpha = roughness^2, height-correlated Smith visibility, Schlick
// Fresnel with f0 = 0.04 for dielectrics and the base colour for metals, a
// Lambertian diffuse lobe mixed with the dielectric specular by its Fresnel
// term, and the metal and dielectric results mixed by `metallic`. Lights
// follow the extension's recommended falloff: inverse square with a smooth
// window at `range`, and the spot cone's squared linear ramp in cos(angle).
// KHR_materials_clearcoat adds a second dielectric GGX lobe over all of it
// (Coat).
#pragma once

#include "base/vec.h"
#include "pipeline/data/gpu_types.h"

namespace rast {
namespace pbr {

constexpr float kPi = 3.14159265358979f;

KOKKOS_INLINE_FUNCTION float3 mix(float3 a, float3 b, float t) { return a * (1.0f - t) + b * t; }
KOKKOS_INLINE_FUNCTION float3 mix(float3 a, float3 b, float3 t) {
  return float3{a.x + (b.x - a.x) * t.x, a.y + (b.y - a.y) * t.y, a.z + (b.z - a.z) * t.z};
}

// Schlick's Fresnel: f0 + (f90 - f0)(1 - VdotH)^5.
KOKKOS_INLINE_FUNCTION float3 fresnelSchlick(float3 f0, float f90, float VdotH) {
  const float x = clamp01(1.0f - VdotH), x2 = x * x, x5 = x2 * x2 * x;
  return float3{f0.x + (f90 - f0.x) * x5, f0.y + (f90 - f0.y) * x5, f0.z + (f90 - f0.z) * x5};
}

// Height-correlated Smith visibility V = G / (4 NdotL NdotV).
KOKKOS_INLINE_FUNCTION float visibilityGgx(float NdotL, float NdotV, float a) {
  const float a2 = a * a;
  const float gv = NdotL * ::sqrtf(NdotV * NdotV * (1.0f - a2) + a2);
  const float gl = NdotV * ::sqrtf(NdotL * NdotL * (1.0f - a2) + a2);
  const float g = gv + gl;
  return g > 0.0f ? 0.5f / g : 0.0f;
}

// Trowbridge-Reitz (GGX) normal distribution.
KOKKOS_INLINE_FUNCTION float distributionGgx(float NdotH, float a) {
  const float a2 = a * a;
  const float f = NdotH * NdotH * (a2 - 1.0f) + 1.0f;
  return a2 / (kPi * f * f);
}

// What the BRDF needs of a surface point: base colour (linear), metallic and
// perceptual roughness in [0, 1].
struct Surface {
  float3 base;
  float metallic, roughness;
};

// Light reaching a point from one light, with the unit vector L towards it.
KOKKOS_INLINE_FUNCTION float3 incidentLight(const PunctualGPU& l, const float3& P, float3& L) {
  if (l.type == 0) {  // directional: no falloff
    L = float3{-l.direction.x, -l.direction.y, -l.direction.z};
    return l.color;
  }
  const float3 d = l.position - P;
  const float dist2 = dot(d, d);
  const float dist = ::sqrtf(dist2);
  L = dist > 0.0f ? d * (1.0f / dist) : float3{0.0f, 0.0f, 1.0f};
  float att = dist2 > 0.0f ? 1.0f / dist2 : 0.0f;
  if (l.range > 0.0f) {
    const float r = dist / l.range, r2 = r * r;
    att *= clamp01(1.0f - r2 * r2);
  }
  if (l.type == 2) {  // spot: cos of the angle from the axis, ramped between the cones
    const float cd = -dot(l.direction, L);
    const float t = clamp01(cd * l.lightAngleScale + l.lightAngleOffset);
    att *= t * t;
  }
  return l.color * att;
}

// Outgoing radiance towards V from light arriving along L with radiance E
// (colour x intensity x attenuation), Appendix B's mix of the metal and
// dielectric BRDFs as the Khronos renderer evaluates it.
KOKKOS_INLINE_FUNCTION float3 shadeLight(const Surface& s, const float3& N, const float3& V, const float3& L,
                                        const float3& E) {
  const float NdotL = clamp01(dot(N, L));
  const float NdotV = clamp01(dot(N, V));
  const float3 H = normalize(L + V);
  const float NdotH = clamp01(dot(N, H));
  const float VdotH = clamp01(dot(V, H));
  const float a = s.roughness * s.roughness;
  const float3 diffuse = E * (NdotL / kPi) * s.base;
  float3 color = diffuse * (1.0f - s.metallic);
  if (NdotL > 0.0f || NdotV > 0.0f) {
    const float spec = NdotL * visibilityGgx(NdotL, NdotV, a) * distributionGgx(NdotH, a);
    const float3 specular = E * spec;
    const float3 fd = fresnelSchlick(float3{0.04f, 0.04f, 0.04f}, 1.0f, VdotH);
    const float3 dielectric = mix(diffuse, specular, fd);
    // mix(x, m, 0) is x: a dielectric material skips the metal lobe, same bits.
    color = dielectric;
    if (s.metallic > 0.0f) color = mix(dielectric, fresnelSchlick(s.base, 1.0f, VdotH) * specular, s.metallic);
  }
  return color;
}

// KHR_materials_clearcoat's layer at a fragment, as the Khronos Sample
// Renderer draws it: a dielectric GGX lobe (f0 = ((1.5 - 1) / (1.5 + 1))^2 =
// 0.04, f90 1) at the coat's normal n and perceptual roughness, over the
// base's light: f = mix(f_base, f_coat, factor * Fc), Fc Schlick's Fresnel
// at dot(n, V). weight = factor * Fc (0: no coat).
struct Coat {
  float factor = 0.0f, roughness = 0.0f, weight = 0.0f;
  float3 n{0.0f, 0.0f, 1.0f};
};

KOKKOS_INLINE_FUNCTION float coatFresnel(float NdotV) {
  const float x = clamp01(1.0f - NdotV), x2 = x * x;
  return 0.04f + (1.0f - 0.04f) * (x2 * x2 * x);
}

// A light's part `base` (shadeLight) with the coat over it: the coat's GGX
// specular for light E arriving along L, mixed in by the coat's weight.
KOKKOS_INLINE_FUNCTION float3 coated(const Coat& c, const float3& base, const float3& V, const float3& L,
                                     const float3& E) {
  const float3 H = normalize(L + V);
  const float NdotL = clamp01(dot(c.n, L)), NdotV = clamp01(dot(c.n, V)), NdotH = clamp01(dot(c.n, H));
  const float a = c.roughness * c.roughness;
  const float3 spec = E * (NdotL * visibilityGgx(NdotL, NdotV, a) * distributionGgx(NdotH, a));
  return mix(base, spec, c.weight);
}

// The coat's normal from its normal map's texel in the frame (T, B, Ng):
// TBN * normalize((2 rgb - 1) * (scale, scale, 1)), left unnormalised as the
// Sample Renderer leaves it (the frame is orthonormal).
KOKKOS_INLINE_FUNCTION float3 coatNormal(float4 texel, float scale, const float3& T, const float3& B,
                                         const float3& Ng) {
  float3 t{(2.0f * texel.x - 1.0f) * scale, (2.0f * texel.y - 1.0f) * scale, 2.0f * texel.z - 1.0f};
  t = normalize(t);
  return T * t.x + B * t.y + Ng * t.z;
}

// A normal map's texel (linear RGB in [0, 1]) applied in the frame (T, B, Ng):
// n = normalize(TBN * normalize((2 rgb - 1) * (scale, scale, 1))).
KOKKOS_INLINE_FUNCTION float3 perturbNormal(float3 texel, float scale, const float3& T, const float3& B,
                                           const float3& Ng) {
  float3 t{(2.0f * texel.x - 1.0f) * scale, (2.0f * texel.y - 1.0f) * scale, 2.0f * texel.z - 1.0f};
  t = normalize(t);
  return normalize(T * t.x + B * t.y + Ng * t.z);
}

}  // namespace pbr
}  // namespace rast
