// The exact rasterisation rules every raster method shares: fixed-point
// snapping, integer edge functions, the top-left fill rule, the depth value at
// a pixel and the visibility key that resolves the depth test.
//
// Window space is OpenGL's: y up, pixel (x, y) centred at (x + 0.5, y + 0.5).
// Vertices are snapped to 1/256 pixel (kSubBits = 8). Edge functions are
// evaluated exactly in 64-bit integers at pixel centres, so whether a pixel is
// covered never depends on rounding, and two triangles sharing an edge neither
// both cover nor both miss a pixel on it.
//
// What only the visbuffer method needs (its 8x8 blocks, work hints, occluders
// and the rectangle depth test built on these rules) is in visbuffer_blocks.h.
#pragma once

#include "backends/tuning.h"
#include "pipeline/rules/clip.h"
#include "pipeline/rules/depth_plane.h"
#include "pipeline/data/gpu_types.h"

#include <type_traits>

namespace rast {

// kSubBits, kSubOne, kSubHalf: pipeline/data/gpu_types.h (the units of SnapVert).
// Snapped coordinates stay within +-2^15 pixels (2^23 in fixed point), so edge
// function products stay below 2^48 and sums below 2^50: exact in int64.
constexpr int32_t kMaxWindowCoord = 1 << 15;
constexpr int32_t kMaxFramebufferSide = 16384;

// Guard band in NDC units for a viewport side of `size` pixels, chosen so that
// clipped vertices land inside +-kMaxWindowCoord pixels, with margin for rounding.
inline float guardBand(int size) { return float(2 * (kMaxWindowCoord - 64)) / float(size) - 1.0f; }

KOKKOS_INLINE_FUNCTION int32_t floorDiv(int32_t a, int32_t b) {  // b > 0
  return a >= 0 ? a / b : -((-a + b - 1) / b);
}

KOKKOS_INLINE_FUNCTION SnapVert snapVertex(const float4 p, const Viewport& vp) {
  const float hw = 0.5f * float(vp.width), hh = 0.5f * float(vp.height);
  const float iw = 1.0f / p.w;
  const float nx = p.x / p.w, ny = p.y / p.w, nz = p.z / p.w;
  const float wx = nx * hw + hw, wy = ny * hh + hh;
  SnapVert s;
  s.x = fineCoord(wx * float(kSubOne));  // snapped to 1/256 pixel, plus the residual (depth_plane.h)
  s.y = fineCoord(wy * float(kSubOne));
  s.z = nz * 0.5f + 0.5f;
  s.invW = iw;
  return s;
}

// Bits of a vertex's clip code beyond the six planes of clip.h.
constexpr uint32_t kCodeNonFinite = 1u << 6;
constexpr uint32_t kCodeWNotPositive = 1u << 7;

// The vertex stage's record for one drawn vertex: snapped when it lies inside
// every clipping plane with w > 0; otherwise x, y, z are unused and invW holds
// minus its clip code (planes outside, non-finite, w <= 0), which the setup
// needs to classify the triangle without reloading clip coordinates.
KOKKOS_INLINE_FUNCTION SnapVert snapOrFlag(const float4 p, const Viewport& vp, float gx, float gy) {
  uint32_t code = kCodeNonFinite;
  if (finite4(p)) code = clipCode(p, gx, gy) | (p.w > 0.0f ? 0u : kCodeWNotPositive);
  if (code == 0) return snapVertex(p, vp);
  SnapVert s{0, 0, 0.0f, -float(code)};
  return s;
}

KOKKOS_INLINE_FUNCTION uint32_t snapCode(const SnapVert& s) { return s.invW > 0.0f ? 0u : uint32_t(-s.invW); }

// The pixels of a counter-clockwise RasterTri's box: those with a sample point
// x*256 + 128 + offset inside its corners' range (for a single sample: the
// pixel centres inside the box), clamped to the viewport; empty when min > max.
KOKKOS_INLINE_FUNCTION void pixelBox(const RasterTri& t, const Viewport& vp, int32_t& minX, int32_t& maxX,
                                     int32_t& minY, int32_t& maxY) {
  int32_t lx = t.x[0], hx = t.x[0], ly = t.y[0], hy = t.y[0];
  for (int i = 1; i < 3; ++i) {
    lx = t.x[i] < lx ? t.x[i] : lx; hx = t.x[i] > hx ? t.x[i] : hx;
    ly = t.y[i] < ly ? t.y[i] : ly; hy = t.y[i] > hy ? t.y[i] : hy;
  }
  const SamplePattern& sp = vp.samples;
  minX = floorDiv(lx - kSubHalf - sp.maxX + kSubOne - 1, kSubOne);
  maxX = floorDiv(hx - kSubHalf - sp.minX, kSubOne);
  minY = floorDiv(ly - kSubHalf - sp.maxY + kSubOne - 1, kSubOne);
  maxY = floorDiv(hy - kSubHalf - sp.minY, kSubOne);
  minX = minX < 0 ? 0 : minX;
  minY = minY < 0 ? 0 : minY;
  maxX = maxX > vp.width - 1 ? vp.width - 1 : maxX;
  maxY = maxY > vp.height - 1 ? vp.height - 1 : maxY;
}

// Completes a RasterTri whose t.x, t.y, t.z, t.invW, t.bary hold the snapped
// corners. Returns false when it is culled, degenerate after snapping, or
// covers no pixel centre of the viewport.
//   frontCCW: counter-clockwise triangles (in window space) face the viewer.
KOKKOS_INLINE_FUNCTION bool finishTriangle(const Viewport& vp, bool cullBack, bool frontCCW, uint32_t prim,
                                           RasterTri& t) {
  const int64_t area = int64_t(t.x[1] - t.x[0]) * int64_t(t.y[2] - t.y[0]) -
                       int64_t(t.x[2] - t.x[0]) * int64_t(t.y[1] - t.y[0]);
  if (area == 0) return false;
  const bool ccw = area > 0;
  if (cullBack && ccw != frontCCW) return false;
  if (!ccw) {  // make it counter-clockwise so "inside" means all edge functions positive
    auto sw = [](auto& p, auto& q) { auto tmp = p; p = q; q = tmp; };
    sw(t.x[1], t.x[2]); sw(t.y[1], t.y[2]); sw(t.z[1], t.z[2]); sw(t.invW[1], t.invW[2]);
    sw(t.bary[1][0], t.bary[2][0]); sw(t.bary[1][1], t.bary[2][1]);
  }
  const int64_t area2 = ccw ? area : -area;
  t.invArea = 1.0f / float(area2);
  pixelBox(t, vp, t.minX, t.maxX, t.minY, t.maxY);
  t.prim = prim;
  return t.minX <= t.maxX && t.minY <= t.maxY;
}

// Alpha classes (docs/transparency.md): the raster triangles of MASK and BLEND
// materials are drawn by passes of their own (pipeline/blend/), not by the
// raster methods. The setup marks them with an empty box, which every method
// skips (no pixel, block, bin or occluder), holding the class in maxY; their
// passes recompute the box with pixelBox.
enum AlphaClass : int32_t { kAlphaOpaque = 0, kAlphaMask = 1, kAlphaBlend = 2 };
KOKKOS_INLINE_FUNCTION void markAlphaClass(RasterTri& t, int32_t cls) {
  t.minX = 0;
  t.minY = 0;
  t.maxX = -1;
  t.maxY = -1 - cls;
}
KOKKOS_INLINE_FUNCTION int32_t alphaClassOf(const RasterTri& t) {
  return t.maxX == -1 && t.minX == 0 && t.maxY < -1 ? -1 - t.maxY : int32_t(kAlphaOpaque);
}

KOKKOS_INLINE_FUNCTION void putCorner(RasterTri& t, int i, const SnapVert& s, float b1, float b2) {
  t.x[i] = fineToSnapped(s.x); t.y[i] = fineToSnapped(s.y); t.z[i] = s.z; t.invW[i] = s.invW;
  t.bary[i][0] = b1; t.bary[i][1] = b2;
}

// Whether a vertex's window position lies within +-kMaxWindowCoord pixels, so
// that snapping it to fixed point cannot overflow int32 (undefined behaviour;
// found by scripts/fuzz/fuzz_cli.sh). Clipped vertices land inside the guard band
// up to rounding; a projective model matrix can leave w so small that one
// does not, and the piece is then dropped. False for NaN too.
KOKKOS_INLINE_FUNCTION bool snappable(const float4 p, const Viewport& vp) {
  const float hw = 0.5f * float(vp.width), hh = 0.5f * float(vp.height);
  const float wx = (p.x / p.w) * hw + hw, wy = (p.y / p.w) * hh + hh, lim = float(kMaxWindowCoord);
  return wx > -lim && wx < lim && wy > -lim && wy < lim;
}

// Snaps a clip-space triangle to a RasterTri (see finishTriangle). Corner
// depths are those of the corners themselves; the setup replaces them by the
// drawn triangle's plane (depth_plane.h).
KOKKOS_INLINE_FUNCTION bool setupTriangle(const ClipVert& a, const ClipVert& b, const ClipVert& c, const Viewport vp,
                                          bool cullBack, bool frontCCW, uint32_t prim, RasterTri& t) {
  const ClipVert* v[3] = {&a, &b, &c};
  for (int i = 0; i < 3; ++i) {
    if (!(v[i]->p.w > 0.0f) || !snappable(v[i]->p, vp)) return false;
    putCorner(t, i, snapVertex(v[i]->p, vp), v[i]->b1, v[i]->b2);
  }
  return finishTriangle(vp, cullBack, frontCCW, prim, t);
}

// Edge functions of a RasterTri as E_i(X, Y) = A_i * X + B_i * Y + C_i over
// integer pixel coordinates, E_i > 0 inside. Edge i runs from vertex i to i+1;
// E_0 is the weight of vertex 2, E_1 of vertex 0, E_2 of vertex 1.
struct Edges {
  int64_t A[3], B[3], C[3];
  int64_t bias[3];  // 1 on top-left edges, else 0: inside means E_i + bias_i > 0
  // On GPUs, the same functions as products of 32-bit factors, which eval()
  // uses there:
  //   E_i(X, Y) = dx_i (256 Y + cy_i) + ndy_i (256 X + cx_i),
  // ndy_i = -dy_i, cx_i = 128 - x_i, cy_i = 128 - y_i. Snapped coordinates lie
  // within +-2^23 (kMaxWindowCoord in fixed point) and pixel coordinates below
  // 2^14, so every factor fits in 32 bits and each product (below 2^48) is
  // one widening multiply: A_i X + B_i Y + C_i with 64-bit coefficients took
  // about three times the instructions, and a GPU's item and shading set-ups
  // evaluate edges a dozen times (the same values). A CPU multiplies 64-bit
  // integers in one instruction; there the factors (fields and evaluation)
  // cost the million one-pixel triangles of `tiny` 5-10% (its raster and
  // shading set up a triangle a pixel), so host backends keep A X + B Y + C.
  struct Factors {
    int32_t dx[3], ndy[3], cx[3], cy[3];
    // E_i at (ox, oy) 1/256 pixel from the centre of pixel (X, Y), the
    // offset folded into the factors (offsets within +-2 pixels, as the
    // derivatives' neighbours take, keep them in 32 bits).
    KOKKOS_INLINE_FUNCTION int64_t sample(int i, int32_t X, int32_t Y, int32_t ox, int32_t oy) const {
      return int64_t(dx[i]) * int64_t(kSubOne * Y + cy[i] + oy) + int64_t(ndy[i]) * int64_t(kSubOne * X + cx[i] + ox);
    }
    KOKKOS_INLINE_FUNCTION int64_t eval(int i, int32_t X, int32_t Y) const { return sample(i, X, Y, 0, 0); }
  };
  struct NoFactors {};
  std::conditional_t<kOnDevice, Factors, NoFactors> gpu;
  KOKKOS_INLINE_FUNCTION static Factors factorsOf(const RasterTri& t) {
    Factors g;
    for (int i = 0; i < 3; ++i) {
      const int j = i == 2 ? 0 : i + 1;
      g.dx[i] = t.x[j] - t.x[i];
      g.ndy[i] = t.y[i] - t.y[j];
      g.cx[i] = kSubHalf - t.x[i];
      g.cy[i] = kSubHalf - t.y[i];
    }
    return g;
  }

