// Points and lines: OpenGL's non-antialiased rasterization rules in exact
// fixed point, the items they are drawn from, and how their fragments enter the
// visibility buffer (docs/points-lines.md).
//
// Items. One key space numbers everything a point/line pass can draw, so that a
// fragment's visibility key says where it came from:
//   [0, L)                 the scene's line segments (glTF LINES, LINE_LOOP, LINE_STRIP)
//   [L, L+P)               the scene's points (glTF POINTS)
//   [L+P, L+P+3T)          triangle edges (polygon mode line, wireframe overlay): 3 per drawn triangle
//   [L+P+3T, L+P+6T)       triangle corners (polygon mode point): 3 per drawn triangle
// A fragment's key is visKey(depth, kLineFlag | item): the flag keeps item
// numbers apart from raster triangle indices, and at equal depth a triangle
// (flag clear) wins over a line, as the earlier draw wins in OpenGL.
//
// Rules (window space, y up, pixel (X, Y) centred at (X+0.5, Y+0.5), 1/256 pixel):
// * Lines of width 1: the diamond-exit rule. A pixel is lit when the segment
//   leaves its diamond |x - xc| + |y - yc| < 1/2, i.e. the exit point of the
//   line through the diamond lies in (start, end] along the segment. A line
//   exactly on a diamond corner counts as passing just below it (x-major) or
//   just left of it (y-major): the perturbation the GL spec allows, chosen as
//   Mesa's llvmpipe chooses it.
// * Wider lines: the parallelogram rule: pixel centres c with
//   start <= c < end along the major axis, and within [-w/2, w/2) of the line
//   along the minor axis.
// * Points of size s: pixel centres in [x - s/2, x + s/2) x [y - s/2, y + s/2).
// * Segments are clipped against near and far in clip space (the visible part
//   stays); the guard band keeps the fixed-point range, as for triangles. A
//   point outside near/far (or the guard band) is dropped, as GL clips points.
// Depth of a line fragment: window depth interpolated linearly along the major
// axis at the pixel centre; a point's depth is its vertex's.
#pragma once

#include "pipeline/data/device_scene.h"
#include "pipeline/data/line_pass.h"
#include "pipeline/rules/raster_rules.h"
#include "host/settings/render_settings.h"

namespace rast {

// SnapVert holds fine coordinates (depth_plane.h); points and lines work on
// the 1/256-pixel snapped positions, as the triangles' coverage does.
KOKKOS_INLINE_FUNCTION SnapVert toSnapped(SnapVert s) {
  s.x = fineToSnapped(s.x);
  s.y = fineToSnapped(s.y);
  return s;
}

// The segment (or point: a == b) an item draws, as drawn vertex indices.
struct LineSource {
  DView<LineGPU> lines, points;
  DView<DrawGPU> draws;
  DView<uint32_t> drawTriStart, indices;
  DView<SnapVert> snap;
  uint32_t numDraws;
  LinePass pass;

