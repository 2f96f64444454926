// Window depth at the snapped corners of a raster triangle, taken from the
// plane of the triangle as it was given rather than from its corners' own
// depth.
//
// Coverage uses corners snapped to 1/256 pixel, and depth is interpolated over
// the snapped triangle (depthAt in raster_rules.h). With each corner keeping
// the depth of its unsnapped position, the interpolated plane is tilted by the
// snapping: the error is the depth gradient times up to 1/512 pixel, which on a
// thin triangle seen at a grazing angle reached 6.6e-5 (milk truck, eye inside
// the cab) while OpenGL (llvmpipe) stayed within 2.3e-6 (docs/determinism.md).
// Giving each snapped corner the depth the true plane has *there* makes the
// interpolation reproduce the true plane; coverage and the RasterTri layout are
// untouched.
//
//  * Unclipped triangles (the common path, float only): the vertex stage keeps
//    the snapping residual of each corner (SnapVert's 16 fractional bits), and
//    the setup moves each corner's depth along the true triangle's gradient.
//  * Clipped pieces: a corner made by clipping has its depth from a float
//    intersection (z and w interpolated separately, which cancels badly close to
//    the near plane), so every corner of every piece takes its depth from the
//    plane of the drawn triangle, computed once in double from its clip
//    coordinates. Clipping is rare; the double arithmetic stays off the common path.
//
// A corner's depth is only replaced where it is off the plane by more than
// kDepthKeep (2^-22, about 2.4e-7, four float steps just below depth 1). Nearly
// every triangle is far from that, so its bits stay what they were: depth ties
// between neighbouring triangles (which meet at equal depth up to the last bit)
// resolve exactly as before, and primitive ids only change where the old depth
// was really wrong.
#pragma once

#include "pipeline/data/gpu_types.h"

namespace rast {

constexpr float kDepthKeep = 1.0f / float(1 << 22);

// SnapVert coordinates carry kFineBits fractional bits: the snapped position
// (kSubBits, see raster_rules.h) plus the rounding residual. |x| stays below
// 2^15 pixels (guard band), so 2^31 still holds it.
constexpr int kFineBits = 16;
constexpr int kFineShift = kFineBits - 8;  // 8 = kSubBits
constexpr int32_t kFineHalf = 1 << (kFineShift - 1);

// Snapped coordinate (1/256 pixel) of a fine coordinate, and the residual
// (unsnapped - snapped) in 1/65536 pixel, in [-128, 127]. The shift of a
// negative value is arithmetic (floor) on every compiler rast supports.
KOKKOS_INLINE_FUNCTION int32_t fineToSnapped(int32_t f) { return (f + kFineHalf) >> kFineShift; }
KOKKOS_INLINE_FUNCTION int32_t fineResidual(int32_t f) { return f - fineToSnapped(f) * (1 << kFineShift); }

// v: the unsnapped coordinate in 1/256 pixel; snapped = floor(v + 0.5) exactly
// as before residuals were kept, so coverage does not change.
KOKKOS_INLINE_FUNCTION int32_t fineCoord(float v) {
  const float snapped = ::floorf(v + 0.5f);
  const float r = (v - snapped) * float(1 << kFineShift);  // exact: v - snapped is representable
  int32_t q = int32_t(::floorf(r + 0.5f));
  q = q > kFineHalf - 1 ? kFineHalf - 1 : q;  // +half would read back as the next snapped value
  return int32_t(snapped) * (1 << kFineShift) + q;
}

// Moves the corner depths t.z of a triangle whose snapped corners are in t.x,
// t.y (any orientation) to the plane through the unsnapped corners (snapped +
// residual rx, ry in 1/65536 pixel). In 1/256-pixel units throughout. The
// snapped area is exact; the unsnapped one is that plus terms of the residuals,
// each accurate to a float rounding of itself, so slivers keep their precision.
// A triangle that snapping fattens more than four times keeps its depths: its
// true plane is too steep to extrapolate to the snapped corners.
KOKKOS_INLINE_FUNCTION void depthAtSnappedCorners(RasterTri& t, const int32_t (&rx)[3], const int32_t (&ry)[3]) {
  const int64_t e1x = int64_t(t.x[1]) - t.x[0], e1y = int64_t(t.y[1]) - t.y[0];
  const int64_t e2x = int64_t(t.x[2]) - t.x[0], e2y = int64_t(t.y[2]) - t.y[0];
  const int64_t areaS = e1x * e2y - e2x * e1y;
  if (areaS == 0) return;
  const float s = 1.0f / float(1 << kFineShift);
  float r[3][2];
  for (int i = 0; i < 3; ++i) {
    r[i][0] = float(rx[i]) * s;
    r[i][1] = float(ry[i]) * s;
  }
  const float p1x = r[1][0] - r[0][0], p1y = r[1][1] - r[0][1];  // exact: multiples of 1/256 below 1
  const float p2x = r[2][0] - r[0][0], p2y = r[2][1] - r[0][1];
  const float f1x = float(e1x), f1y = float(e1y), f2x = float(e2x), f2y = float(e2y);
  const float dA = (f1x * p2y + p1x * f2y + p1x * p2y) - (f2x * p1y + p2x * f1y + p2x * p1y);
  const float areaS_f = float(areaS), areaT = areaS_f + dA;
  if (!(areaS_f > 0.0f ? areaT >= 0.25f * areaS_f : areaT <= 0.25f * areaS_f)) return;
  const float E1x = f1x + p1x, E1y = f1y + p1y, E2x = f2x + p2x, E2y = f2y + p2y;
  const float dz1 = t.z[1] - t.z[0], dz2 = t.z[2] - t.z[0];
  const float inv = 1.0f / areaT;
  const float gx = (dz1 * E2y - dz2 * E1y) * inv, gy = (dz2 * E1x - dz1 * E2x) * inv;
  float z[3];
  for (int i = 0; i < 3; ++i) {
    const float d = gx * r[i][0] + gy * r[i][1];
    if (!isFinite(d)) return;
    z[i] = d > kDepthKeep || d < -kDepthKeep ? t.z[i] - d : t.z[i];
  }
  for (int i = 0; i < 3; ++i) t.z[i] = z[i];
}

// The depth plane of a drawn triangle from its clip coordinates, valid
// wherever the triangle projects (also where clipping cut it): clip points of
// the triangle satisfy n . (x, y, z, w) = 0, so window depth is affine in the
// window position. Built and evaluated in double (rare: clipped triangles only).
struct DepthPlane {
  double a = 0.0, b = 0.0, c = 0.0;  // depth = a X + b Y + c, X, Y in 1/256 pixel
  bool valid = false;

