// The colour film's encodings, in one place: the sRGB transfer curve (exact, in
// double, for building tables on the host; table-driven in kernels so every
// backend produces the same bytes) and RGBA8 packing (R in the low byte).
//
// Kernels shade linear light. It becomes bytes in exactly one of two ways:
// the direct path packs each pixel as it is shaded (packSrgb8, when nothing
// needs the frame in float), or the float film (FrameBuffers::hdr) runs the
// post chain and then its one encoder (core/post/encode.cpp) packs it.
#pragma once

#include "base/vec.h"

#include <vector>

namespace rast {

// Exact curve (IEC 61966-2-1), host side.
double srgbDecode(double encoded);  // [0,1] encoded -> linear
double srgbEncode(double linear);   // linear -> [0,1] encoded (clamped)
uint32_t srgbEncodeByte(double linear);  // rounded to the nearest byte

// Tables: the decode table is uploaded with the scene (DeviceScene::srgbToLinear),
// the encoder's as srgbEncodePacked (DeviceScene::srgbEncodePacked).
std::vector<float> srgbDecodeTable();      // 256 entries: byte -> linear
// kSrgbEncodeTableSize entries: 256 decision thresholds (byte b encodes
// linear values in [t(b), t(b+1))), +inf at 256, then kSrgbBuckets starting
// bytes (see encodeSrgb8).
std::vector<float> srgbEncodeThresholds();
// kSrgbBuckets entries for encodeSrgb8Packed, from srgbEncodeThresholds().
std::vector<uint32_t> srgbEncodePacked();

// encodeSrgb8's buckets: floats in [2^-13, 1) by exponent and top 7 mantissa
// bits (13 octaves of 128). Each holds the byte its lower end encodes to. A
// bucket is narrower than the gap between two thresholds there (width/gap is
// about 0.875 c^0.417 < 1), so it holds at most one: a value's byte is its
// bucket's, or one more. Below 2^-13 every value encodes to 0 (t(1) is
// about 1.5e-4).
constexpr uint32_t kSrgbBucketShift = 16;                   // keeps exponent + 7 mantissa bits
constexpr uint32_t kSrgbBucketFirst = (127u - 13u) << 7;    // 2^-13 >> kSrgbBucketShift
constexpr uint32_t kSrgbBuckets = 13u << 7;                 // up to 1.0 (exclusive)
constexpr uint32_t kSrgbBucketBase = 257;                   // first bucket entry in the table
constexpr uint32_t kSrgbEncodeTableSize = kSrgbBucketBase + kSrgbBuckets;
constexpr float kSrgbBucketMin = 1.0f / 8192.0f;            // 2^-13

// Linear [0,1] -> sRGB-encoded byte: the largest b with t(b) <= c over the
// 256 decision thresholds (computed in double on the host), i.e. the same
// bytes on every backend and as a binary search over them, found from the
// bucket of c's float bits and one comparison (an eight-step binary search,
// dependent and mispredicted, cost half of a simple frame's shading on the
// CPU). NaN and negatives encode as 0, values from 1.0 up as 255.
template <class Table>
KOKKOS_INLINE_FUNCTION uint32_t encodeSrgb8(float c, const Table& t) {
  if (!(c >= kSrgbBucketMin)) return 0;
  if (c >= 1.0f) return 255;
  const uint32_t b = uint32_t(t(kSrgbBucketBase + (floatBits(c) >> kSrgbBucketShift) - kSrgbBucketFirst));
  return b + (t(b + 1) <= c ? 1u : 0u);
}

// encodeSrgb8 without branches (selects only), for loops the compiler
// vectorizes with gathers (AVX2): the same bytes for every input.
KOKKOS_INLINE_FUNCTION uint32_t encodeSrgb8Flat(float c, const float* t) {
  const int32_t k = int32_t(floatBits(c) >> kSrgbBucketShift) - int32_t(kSrgbBucketFirst);
  const int32_t k1 = k > 0 ? k : 0;  // any bucket for values out of range: the result is selected away
  const int32_t k2 = k1 < int32_t(kSrgbBuckets) - 1 ? k1 : int32_t(kSrgbBuckets) - 1;
  const int32_t b = int32_t(t[kSrgbBucketBase + k2]);
  const int32_t r = b + (t[b + 1] <= c ? 1 : 0);  // t(b + 1) is at most t(256) = +inf
  return uint32_t(c >= 1.0f ? 255 : (c >= kSrgbBucketMin ? r : 0));  // NaN, negatives, -0: 0
}

// encodeSrgb8 with one table read instead of two, for the CPU's span loops
// (core/shade_spans.h), where each read is a gather: each bucket's entry
// (srgbEncodePacked) holds its starting byte b (bits 17 up) and the low 16
// bits of t(b + 1) when that threshold lies in the bucket (same upper bits),
// else 0x10000. t(b + 1) <= c then compares the low bits only. The same bytes
// for every input.
// Split in two so that a caller can issue its channels' reads together
// (packSrgb8Packed): the entry's index, always in the table, and the byte.
KOKKOS_INLINE_FUNCTION uint32_t srgbPackedIndex(float c) {
  const int32_t k = int32_t(floatBits(c) >> kSrgbBucketShift) - int32_t(kSrgbBucketFirst);
  const int32_t k1 = k > 0 ? k : 0;  // any bucket for values out of range: the result is selected away
  return uint32_t(k1 < int32_t(kSrgbBuckets) - 1 ? k1 : int32_t(kSrgbBuckets) - 1);
}
KOKKOS_INLINE_FUNCTION uint32_t srgbFromPacked(float c, uint32_t e) {
  const int32_t r = int32_t(e >> 17) + (int32_t(floatBits(c) & 0xffffu) >= int32_t(e & 0x1ffffu) ? 1 : 0);
  return uint32_t(c >= 1.0f ? 255 : (c >= kSrgbBucketMin ? r : 0));  // NaN, negatives, -0: 0
}
KOKKOS_INLINE_FUNCTION uint32_t encodeSrgb8Packed(float c, const uint32_t* packed) {
  return srgbFromPacked(c, packed[srgbPackedIndex(c)]);
}

// Linear [0,1] -> sRGB-encoded byte, with the exact piecewise curve in float
// (host values such as the background; kernels use the table).
KOKKOS_INLINE_FUNCTION uint32_t linearToSrgb8(float c) {
  c = clamp01(c);
  const float s = c <= 0.0031308f ? c * 12.92f : 1.055f * ::powf(c, 1.0f / 2.4f) - 0.055f;
  return uint32_t(s * 255.0f + 0.5f);
}

// (mulRn, addRn: the same byte wherever it is compiled.)
KOKKOS_INLINE_FUNCTION uint32_t unorm8(float v) { return uint32_t(addRn(mulRn(clamp01(v), 255.0f), 0.5f)); }

// Light: sRGB-encoded colour, linear alpha.
template <class Table>
KOKKOS_INLINE_FUNCTION uint32_t packSrgb8(float4 c, const Table& t) {
  return encodeSrgb8(c.x, t) | encodeSrgb8(c.y, t) << 8 | encodeSrgb8(c.z, t) << 16 | unorm8(c.w) << 24;
}

// packSrgb8 from the packed table, the three reads issued before any is used:
// on a GPU each is a trip to the L1 cache, and encodeSrgb8's two dependent
// reads per channel, one channel after the other, were a fifth of the per-pixel
// kernel's stalls (Nsight Compute, H100). The same bytes.
template <class Packed>
KOKKOS_INLINE_FUNCTION uint32_t packSrgb8Packed(float4 c, const Packed& packed) {
  const uint32_t er = packed(srgbPackedIndex(c.x)), eg = packed(srgbPackedIndex(c.y)), eb = packed(srgbPackedIndex(c.z));
  return srgbFromPacked(c.x, er) | srgbFromPacked(c.y, eg) << 8 | srgbFromPacked(c.z, eb) << 16 | unorm8(c.w) << 24;
}

// Data (the diagnostic shading modes: normals, uv, mip level): stored as raw
// bytes, opaque.
KOKKOS_INLINE_FUNCTION uint32_t packRaw8(float4 c) {
  return unorm8(c.x) | unorm8(c.y) << 8 | unorm8(c.z) << 16 | 0xff000000u;
}

// The float film's one encoding of a pixel (postEncode's, and the BLEND
// resolve's where it folds the encode in): light as sRGB bytes, the
// diagnostic modes' data (raw) as raw bytes; straight: the film holds
// premultiplied alpha and the bytes are straight alpha, as PNG stores them.
template <class Packed>
KOKKOS_INLINE_FUNCTION uint32_t encodeFilm(float4 c, const bool raw, const bool straight, const Packed& packed) {
  if (!straight) return raw ? packRaw8(c) : packSrgb8Packed(c, packed);
  const float a = c.w > 0.0f ? (c.w < 1.0f ? c.w : 1.0f) : 0.0f;  // NaN: 0
  if (a > 0.0f && a < 1.0f) c = float4{divRn(c.x, a), divRn(c.y, a), divRn(c.z, a), a};
  c.w = a;
  const uint32_t rgb = raw ? packRaw8(c) & 0xffffffu : packSrgb8Packed(c, packed) & 0xffffffu;
  return rgb | unorm8(a) << 24;
}

// A sample's result under BLEND layers (docs/transparency.md): what lies in
// front (premultiplied colour acc, transmittance T) over its opaque colour,
// the film's alpha composited the same way. Written with mulRn and addRn: the
// GPU's shading composites the uniform blocks' pixels as it shades them, in
// the bits of the resolve's passes.
KOKKOS_INLINE_FUNCTION float4 overOpaque(const float3 acc, float T, const float4 opq) {
  return float4{addRn(acc.x, mulRn(T, opq.x)), addRn(acc.y, mulRn(T, opq.y)), addRn(acc.z, mulRn(T, opq.z)),
                addRn(1.0f, -mulRn(T, addRn(1.0f, -opq.w)))};
}

// The inverse of the two packings (linear light, or raw values in [0,1]).
template <class Lut>
KOKKOS_INLINE_FUNCTION float4 unpackSrgb8(uint32_t c, const Lut& lut) {
  return {lut(c & 0xff), lut((c >> 8) & 0xff), lut((c >> 16) & 0xff), float(c >> 24) * (1.0f / 255.0f)};
}
KOKKOS_INLINE_FUNCTION float4 unpackRaw8(uint32_t c) {
  return {(c & 0xff) / 255.0f, ((c >> 8) & 0xff) / 255.0f, ((c >> 16) & 0xff) / 255.0f, 1.0f};
}

}  // namespace rast