  // Drawn vertex of corner c (0..2) of drawn triangle t.
  KOKKOS_INLINE_FUNCTION uint32_t corner(uint32_t t, int c, uint32_t* d = nullptr) const {
    const uint32_t di = findRange(drawTriStart, numDraws, t);
    const DrawGPU& dr = draws(di);
    if (d) *d = di;
    return dr.dstVertex + indices(3 * (dr.srcTri + (t - dr.dstTri)) + uint32_t(c));
  }
  // False when the item is not drawn (a back face under culling).
  KOKKOS_INLINE_FUNCTION bool triangleDrawn(uint32_t t) const {
    if (!pass.cullBack) return true;
    uint32_t d;
    const uint32_t v0 = corner(t, 0, &d), v1 = corner(t, 1), v2 = corner(t, 2);
    const SnapVert a = toSnapped(snap(v0)), b = toSnapped(snap(v1)), c = toSnapped(snap(v2));
    // Culled as the fill would be; a triangle that needs clipping is kept (its
    // window-space orientation is not known without clipping it).
    if (snapCode(a) || snapCode(b) || snapCode(c)) return true;
    const int64_t area = int64_t(b.x - a.x) * int64_t(c.y - a.y) - int64_t(c.x - a.x) * int64_t(b.y - a.y);
    const bool frontCCW = draws(d).mirrored == 0;
    return area != 0 && (area > 0) == frontCCW;
  }
  KOKKOS_INLINE_FUNCTION bool lineItem(uint32_t k, uint32_t& a, uint32_t& b) const {
    if (k < pass.numLines) {
      a = lines(k).v0;
      b = lines(k).v1;
      return true;
    }
    const uint32_t e = k - pass.numLines, t = e / 3;
    const int c = int(e % 3);
    a = corner(t, c);
    b = corner(t, c == 2 ? 0 : c + 1);
    return triangleDrawn(t);
  }
  KOKKOS_INLINE_FUNCTION bool pointItem(uint32_t k, uint32_t& a) const {
    if (k < pass.numPoints) {
      a = points(k).v0;
      return true;
    }
    const uint32_t e = k - pass.numPoints, t = e / 3;
    a = corner(t, int(e % 3));
    return triangleDrawn(t);
  }
};

KOKKOS_INLINE_FUNCTION int64_t floorDiv64(int64_t a, int64_t b) {  // b > 0
  return a >= 0 ? a / b : -((-a + b - 1) / b);
}
KOKKOS_INLINE_FUNCTION int64_t ceilDiv64(int64_t a, int64_t b) { return -floorDiv64(-a, b); }

// A segment ready to rasterize, in coordinates where the major axis u
// increases from start a to end b (u = +-x or +-y in 1/256 pixel) and the minor
// axis v is x or y unchanged. Major pixel index P (centre 256 P + 128) maps
// back to the window pixel index sgn > 0 ? P : -P - 1.
struct LineRaster {
  int32_t ua, va, ub, vb;  // ub > ua, |vb - va| <= ub - ua
  int32_t xMajor, sgn;
  int32_t lo, hi;          // major pixel indices to visit (in the viewport), lo > hi: none
  int32_t minorLimit;      // viewport size along the minor axis
  float za, zb;
  int32_t width;           // 1/256 pixel
};

// Clips the segment between clip positions pa, pb against near, far and the
// guard band and snaps what is left. False when nothing is left or it has no
// length after snapping (a zero-length line draws nothing under diamond-exit).
KOKKOS_INLINE_FUNCTION bool setupLine(float4 pa, float4 pb, const Viewport& vp, float gx, float gy, int32_t width,
                                      LineRaster& r) {
  if (!finite4(pa) || !finite4(pb)) return false;
  float t0 = 0.0f, t1 = 1.0f;
  for (int k = 0; k < 6; ++k) {
    const float da = planeDistance(k, pa, gx, gy), db = planeDistance(k, pb, gx, gy);
    if (da < 0.0f && db < 0.0f) return false;
    if (da < 0.0f) {
      const float t = da / (da - db);
      t0 = t > t0 ? t : t0;
    } else if (db < 0.0f) {
      const float t = da / (da - db);
      t1 = t < t1 ? t : t1;
    }
  }
  if (!(t0 <= t1)) return false;
  auto lerp = [&](float t) {
    return float4{pa.x + t * (pb.x - pa.x), pa.y + t * (pb.y - pa.y), pa.z + t * (pb.z - pa.z), pa.w + t * (pb.w - pa.w)};
  };
  const float4 ca = t0 > 0.0f ? lerp(t0) : pa, cb = t1 < 1.0f ? lerp(t1) : pb;
  if (!(ca.w > 0.0f) || !(cb.w > 0.0f)) return false;
  const SnapVert a = toSnapped(snapVertex(ca, vp)), b = toSnapped(snapVertex(cb, vp));
  const int32_t dx = b.x - a.x, dy = b.y - a.y;
  if (dx == 0 && dy == 0) return false;
  const int32_t adx = dx < 0 ? -dx : dx, ady = dy < 0 ? -dy : dy;
  r.xMajor = adx >= ady ? 1 : 0;
  const int32_t ma = r.xMajor ? a.x : a.y, mb = r.xMajor ? b.x : b.y;
  r.sgn = mb > ma ? 1 : -1;
  r.ua = r.sgn * ma;
  r.ub = r.sgn * mb;
  r.va = r.xMajor ? a.y : a.x;
  r.vb = r.xMajor ? b.y : b.x;
  r.za = a.z;
  r.zb = b.z;
  r.width = width;
  const int32_t majorSize = r.xMajor ? vp.width : vp.height;
  r.minorLimit = r.xMajor ? vp.height : vp.width;
  // Candidates: centres from half a pixel before the start to the end (the
  // diamond's exit lies within half a pixel after its centre).
  int32_t lo = floorDiv(r.ua - kSubOne, kSubOne), hi = floorDiv(r.ub - kSubHalf, kSubOne);
  const int32_t vlo = r.sgn > 0 ? 0 : -majorSize, vhi = r.sgn > 0 ? majorSize - 1 : -1;
  r.lo = lo > vlo ? lo : vlo;
  r.hi = hi < vhi ? hi : vhi;
  return r.lo <= r.hi;
}

KOKKOS_INLINE_FUNCTION uint32_t lineSpans(const LineRaster& r) {
  return r.lo > r.hi ? 0u : uint32_t((r.hi - r.lo) / kLineSpan + 1);
}

// Calls emit(X, Y, depth) for each pixel the line lights in the major pixel
// columns p0..p1. The minor position steps exactly from column to column (one
// 64-bit division per call, not per column).
template <class Emit>
KOKKOS_INLINE_FUNCTION void lineColumns(const LineRaster& r, int32_t p0, int32_t p1, Emit&& emit) {
  const int64_t S = kSubOne;
  const int64_t du = int64_t(r.ub) - r.ua, dv = int64_t(r.vb) - r.va;
  const int64_t D = du * S;                   // one pixel along the minor axis, times du
  const int64_t stepN = dv * S;               // |stepN| <= D
  const float invDu = 1.0f / float(du);
  int64_t c = int64_t(p0) * S + kSubHalf;       // centre along the major axis
  int64_t N = int64_t(r.va) * du + dv * (c - r.ua);  // minor position of the line at c, times du
  // The pixel row whose diamond the line crosses at c; a line exactly on a
  // diamond corner (N a multiple of D) counts as passing just below it.
  int64_t Q = floorDiv64(N - 1, D);
  int64_t rem = N - Q * D;                    // in (0, D]
  const int64_t den1 = du + dv, den2 = du - dv;  // >= 0
  for (int32_t P = p0; P <= p1; ++P) {
    float t = float(c - r.ua) * invDu;
    t = t < 0.0f ? 0.0f : (t > 1.0f ? 1.0f : t);
    const float z = clamp01(r.za + t * (r.zb - r.za));
    const int32_t X0 = r.sgn > 0 ? P : -P - 1;
    if (r.width == kSubOne) {
      // Diamond-exit: the diamond in this column is the one whose vertical
      // (minor) diagonal the line crosses; the exit lies u = min(u1, u2) past
      // the centre (the line leaves through one of the two far sides).
      const int64_t E = rem - kSubHalf * du;  // (line - diamond centre) * du, in (-D/2, D/2]
      const int64_t num1 = kSubHalf * du - E, num2 = kSubHalf * du + E;
      auto exitWithin = [&](int64_t L) {  // exit u <= L
        return (den1 > 0 && num1 <= L * den1) || (den2 > 0 && num2 <= L * den2);
      };
      if (exitWithin(int64_t(r.ub) - c) && !exitWithin(int64_t(r.ua) - c) && Q >= 0 && Q < r.minorLimit) {
        if (r.xMajor) emit(X0, int32_t(Q), z); else emit(int32_t(Q), X0, z);
      }
    } else if (c >= r.ua && c < r.ub) {
      // Parallelogram: centres start <= c < end, minor centre within [-w/2, w/2).
      const int64_t den = 2 * D;
      int64_t q0 = ceilDiv64(2 * N - int64_t(r.width) * du - S * du, den);
      int64_t q1 = ceilDiv64(2 * N + int64_t(r.width) * du - S * du, den) - 1;
      q0 = q0 < 0 ? 0 : q0;
      q1 = q1 > r.minorLimit - 1 ? r.minorLimit - 1 : q1;
      for (int64_t q = q0; q <= q1; ++q) {
        if (r.xMajor) emit(X0, int32_t(q), z); else emit(int32_t(q), X0, z);
      }
    }
    c += S;
    N += stepN;
    rem += stepN;
    if (rem > D) {
      rem -= D;
      ++Q;
    } else if (rem <= 0) {
      rem += D;
      --Q;
    }
  }
}

template <class Emit>
KOKKOS_INLINE_FUNCTION void lineColumn(const LineRaster& r, int32_t P, Emit&& emit) {
  lineColumns(r, P, P, emit);
}

// A point ready to rasterize: the pixels [x0, x1] x [y0, y1] (in the viewport).
struct PointRaster {
  int32_t x0, x1, y0, y1;
  float z;
};

KOKKOS_INLINE_FUNCTION bool setupPoint(float4 p, const Viewport& vp, float gx, float gy, int32_t size, PointRaster& r) {
  if (!finite4(p) || clipCode(p, gx, gy) != 0 || !(p.w > 0.0f)) return false;
  const SnapVert s = toSnapped(snapVertex(p, vp));
  // Centres 256 X + 128 in [x - size/2, x + size/2), in doubled units.
  const int64_t den = 2 * int64_t(kSubOne);
  const int64_t x0 = ceilDiv64(2 * int64_t(s.x) - size - kSubOne, den), x1 = ceilDiv64(2 * int64_t(s.x) + size - kSubOne, den) - 1;
  const int64_t y0 = ceilDiv64(2 * int64_t(s.y) - size - kSubOne, den), y1 = ceilDiv64(2 * int64_t(s.y) + size - kSubOne, den) - 1;
  r.x0 = int32_t(x0 < 0 ? 0 : x0);
  r.y0 = int32_t(y0 < 0 ? 0 : y0);
  r.x1 = int32_t(x1 > vp.width - 1 ? vp.width - 1 : x1);
  r.y1 = int32_t(y1 > vp.height - 1 ? vp.height - 1 : y1);
  r.z = s.z;
  return r.x0 <= r.x1 && r.y0 <= r.y1;
}

// Depth a pass item's fragment competes with: the wireframe overlay is drawn on
// top (depth 0) or, hidden-line, pulled slightly towards the camera.
KOKKOS_INLINE_FUNCTION float overlayDepth(const LinePass& p, uint32_t key, float z) {
  if (key < p.numLines + p.numPoints || key >= p.numLines + p.numPoints + 3 * p.numTris || p.edges < 2) return z;
  if (p.edges == 2) return 0.0f;
  const float b = z - (1.0f - z) * kHiddenLineBias;
  return b > 0.0f ? b : 0.0f;
}

// Writes a fragment into every sample of pixel (X, Y).
KOKKOS_INLINE_FUNCTION void writeLineFragment(uint64_t* vis, int32_t width, int samples, int32_t X, int32_t Y, float z,
                                              uint32_t key) {
  const uint64_t k = visKey(z, kLineFlag | key);
  uint64_t* px = vis + (int64_t(Y) * width + X) * samples;
  for (int s = 0; s < samples; ++s)
    if (k < px[s]) Kokkos::atomic_fetch_min(&px[s], k);
}

// Shading of point and line fragments: unlit, the material's base colour times
// the vertex colour of the item's first vertex (flat). Edges of the wireframe
// overlay are black, so that they show over the shaded fill.
struct LineShade {
  DView<LineGPU> lines, points;
  DView<DrawGPU> draws;
  DView<uint32_t> drawTriStart, indices;
  DView<MaterialGPU> materials;
  DView<float4> colors;
  uint32_t numDraws;
  int32_t hasColor;
  LinePass pass;