  KOKKOS_INLINE_FUNCTION DepthPlane() {}
  KOKKOS_INLINE_FUNCTION DepthPlane(const float4& p0, const float4& p1, const float4& p2, const Viewport& vp) {
    const double o[4] = {p0.x, p0.y, p0.z, p0.w};
    const double u[4] = {double(p1.x) - o[0], double(p1.y) - o[1], double(p1.z) - o[2], double(p1.w) - o[3]};
    const double v[4] = {double(p2.x) - o[0], double(p2.y) - o[1], double(p2.z) - o[2], double(p2.w) - o[3]};
    // n_j = (-1)^j det(o, u, v without column j): orthogonal to o, u, v.
    const double nx = det3(o, u, v, 1, 2, 3), ny = -det3(o, u, v, 0, 2, 3), nz = det3(o, u, v, 0, 1, 3),
                 nw = -det3(o, u, v, 0, 1, 2);
    if (!(nz != 0.0)) return;
    // ndc z = -(nx X_ndc + ny Y_ndc + nw) / nz; X_ndc = X / (256 hw) - 1; depth = ndc z / 2 + 1/2.
    const double hw = 0.5 * double(vp.width), hh = 0.5 * double(vp.height);
    const double k = -0.5 / nz;
    a = k * nx / (256.0 * hw);
    b = k * ny / (256.0 * hh);
    c = 0.5 + k * (nw - nx - ny);
    valid = a - a == 0.0 && b - b == 0.0 && c - c == 0.0;  // finite
  }
  KOKKOS_INLINE_FUNCTION static double det3(const double (&o)[4], const double (&u)[4], const double (&v)[4], int i,
                                             int j, int k) {
    return o[i] * (u[j] * v[k] - u[k] * v[j]) - o[j] * (u[i] * v[k] - u[k] * v[i]) + o[k] * (u[i] * v[j] - u[j] * v[i]);
  }
  KOKKOS_INLINE_FUNCTION double at(int32_t X, int32_t Y) const { return a * double(X) + b * double(Y) + c; }
};

// Every corner of a clipped piece takes the drawn triangle's plane depth.
KOKKOS_INLINE_FUNCTION void depthFromPlane(RasterTri& t, const DepthPlane& p) {
  if (!p.valid) return;
  float z[3];
  for (int i = 0; i < 3; ++i) {
    const double want = p.at(t.x[i], t.y[i]), d = want - double(t.z[i]);
    if (!(d - d == 0.0)) return;  // not finite
    z[i] = d > double(kDepthKeep) || d < -double(kDepthKeep) ? float(want) : t.z[i];
  }
  for (int i = 0; i < 3; ++i) t.z[i] = z[i];
}

}  // namespace rast
