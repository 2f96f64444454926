// Homogeneous clipping (Sutherland-Hodgman) of one triangle against the near
// and far planes and a guard band around the viewport.
//
// Only the near/far planes change what is visible. The guard-band planes lie far
// outside the viewport; they exist so that every vertex that reaches fixed-point
// snapping fits its integer range (see raster_rules.h), however large the
// triangle. Triangles inside all planes (the common case) pass through untouched.
#pragma once

#include "base/vec.h"

namespace rast {

struct ClipVert {
  float4 p;       // clip-space position
  float b1, b2;   // barycentrics in the source triangle (b0 = 1 - b1 - b2)
};

// Six planes can add one vertex each to a triangle (9); the slack absorbs a
// polygon made slightly non-convex by rounding, which can gain two per plane.
constexpr int kMaxClipVerts = 16;

// Signed distance to plane `k` (inside when >= 0). g is the guard band in
// normalised device units: |x/w| <= gx, |y/w| <= gy.
KOKKOS_INLINE_FUNCTION float planeDistance(int k, const float4& p, float gx, float gy) {
  switch (k) {
    case 0: return p.z + p.w;       // near: z >= -w
    case 1: return p.w - p.z;       // far:  z <= w
    case 2: return p.x + gx * p.w;  // guard band left
    case 3: return gx * p.w - p.x;  // guard band right
    case 4: return p.y + gy * p.w;  // guard band bottom
    default: return gy * p.w - p.y; // guard band top
  }
}

KOKKOS_INLINE_FUNCTION bool finite4(const float4& p) {
  return isFinite(p.x) && isFinite(p.y) && isFinite(p.z) && isFinite(p.w);
}

// Bit k set: the point is outside plane k (see planeDistance).
KOKKOS_INLINE_FUNCTION uint32_t clipCode(const float4& p, float gx, float gy) {
  uint32_t code = 0;
  for (int k = 0; k < 6; ++k)
    if (planeDistance(k, p, gx, gy) < 0.0f) code |= 1u << k;
  return code;
}

// Whether a triangle lies wholly beyond one side plane of the viewport itself
// (|x/w| <= 1, |y/w| <= 1; the side planes above are the guard band's, far
// outside it). Each plane's distance is linear in clip space, so the whole
// triangle is beyond it, and every part of it with w > 0 (all that is left
// after the near and far planes) projects outside the viewport: clipping it
// would give pieces that cover no pixel centre. A rounded distance is
// negative only where the exact one is.
KOKKOS_INLINE_FUNCTION bool outsideViewportSide(const float4& a, const float4& b, const float4& c) {
  for (int k = 2; k < 6; ++k)
    if (planeDistance(k, a, 1.0f, 1.0f) < 0.0f && planeDistance(k, b, 1.0f, 1.0f) < 0.0f &&
        planeDistance(k, c, 1.0f, 1.0f) < 0.0f)
      return true;
  return false;
}

// Clips the triangle in v[0..2] in place; returns the vertex count of the
// resulting convex polygon (0 when nothing is left, 3 when untouched).
//
// Each intersection is computed from the edge's inside vertex towards its
// outside vertex, whatever the edge's direction in this triangle. Two triangles
// sharing an edge therefore get bit-identical new vertices, and the shared edge
// stays watertight after clipping.
KOKKOS_INLINE_FUNCTION int clipTriangle(ClipVert (&v)[kMaxClipVerts], float gx, float gy) {
  if (!finite4(v[0].p) || !finite4(v[1].p) || !finite4(v[2].p)) return 0;
  uint32_t outAll = 0x3f, outAny = 0;
  for (int i = 0; i < 3; ++i) {
    const uint32_t code = clipCode(v[i].p, gx, gy);
    outAll &= code;
    outAny |= code;
  }
  if (outAll) return 0;      // wholly outside one plane
  if (!outAny) return 3;     // wholly inside: the common case

  // Each plane reads one buffer and writes the other (no copying back), and
  // each vertex's distance is computed once: on a GPU this runs in one
  // thread while its warp waits, through local memory.
  ClipVert tmp[kMaxClipVerts];
  ClipVert* src = v;
  ClipVert* dst = tmp;
  int n = 3;
  for (int k = 0; k < 6; ++k) {
    if (!(outAny & (1 << k))) continue;
    int m = 0;
    const float d0 = planeDistance(k, src[0].p, gx, gy);
    float da = d0;
    for (int i = 0; i < n; ++i) {
      const ClipVert& a = src[i];
      const ClipVert& b = src[i + 1 < n ? i + 1 : 0];
      const float db = i + 1 < n ? planeDistance(k, b.p, gx, gy) : d0;
      const bool ina = da >= 0.0f, inb = db >= 0.0f;
      if (m + 2 > kMaxClipVerts) return 0;  // unreachable for convex input; never overflow
      if (ina) dst[m++] = a;
      if (ina != inb) {
        const ClipVert& in = ina ? a : b;
        const ClipVert& out = ina ? b : a;
        const float din = ina ? da : db, dout = ina ? db : da;
        const float t = din / (din - dout);
        ClipVert r;
        r.p.x = in.p.x + t * (out.p.x - in.p.x);
        r.p.y = in.p.y + t * (out.p.y - in.p.y);
        r.p.z = in.p.z + t * (out.p.z - in.p.z);
        r.p.w = in.p.w + t * (out.p.w - in.p.w);
        r.b1 = in.b1 + t * (out.b1 - in.b1);
        r.b2 = in.b2 + t * (out.b2 - in.b2);
        dst[m++] = r;
      }
      da = db;
    }
    n = m;
    if (n < 3) return 0;
    ClipVert* const t = src;
    src = dst;
    dst = t;
  }
  if (src != v)
    for (int i = 0; i < n; ++i) v[i] = src[i];
  return n;
}

}  // namespace rast
