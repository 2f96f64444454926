// The exact window depth of a drawn triangle at a pixel centre, for checking a
// renderer's depth buffer: the view ray through the pixel centre intersected
// with the triangle's plane, in long double.
//
// The triangle is the one both renderers are handed: MVP = viewProj * model in
// double, rounded to float (as the vertex stage and glref do), times the float
// object-space positions. Each product of two floats is exact in double, so the
// clip coordinates here are exact to about 1e-16; everything the renderer adds
// after that (float clip coordinates, clipping, snapping, setup, interpolation)
// shows up as error. Independent of core/: only the scene, the camera and plain
// arithmetic.
#pragma once

#include "host/scene/camera.h"
#include "host/scene/scene.h"

#include <cmath>
#include <cstdint>
#include <vector>

namespace rast::test {

struct ClipTriangle {
  long double c[3][4];  // clip-space x, y, z, w of the three corners
};

// Clip-space corners of every drawn triangle, indexed by primitive id - 1.
inline std::vector<ClipTriangle> drawnTrianglesInClipSpace(const Scene& s, const glm::dmat4& viewProj) {
  std::vector<ClipTriangle> out;
  for (const Draw& d : s.draws) {
    float mvp[4][4];  // [column][row], summed in the vertex stage's order
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) {
        double acc = 0.0;
        for (int k = 0; k < 4; ++k) acc += viewProj[k][r] * d.model[c][k];
        mvp[c][r] = float(acc);
      }
    const MeshPrim& p = s.prims[d.prim];
    for (uint32_t t = 0; t < p.triCount; ++t) {
      ClipTriangle ct;
      for (int k = 0; k < 3; ++k) {
        const float3 v = s.positions[p.firstVertex + s.indices[3 * (p.firstTri + t) + k]];
        for (int r = 0; r < 4; ++r)
          ct.c[k][r] = (long double)mvp[0][r] * v.x + (long double)mvp[1][r] * v.y + (long double)mvp[2][r] * v.z +
                       (long double)mvp[3][r];
      }
      out.push_back(ct);
    }
  }
  return out;
}

// Window depth (glDepthRange(0, 1)) where the ray through window position
// (px, py) (pixels, y up) meets the triangle's plane. With P = c0 + b1 (c1 - c0)
// + b2 (c2 - c0), the ray condition P.x = ndcX P.w, P.y = ndcY P.w is two linear
// equations in b1, b2. Returns false when the plane contains the ray.
inline bool exactWindowDepth(const ClipTriangle& t, int width, int height, double px, double py, double& depth) {
  const long double nx = (long double)px / width * 2 - 1, ny = (long double)py / height * 2 - 1;
  long double f[3], g[3];
  for (int k = 0; k < 3; ++k) {
    f[k] = t.c[k][0] - nx * t.c[k][3];
    g[k] = t.c[k][1] - ny * t.c[k][3];
  }
  const long double a11 = f[1] - f[0], a12 = f[2] - f[0], a21 = g[1] - g[0], a22 = g[2] - g[0];
  const long double det = a11 * a22 - a12 * a21;
  if (det == 0) return false;
  const long double b1 = (-f[0] * a22 + g[0] * a12) / det, b2 = (-g[0] * a11 + f[0] * a21) / det;
  long double p[4];
  for (int r = 0; r < 4; ++r) p[r] = t.c[0][r] + b1 * (t.c[1][r] - t.c[0][r]) + b2 * (t.c[2][r] - t.c[0][r]);
  // Both renderers clamp to the depth range; a pixel centre a hair beyond the
  // near plane (covered through snapping) is exactly right at 0.
  const long double z = 0.5L + 0.5L * p[2] / p[3];
  depth = double(z < 0 ? 0 : z > 1 ? 1 : z);
  return true;
}

// Whether a triangle crosses the near plane (z = -w), i.e. the renderer clips it.
inline bool crossesNear(const ClipTriangle& t) {
  int out = 0;
  for (int k = 0; k < 3; ++k) out += t.c[k][2] + t.c[k][3] < 0 ? 1 : 0;
  return out > 0 && out < 3;
}

// Largest |depth - exact| over the pixels a renderer covered, with the
// triangle it says covers each pixel. ids and depth in the same row order.
// which: 0 every triangle, 1 only those crossing the near plane, 2 the others.
struct DepthError {
  double maxErr = 0.0, sumErr = 0.0;
  int64_t pixels = 0, maxX = -1, maxY = -1;
  uint32_t maxId = 0;
  double maxGot = 0.0, maxWant = 0.0;
};
inline DepthError depthError(const std::vector<ClipTriangle>& tris, int width, int height,
                             const std::vector<uint32_t>& idsBottomUp, const std::vector<float>& depthBottomUp,
                             int which = 0) {
  DepthError e;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const size_t i = size_t(y) * width + x;
      const uint32_t id = idsBottomUp[i];
      if (id == 0 || id > tris.size()) continue;
      if (which != 0 && crossesNear(tris[id - 1]) != (which == 1)) continue;
      double want;
      if (!exactWindowDepth(tris[id - 1], width, height, x + 0.5, y + 0.5, want)) continue;
      const double err = std::abs(double(depthBottomUp[i]) - want);
      ++e.pixels;
      e.sumErr += err;
      if (err > e.maxErr) {
        e.maxErr = err;
        e.maxX = x;
        e.maxY = y;
        e.maxId = id;
        e.maxGot = depthBottomUp[i];
        e.maxWant = want;
      }
    }
  return e;
}

}  // namespace rast::test