  KOKKOS_DEFAULTED_FUNCTION Edges() = default;
  KOKKOS_INLINE_FUNCTION explicit Edges(const RasterTri& t) {
    for (int i = 0; i < 3; ++i) {
      const int j = i == 2 ? 0 : i + 1;
      const int64_t dx = int64_t(t.x[j]) - t.x[i], dy = int64_t(t.y[j]) - t.y[i];
      // E(px, py) = dx * (py - y_i) - dy * (px - x_i), sampled at px = 256 X + 128.
      A[i] = -dy * kSubOne;
      B[i] = dx * kSubOne;
      C[i] = dx * (kSubHalf - int64_t(t.y[i])) - dy * (kSubHalf - int64_t(t.x[i]));
      // Top-left rule, "top" as the image is stored and shown (rows top first,
      // as in D3D and in Mesa's llvmpipe under OpenGL): a pixel centre exactly
      // on an edge belongs to the triangle only for a left edge (going down in
      // our y-up window space) or a top edge of the image, which in y-up space
      // is the horizontal edge with the interior above it (going right).
      // The bias turns that into a plain "> 0" test; it must not enter the
      // weights, which for a sub-pixel triangle it would skew enough to push
      // depth past the far plane.
      bias[i] = (dy < 0 || (dy == 0 && dx > 0)) ? 1 : 0;
    }
    setFactors(gpu, t);
  }
  KOKKOS_INLINE_FUNCTION int64_t eval(int i, int32_t X, int32_t Y) const { return evalWith(gpu, i, X, Y); }
  // B_i dY, the change of E_i over dY rows (on a GPU, B_i = 256 dx_i: one
  // widening multiply).
  KOKKOS_INLINE_FUNCTION int64_t rows(int i, int32_t dY) const { return rowsWith(gpu, i, dY); }
  // The two forms, chosen by the type of `gpu` (the other is not compiled).
  KOKKOS_INLINE_FUNCTION static void setFactors(Factors& g, const RasterTri& t) { g = factorsOf(t); }
  KOKKOS_INLINE_FUNCTION static void setFactors(NoFactors&, const RasterTri&) {}
  KOKKOS_INLINE_FUNCTION int64_t evalWith(const Factors& g, int i, int32_t X, int32_t Y) const { return g.eval(i, X, Y); }
  KOKKOS_INLINE_FUNCTION int64_t evalWith(const NoFactors&, int i, int32_t X, int32_t Y) const {
    return A[i] * X + B[i] * Y + C[i];
  }
  KOKKOS_INLINE_FUNCTION int64_t rowsWith(const Factors& g, int i, int32_t dY) const {
    return int64_t(g.dx[i]) * int64_t(kSubOne * dY);
  }
  KOKKOS_INLINE_FUNCTION int64_t rowsWith(const NoFactors&, int i, int32_t dY) const { return B[i] * dY; }
  // The GPUs' form on any backend (tests compare the two).
  KOKKOS_INLINE_FUNCTION static int64_t factorEval(const RasterTri& t, int i, int32_t X, int32_t Y) {
    return factorsOf(t).eval(i, X, Y);
  }
  // Edge value at a sample offset (ox, oy) in 1/256 pixel from the pixel
  // centre, from the centre's value: A_i / 256 and B_i / 256 a 1/256 pixel,
  // on a GPU the factors ndy_i and dx_i (two widening multiplies where the
  // 64-bit coefficients take a division and a 64-bit multiply each).
  KOKKOS_INLINE_FUNCTION int64_t atSample(int i, int64_t centre, int32_t ox, int32_t oy) const {
    return centre + offsetWith(gpu, i, ox, oy);
  }
  // atSample(i, eval(i, X, Y), ox, oy), the same integer; on a GPU from the
  // factors with the offset folded in (Factors::sample), which took a fifth
  // of the instructions off the BLEND resolve's walk on the H100, whose
  // fragments each evaluate their three edges at their sample.
  KOKKOS_INLINE_FUNCTION int64_t sample(int i, int32_t X, int32_t Y, int32_t ox, int32_t oy) const {
    return sampleWith(gpu, i, X, Y, ox, oy);
  }
  KOKKOS_INLINE_FUNCTION int64_t offsetWith(const Factors& g, int i, int32_t ox, int32_t oy) const {
    return int64_t(g.ndy[i]) * int64_t(ox) + int64_t(g.dx[i]) * int64_t(oy);
  }
  KOKKOS_INLINE_FUNCTION int64_t offsetWith(const NoFactors&, int i, int32_t ox, int32_t oy) const {
    return (A[i] / kSubOne) * ox + (B[i] / kSubOne) * oy;
  }
  KOKKOS_INLINE_FUNCTION int64_t sampleWith(const Factors& g, int i, int32_t X, int32_t Y, int32_t ox, int32_t oy) const {
    return g.sample(i, X, Y, ox, oy);
  }
  KOKKOS_INLINE_FUNCTION int64_t sampleWith(const NoFactors& g, int i, int32_t X, int32_t Y, int32_t ox,
                                            int32_t oy) const {
    return evalWith(g, i, X, Y) + offsetWith(g, i, ox, oy);
  }
  KOKKOS_INLINE_FUNCTION bool inside(int64_t e0, int64_t e1, int64_t e2) const {
    return e0 + bias[0] > 0 && e1 + bias[1] > 0 && e2 + bias[2] > 0;
  }
};

// Whether no pixel centre of [x0, x1] x [y0, y1] is inside: some edge is not
// positive (with its bias) at all four corner centres. Edge functions are
// linear, so it is then not positive at any centre between: exact, no
// pixel is lost. Large triangles' bounding boxes are half outside them.
KOKKOS_INLINE_FUNCTION bool rectOutside(const Edges& e, int32_t x0, int32_t x1, int32_t y0, int32_t y1) {
  for (int i = 0; i < 3; ++i) {
    const int64_t b = e.bias[i];
    if (e.eval(i, x0, y0) + b <= 0 && e.eval(i, x1, y0) + b <= 0 && e.eval(i, x0, y1) + b <= 0 &&
        e.eval(i, x1, y1) + b <= 0)
      return true;
  }
  return false;
}

// Window depth at a covered pixel, from the exact (unbiased) edge values.
// Written as z0 + l1 (z1 - z0) + l2 (z2 - z0): exact on flat triangles and
// closer to how hardware interpolates depth than the three-term sum.
// DepthTerms holds the terms, for a loop over pixels to keep in registers:
// through a RasterTri reference a GPU reloaded the four values (and redid
// both differences) at every covered pixel, since the atomic minimum before
// might have changed them for all the compiler knew.
struct DepthTerms {
  float z0, d1, d2, ia;
  KOKKOS_INLINE_FUNCTION explicit DepthTerms(const RasterTri& t)
      : z0(t.z[0]), d1(t.z[1] - t.z[0]), d2(t.z[2] - t.z[0]), ia(t.invArea) {}
  KOKKOS_INLINE_FUNCTION float at(int64_t e0, int64_t e2) const { return clamp01(plane(e0, e2)); }
  // The same before clamping (the occluder bounds' corners).
  KOKKOS_INLINE_FUNCTION float plane(int64_t e0, int64_t e2) const {
    const float l1 = float(e2) * ia, l2 = float(e0) * ia;
    return z0 + (l1 * d1 + l2 * d2);
  }
};
KOKKOS_INLINE_FUNCTION float depthAt(const RasterTri& t, int64_t e0, int64_t /*e1*/, int64_t e2) {
  return DepthTerms(t).at(e0, e2);
}

// A triangle's depth range over its pixels, widened so that the rounding of
// depthAt() cannot leave it: the interpolation is a convex combination of the
// corner depths up to a few ulps of the terms involved. NaN gives [0, 1].
// The visibility-buffer raster skips 8x8 blocks with it (raster_visbuffer.cpp).
struct DepthBounds {
  float lo, hi;
};
KOKKOS_INLINE_FUNCTION DepthBounds depthBounds(const RasterTri& t) {
  const float a = t.z[0], b = t.z[1], c = t.z[2];
  if (!(a == a && b == b && c == c)) return {0.0f, 1.0f};
  const float mn = a < b ? (a < c ? a : c) : (b < c ? b : c), mx = a > b ? (a > c ? a : c) : (b > c ? b : c);
  const float margin = 1e-6f * (1.0f + (a < 0.0f ? -a : a) + (b < 0.0f ? -b : b) + (c < 0.0f ? -c : c));
  const float lo = mn - margin, hi = mx + margin;
  // Not (lo > 0): a NaN bound (infinite depths) must give 0 and 1 too.
  return {lo > 0.0f ? (lo < 1.0f ? lo : 1.0f) : 0.0f, hi < 1.0f ? (hi > 0.0f ? hi : 0.0f) : 1.0f};
}

// The visibility key: depth in the high word (non-negative floats order like
// their bits), raster triangle index + 1 in the low word. Taking the minimum
// resolves the depth test (LESS) and breaks ties towards the earlier triangle,
// as OpenGL's LESS does, independently of the order fragments arrive in.
KOKKOS_INLINE_FUNCTION uint64_t visKey(float depth, uint32_t rasterIndex) {
  return (uint64_t(floatBits(depth)) << 32) | uint64_t(rasterIndex + 1);
}
constexpr uint64_t kClearKey = uint64_t(0x3f800000u) << 32;  // depth 1.0, no triangle

// Barycentrics (b1, b2) in the drawn triangle at a point whose exact edge
// values in a raster triangle are E0, E1, E2: screen-space weights, made
// perspective-correct (attributes vary linearly in clip space, i.e. with
// weight l_k / w_k), then mapped through the raster triangle's corners
// (RasterTri::bary: clipping moved them). One function for the shade stage
// and the alpha test (pipeline/blend/), so that both get the same bits.
KOKKOS_INLINE_FUNCTION void drawnBarycentrics(int64_t E0, int64_t E1, int64_t E2, float invArea, const float (&invW)[3],
                                              const float (&corner)[3][2], bool perspective, float& b1, float& b2) {
  float w0 = float(E1) * invArea, w1 = float(E2) * invArea, w2 = float(E0) * invArea;
  if (perspective) {
    w0 *= invW[0];
    w1 *= invW[1];
    w2 *= invW[2];
  }
  const float sum = w0 + w1 + w2;
  if (sum != 0.0f && isFinite(sum)) {
    const float inv = 1.0f / sum;
    w0 *= inv; w1 *= inv; w2 *= inv;
  } else {
    w0 = w1 = w2 = 1.0f / 3.0f;
  }
  b1 = w0 * corner[0][0] + w1 * corner[1][0] + w2 * corner[2][0];
  b2 = w0 * corner[0][1] + w1 * corner[1][1] + w2 * corner[2][1];
}

}  // namespace rast