  KOKKOS_INLINE_FUNCTION uint32_t primId(uint32_t key) const {
    const uint32_t L = pass.numLines, P = pass.numPoints, T = pass.numTris;
    if (key < L + P) return T + key + 1;  // segments, then points, after the triangles
    const uint32_t e = key - L - P;
    return (e < 3 * T ? e : e - 3 * T) / 3 + 1;  // edges and corners carry their triangle's id
  }
  KOKKOS_INLINE_FUNCTION float4 color(uint32_t key) const {
    const uint32_t L = pass.numLines, P = pass.numPoints, T = pass.numTris;
    int32_t material = -1;
    uint32_t src = 0;
    if (key < L + P) {
      const LineGPU& l = key < L ? lines(key) : points(key - L);
      material = l.material;
      src = l.src0;
    } else {
      uint32_t e = key - L - P;
      if (e < 3 * T && pass.edges >= 2) return float4{0.0f, 0.0f, 0.0f, 1.0f};
      if (e >= 3 * T) e -= 3 * T;
      const uint32_t t = e / 3;
      const DrawGPU& dr = draws(findRange(drawTriStart, numDraws, t));
      material = dr.material;
      src = dr.srcVertex + indices(3 * (dr.srcTri + (t - dr.dstTri)) + e % 3);
    }
    float4 c = material >= 0 ? materials(material).baseColor : float4{1.0f, 1.0f, 1.0f, 1.0f};
    if (hasColor) c = c * colors(src);
    return c;
  }
};

LineShade makeLineShade(const DeviceScene& s, const LineFrame& f);

// The point/line pass of a frame: after the triangles' raster method (which
// may write every pixel), before shading. Does nothing when the frame draws no
// points or lines.
struct FrameBuffers;
void rasterLinesAndPoints(const DeviceScene& s, FrameBuffers& f, const LinePass& pass);
LinePass makeLinePass(const DeviceScene& s, const RenderSettings& rs);

}  // namespace rast
