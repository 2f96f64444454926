// The image-based light of a fragment, as the Khronos glTF Sample Renderer
// computes it (its ibl.glsl and the IBL block of pbr.frag): Lambertian
// irradiance times base colour, GGX-prefiltered radiance along the reflected
// view at lod = roughness * (mipCount - 1), the split-sum table with its
// multiple-scattering term (Fdez-Aguera) for the dielectric and the metal
// Fresnel, mixed by metallic, occlusion applied with its strength. Reads an
// EnvironmentGPU built once by buildEnvironment (environment.h).
#pragma once

#include "pipeline/shade/cube_map.h"
#include "pipeline/shade/environment.h"

namespace rast {

// The environment's rotation about +Y applied to a lookup direction (the
// Sample Renderer's u_EnvRotation * dir).
KOKKOS_INLINE_FUNCTION float3 envRotate(const EnvironmentGPU& e, float3 d) {
  return {e.cosRot * d.x + e.sinRot * d.z, d.y, e.cosRot * d.z - e.sinRot * d.x};
}

KOKKOS_INLINE_FUNCTION float3 rgb3(float4 c) { return {c.x, c.y, c.z}; }

// Irradiance / pi around normal n, times the intensity (getDiffuseLight).
KOKKOS_INLINE_FUNCTION float3 iblDiffuse(const EnvironmentGPU& e, float3 n) {
  const CubeCoord c = cubeCoord(envRotate(e, n));
  return rgb3(cubeBilinear(e.diffuse, 0u, e.diffuseSize, c)) * e.intensity;
}

// What the image-based light of a fragment needs of its perceptual
// roughness alone: the specular levels at lod = roughness * (mipCount - 1),
// and the split-sum table's rows (their first texels' indices) and weight.
// Found once per triangle on host backends where the roughness is the
// material's (PbrTri::ibl), else per fragment.
struct IblRough {
  float roughness = 1.0f;
  CubeLod lod;
  uint32_t row0 = 0, row1 = 0;
  float b = 0.0f;
};
// In its place where none is kept (a GPU's PbrTri).
struct NoIblRough {};
KOKKOS_INLINE_FUNCTION IblRough iblRough(const EnvironmentGPU& e, float roughness) {
  IblRough r;
  r.roughness = roughness;
  r.lod = cubeLod(e.levelOffset, e.faceSize, e.mipCount, roughness * float(e.mipCount - 1));
  const int32_t n = e.lutSize;
  const float w = clamp01(roughness) * float(n) - 0.5f;
  const int32_t iw = floorIndex(w);  // in [-1, n - 1]
  r.b = w - float(iw);
  r.row0 = uint32_t(imax(iw, 0)) * n;
  r.row1 = uint32_t(imin(iw + 1, n - 1)) * n;
  return r;
}
// Keeps the triangle's part where its PbrTri has room for one; the part for
// a fragment: the kept one where perTri (the material's roughness), else
// found here.
KOKKOS_INLINE_FUNCTION void keepIbl(IblRough& kept, const EnvironmentGPU& e, float roughness) {
  kept = iblRough(e, roughness);
}
KOKKOS_INLINE_FUNCTION void keepIbl(NoIblRough&, const EnvironmentGPU&, float) {}
KOKKOS_INLINE_FUNCTION IblRough iblOf(const IblRough& kept, const EnvironmentGPU& e, float roughness, bool perTri) {
  return perTri ? kept : iblRough(e, roughness);
}
KOKKOS_INLINE_FUNCTION IblRough iblOf(const NoIblRough&, const EnvironmentGPU& e, float roughness, bool) {
  return iblRough(e, roughness);
}

// Prefiltered radiance along direction r at perceptual roughness (getSpecularSample).
KOKKOS_INLINE_FUNCTION float3 iblRadiance(const EnvironmentGPU& e, float3 r, const IblRough& rough) {
  return rgb3(cubeTrilinearAt(e.specular, rough.lod, cubeCoord(envRotate(e, r)))) * e.intensity;
}
KOKKOS_INLINE_FUNCTION float3 iblRadiance(const EnvironmentGPU& e, float3 r, float roughness) {
  return iblRadiance(e, r, iblRough(e, roughness));
}

// Prefiltered radiance along reflect(-v, n) (getIBLRadianceGGX); n, v unit.
KOKKOS_INLINE_FUNCTION float3 iblSpecular(const EnvironmentGPU& e, float3 n, float3 v, float roughness) {
  const float ndv = dot(n, v);
  return iblRadiance(e, normalize(n * (2.0f * ndv) - v), roughness);
}

// The split-sum table at (NdotV, roughness), both clamped to [0, 1],
// bilinear with clamped edges as the reference's texture() reads it.
KOKKOS_INLINE_FUNCTION float2 iblBrdf(const EnvironmentGPU& e, float NdotV, const IblRough& r) {
  const int32_t n = e.lutSize;
  const float u = clamp01(NdotV) * float(n) - 0.5f;
  const int32_t iu = floorIndex(u);  // in [-1, n - 1]
  const float a = u - float(iu), b = r.b;
  const int32_t x0 = imax(iu, 0), x1 = imin(iu + 1, n - 1);
  const float2 t00 = e.lut(r.row0 + x0), t10 = e.lut(r.row0 + x1);
  const float2 t01 = e.lut(r.row1 + x0), t11 = e.lut(r.row1 + x1);
  const float sx = (t00.x * (1.0f - a) + t10.x * a) * (1.0f - b) + (t01.x * (1.0f - a) + t11.x * a) * b;
  const float sy = (t00.y * (1.0f - a) + t10.y * a) * (1.0f - b) + (t01.y * (1.0f - a) + t11.y * a) * b;
  return {sx, sy};
}
KOKKOS_INLINE_FUNCTION float2 iblBrdf(const EnvironmentGPU& e, float NdotV, float roughness) {
  return iblBrdf(e, NdotV, iblRough(e, roughness));
}

// The reference's getIBLGGXFresnel with specularWeight 1: single scattering
// (F0 + Fr (1 - NdotV)^5) f_ab.x + f_ab.y with its roughness-dependent Fr,
// plus the multiple-scattering energy.
KOKKOS_INLINE_FUNCTION float3 iblGgxFresnel(float NdotV, float roughness, float3 f0, float2 fab) {
  const float r = 1.0f - roughness;
  const float3 fr = {(r > f0.x ? r : f0.x) - f0.x, (r > f0.y ? r : f0.y) - f0.y, (r > f0.z ? r : f0.z) - f0.z};
  const float m = 1.0f - NdotV, m2 = m * m, p5 = m2 * m2 * m;
  const float3 kS = f0 + fr * p5;
  const float3 fssEss = kS * fab.x + make3(fab.y, fab.y, fab.y);
  const float ems = 1.0f - (fab.x + fab.y);
  const float3 fAvg = f0 + (make3(1.0f, 1.0f, 1.0f) - f0) * (1.0f / 21.0f);
  const float3 num = fssEss * fAvg * ems;
  const float3 fmsEms = {num.x / (1.0f - fAvg.x * ems), num.y / (1.0f - fAvg.y * ems), num.z / (1.0f - fAvg.z * ems)};
  return fssEss + fmsEms;
}

// The whole image-based light of a metallic-roughness material: n, v unit
// (v towards the eye), roughness perceptual (the material's, before
// squaring), occlusion the occlusion texel's value and its strength:
// colour * (1 + strength (occlusion - 1)), on this light only.
// rough: iblRough(e, roughness). iblLight: the same before the occlusion
// (a clear coat mixes its own specular in there first, pbr_fragment.h).
KOKKOS_INLINE_FUNCTION float3 iblLight(const EnvironmentGPU& e, float3 n, float3 v, float3 baseColor, float metallic,
                                       const IblRough& rough) {
  const float roughness = rough.roughness;
  const float ndv = clamp01(dot(n, v));
  const float2 fab = iblBrdf(e, ndv, rough);
  const float3 specular = iblRadiance(e, normalize(n * (2.0f * dot(n, v)) - v), rough);
  const float3 one = make3(1.0f, 1.0f, 1.0f);
  // A lobe whose weight is 0 is left at 0: x (1 - 0) + 0 0 is x, so the
  // colour has the same bits as with both lobes evaluated, and a material
  // that is all dielectric (most are) or all metal pays for one.
  float3 dielectric = make3(0.0f, 0.0f, 0.0f), metal = make3(0.0f, 0.0f, 0.0f);
  if (metallic < 1.0f) {
    const float3 diffuse = iblDiffuse(e, n) * baseColor;
    const float3 dielF = iblGgxFresnel(ndv, roughness, make3(0.04f, 0.04f, 0.04f), fab);
    dielectric = diffuse * (one - dielF) + specular * dielF;
  }
  if (metallic > 0.0f) metal = iblGgxFresnel(ndv, roughness, baseColor, fab) * specular;
  return dielectric * (1.0f - metallic) + metal * metallic;
}
KOKKOS_INLINE_FUNCTION float3 iblShade(const EnvironmentGPU& e, float3 n, float3 v, float3 baseColor, float metallic,
                                       const IblRough& rough, float occlusion, float occlusionStrength = 1.0f) {
  const float3 color = iblLight(e, n, v, baseColor, metallic, rough);
  return color * (1.0f + occlusionStrength * (occlusion - 1.0f));
}
KOKKOS_INLINE_FUNCTION float3 iblShade(const EnvironmentGPU& e, float3 n, float3 v, float3 baseColor, float metallic,
                                       float roughness, float occlusion, float occlusionStrength = 1.0f) {
  return iblShade(e, n, v, baseColor, metallic, iblRough(e, roughness), occlusion, occlusionStrength);
}

// The environment seen along view direction `dir` (world space, from the
// eye), blurred as the reference's background is (backgroundLod).
KOKKOS_INLINE_FUNCTION float3 envBackground(const EnvironmentGPU& e, float3 dir) {
  return rgb3(cubeTrilinear(e.specular, e.levelOffset, e.faceSize, e.mipCount, envRotate(e, dir), e.backgroundLod)) *
         e.intensity;
}

// The background at pixel (px, py) (from the left and the top) of the image
// `rays` was made for (envViewRays, environment.h).
KOKKOS_INLINE_FUNCTION float3 envBackgroundAt(const EnvironmentGPU& e, const EnvViewRays& rays, int32_t px,
                                              int32_t py) {
  return envBackground(e, normalize(rays.d00 + rays.dx * float(px) + rays.dy * float(py)));
}

}  // namespace rast
