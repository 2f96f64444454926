// Minimal vector math usable inside kernels on every backend.
//
// GLM is used on the host (scene loading, camera set-up, in double precision);
// kernels use these plain structs so the same code compiles with g++, nvcc and
// hipcc without relying on a math library's device annotations.
#pragma once

#include <Kokkos_Core.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace rast {

struct float2 { float x, y; };
struct float3 { float x, y, z; };
struct float4 { float x, y, z, w; };

KOKKOS_INLINE_FUNCTION float3 make3(float x, float y, float z) { return {x, y, z}; }
KOKKOS_INLINE_FUNCTION float4 make4(float x, float y, float z, float w) { return {x, y, z, w}; }

KOKKOS_INLINE_FUNCTION float3 operator+(float3 a, float3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
KOKKOS_INLINE_FUNCTION float3 operator-(float3 a, float3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
KOKKOS_INLINE_FUNCTION float3 operator*(float3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
KOKKOS_INLINE_FUNCTION float3 operator*(float3 a, float3 b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
KOKKOS_INLINE_FUNCTION float dot(float3 a, float3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
KOKKOS_INLINE_FUNCTION float3 cross(float3 a, float3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
KOKKOS_INLINE_FUNCTION float3 normalize(float3 a) {
  const float l2 = dot(a, a);
  if (!(l2 > 0.0f)) return {0.0f, 0.0f, 0.0f};
  const float inv = 1.0f / ::sqrtf(l2);
  return a * inv;
}
KOKKOS_INLINE_FUNCTION float4 operator+(float4 a, float4 b) { return {a.x + b.x, a.y + b.y, a.z + b.z, a.w + b.w}; }
KOKKOS_INLINE_FUNCTION float4 operator*(float4 a, float s) { return {a.x * s, a.y * s, a.z * s, a.w * s}; }
KOKKOS_INLINE_FUNCTION float4 operator*(float4 a, float4 b) { return {a.x * b.x, a.y * b.y, a.z * b.z, a.w * b.w}; }

KOKKOS_INLINE_FUNCTION int32_t imin(int32_t a, int32_t b) { return a < b ? a : b; }
KOKKOS_INLINE_FUNCTION int32_t imax(int32_t a, int32_t b) { return a > b ? a : b; }
KOKKOS_INLINE_FUNCTION uint32_t imaxu(uint32_t a, uint32_t b) { return a > b ? a : b; }
KOKKOS_INLINE_FUNCTION float clamp01(float v) { return v < 0.0f ? 0.0f : (v > 1.0f ? 1.0f : v); }
// One IEEE multiply, add or division, never fused or approximated: the same
// bits in a translation unit that the CUDA build compiles with fused
// multiply-adds and fast division (the GPU's shading, CMakeLists.txt) as in
// every other, for arithmetic whose result another pass must reproduce (the
// film's composite and encoding, base/color.h). Host and HIP builds never
// contract (-ffp-contract=off).
KOKKOS_INLINE_FUNCTION float mulRn(float a, float b) {
#if defined(__CUDA_ARCH__)
  return __fmul_rn(a, b);
#else
  return a * b;
#endif
}
KOKKOS_INLINE_FUNCTION float addRn(float a, float b) {
#if defined(__CUDA_ARCH__)
  return __fadd_rn(a, b);
#else
  return a + b;
#endif
}
KOKKOS_INLINE_FUNCTION float divRn(float a, float b) {
#if defined(__CUDA_ARCH__)
  return __fdiv_rn(a, b);
#else
  return a / b;
#endif
}
KOKKOS_INLINE_FUNCTION bool isFinite(float v) {
  // True for finite values; false for NaN and +-Inf (NaN fails every comparison).
  return v - v == 0.0f;
}

// Column-major 4x4 matrix (OpenGL/GLM layout): m[col*4 + row].
struct mat4f { float m[16]; };
struct mat4d { double m[16]; };
struct mat3f { float m[9]; };

KOKKOS_INLINE_FUNCTION float4 mul(const mat4f& M, float3 p) {
  // Evaluated row by row in a fixed order with no fused multiply-add so that all
  // backends produce bit-identical clip coordinates (see docs/determinism.md).
  float4 r;
  r.x = M.m[0] * p.x + M.m[4] * p.y + M.m[8] * p.z + M.m[12];
  r.y = M.m[1] * p.x + M.m[5] * p.y + M.m[9] * p.z + M.m[13];
  r.z = M.m[2] * p.x + M.m[6] * p.y + M.m[10] * p.z + M.m[14];
  r.w = M.m[3] * p.x + M.m[7] * p.y + M.m[11] * p.z + M.m[15];
  return r;
}
KOKKOS_INLINE_FUNCTION float3 mulPoint(const mat4f& M, float3 p) {
  const float4 r = mul(M, p);
  return {r.x, r.y, r.z};
}
KOKKOS_INLINE_FUNCTION float3 mul(const mat3f& M, float3 v) {
  return {M.m[0] * v.x + M.m[3] * v.y + M.m[6] * v.z,
          M.m[1] * v.x + M.m[4] * v.y + M.m[7] * v.z,
          M.m[2] * v.x + M.m[5] * v.y + M.m[8] * v.z};
}

KOKKOS_INLINE_FUNCTION uint32_t floatBits(float f) {
  uint32_t u;
  memcpy(&u, &f, sizeof(u));
  return u;
}
KOKKOS_INLINE_FUNCTION float bitsFloat(uint32_t u) {
  float f;
  memcpy(&f, &u, sizeof(f));
  return f;
}

}  // namespace rast
