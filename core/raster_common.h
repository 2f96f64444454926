// The exact rasterisation rules every raster method shares: fixed-point
// snapping, integer edge functions, the top-left fill rule and the depth value.
//
// Window space is OpenGL's: y up, pixel (x, y) centred at (x + 0.5, y + 0.5).
// Vertices are snapped to 1/256 pixel (kSubBits = 8). Edge functions are
// evaluated exactly in 64-bit integers at pixel centres, so whether a pixel is
// covered never depends on rounding, and two triangles sharing an edge neither
// both cover nor both miss a pixel on it.
#pragma once

#include "../backends/tuning.h"
#include "clip.h"
#include "depth_plane.h"
#include "gpu_types.h"

#include <type_traits>

namespace rast {

constexpr int kSubBits = 8;
constexpr int32_t kSubOne = 1 << kSubBits;      // one pixel in fixed point
constexpr int32_t kSubHalf = kSubOne / 2;       // pixel centre offset
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
  int32_t lx = t.x[0], hx = t.x[0], ly = t.y[0], hy = t.y[0];
  for (int i = 1; i < 3; ++i) {
    lx = t.x[i] < lx ? t.x[i] : lx; hx = t.x[i] > hx ? t.x[i] : hx;
    ly = t.y[i] < ly ? t.y[i] : ly; hy = t.y[i] > hy ? t.y[i] : hy;
  }
  // Pixels with a sample point x*256 + 128 + offset inside [lx, hx] (for a
  // single sample: the pixel centres inside the box).
  const SamplePattern& sp = vp.samples;
  t.minX = floorDiv(lx - kSubHalf - sp.maxX + kSubOne - 1, kSubOne);
  t.maxX = floorDiv(hx - kSubHalf - sp.minX, kSubOne);
  t.minY = floorDiv(ly - kSubHalf - sp.maxY + kSubOne - 1, kSubOne);
  t.maxY = floorDiv(hy - kSubHalf - sp.minY, kSubOne);
  t.minX = t.minX < 0 ? 0 : t.minX;
  t.minY = t.minY < 0 ? 0 : t.minY;
  t.maxX = t.maxX > vp.width - 1 ? vp.width - 1 : t.maxX;
  t.maxY = t.maxY > vp.height - 1 ? vp.height - 1 : t.maxY;
  t.prim = prim;
  return t.minX <= t.maxX && t.minY <= t.maxY;
}

KOKKOS_INLINE_FUNCTION void putCorner(RasterTri& t, int i, const SnapVert& s, float b1, float b2) {
  t.x[i] = fineToSnapped(s.x); t.y[i] = fineToSnapped(s.y); t.z[i] = s.z; t.invW[i] = s.invW;
  t.bary[i][0] = b1; t.bary[i][1] = b2;
}

// Whether a vertex's window position lies within +-kMaxWindowCoord pixels, so
// that snapping it to fixed point cannot overflow int32 (undefined behaviour;
// found by scripts/fuzz_cli.sh). Clipped vertices land inside the guard band
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
    KOKKOS_INLINE_FUNCTION int64_t eval(int i, int32_t X, int32_t Y) const {
      return int64_t(dx[i]) * int64_t(kSubOne * Y + cy[i]) + int64_t(ndy[i]) * int64_t(kSubOne * X + cx[i]);
    }
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
  // Edge value at a sample offset (ox, oy) in 1/256 pixel from the pixel centre.
  KOKKOS_INLINE_FUNCTION int64_t atSample(int i, int64_t centre, int32_t ox, int32_t oy) const {
    return centre + (A[i] / kSubOne) * ox + (B[i] / kSubOne) * oy;
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

// The visbuffer method's work items: a raster triangle's bounding box cut
// along a fixed grid of 8x8-pixel blocks (raster_visbuffer.cpp); the setup
// counts them as it writes the triangles (primitive_setup.cpp).
constexpr int kVisBlockShift = 3;
constexpr uint32_t kFarDepthBits = 0x3f800000u;  // a block's depth bound when nothing is known: the clear depth
inline uint32_t visBlocks(const Viewport& vp, int32_t& blocksPerRow) {  // blocks of the frame
  blocksPerRow = (vp.width + (1 << kVisBlockShift) - 1) >> kVisBlockShift;
  return uint32_t(blocksPerRow) * uint32_t((vp.height + (1 << kVisBlockShift) - 1) >> kVisBlockShift);
}
// Every kWorkHintItems-th item's raster triangle (f.workHint, written by the
// setup with workOffset): an item's triangle lies between the hints around
// it, so the raster's search covers the few triangles of those items instead
// of all of them (17 dependent loads an item over engine's 87,000 raster
// triangles: its raster took 60 us with that search, 55 with the hints, on
// an H100).
// A hint holds the frame (FrameUniforms::frame) that wrote it above the
// triangle, so that one left from another frame is never used, and nothing
// is cleared between frames (the buffer starts zeroed; frames count from 1).
// That lets a very large triangle write the first and last hints of its
// items only: where its interior's are stale, the search covers every
// triangle, as it did without hints. Up to kWorkHintsWritten hints (16,384
// items) a triangle writes them all, one thread storing them in a row: a
// view from inside a dense model has many triangles of thousands of items
// among tens of thousands (on the H100, 64 instead of 4 took engine_inside's
// raster from 99 to 90 us and overdraw's from 85 to 82; milktruck_cab, whose
// largest triangles span 5 to 64 hints, and bigtri, whose two span more,
// were even; box's setup took 0.3 us more). All of them, for any size, cost
// bigtri's setup 2.4 us: a single thread writing a clipped piece's hundreds.
constexpr int kWorkHintShift = 8;
constexpr uint32_t kWorkHintItems = 1u << kWorkHintShift;
constexpr uint32_t kWorkHintsWritten = 64;  // a triangle spanning more writes its first and last only
KOKKOS_INLINE_FUNCTION uint64_t workHintWord(uint32_t frame, uint32_t tri) { return uint64_t(frame) << 32 | tri; }
// Records raster triangle `tri`, whose items are [first, end), in the hints.
KOKKOS_INLINE_FUNCTION void markWorkHints(uint64_t* hint, uint32_t hints, uint32_t frame, uint32_t first, uint32_t end,
                                          uint32_t tri) {
  if (end <= first) return;
  const uint64_t h0 = (uint64_t(first) + kWorkHintItems - 1) >> kWorkHintShift;
  const uint64_t h1 = (uint64_t(end) + kWorkHintItems - 1) >> kWorkHintShift;  // past the last
  const uint64_t stop = h1 < hints ? h1 : hints;
  const uint64_t word = workHintWord(frame, tri);
  if (h1 - h0 > kWorkHintsWritten) {
    if (h0 < hints) hint[h0] = word;
    if (h1 - 1 < hints) hint[h1 - 1] = word;
    return;
  }
  for (uint64_t h = h0; h < stop; ++h) hint[h] = word;
}
// Bounds [lo, hi) for the search of item w among n raster triangles, from
// this frame's hints (lo: a triangle at or before w's, the caller's).
KOKKOS_INLINE_FUNCTION void workHintBounds(const uint64_t* hint, uint32_t hints, uint32_t frame, uint32_t total,
                                           uint32_t n, uint32_t w, uint32_t& lo, uint32_t& hi) {
  hi = n;
  const uint32_t h = w >> kWorkHintShift;
  if (h >= hints || n == 0) return;
  const uint64_t a = hint[h];
  if (uint32_t(a >> 32) == frame) {
    const uint32_t t = uint32_t(a) < n ? uint32_t(a) : n - 1;
    lo = t > lo ? t : lo;
  }
  if (h + 1 < hints && (uint64_t(h + 1) << kWorkHintShift) < total) {
    const uint64_t b = hint[h + 1];
    if (uint32_t(b >> 32) == frame) hi = uint32_t(b) < n ? uint32_t(b) + 1 : n;
  }
  if (hi <= lo) hi = lo + 1;
}

// A raster triangle's visbuffer work items: the 8x8 blocks its box meets,
// except that a box of at most 8x8 pixels is one item wherever it lies (up to
// four blocks): a dense mesh's small triangles mostly straddle block edges,
// and each item pays a search for its triangle and the triangle's edge setup.
KOKKOS_INLINE_FUNCTION bool smallBox(const RasterTri& t) {
  return t.maxX - t.minX < (1 << kVisBlockShift) && t.maxY - t.minY < (1 << kVisBlockShift);
}
KOKKOS_INLINE_FUNCTION uint32_t visBlocksOf(const RasterTri& t, uint32_t& bw) {
  if (smallBox(t)) {
    bw = 1;
    return 1;
  }
  bw = uint32_t((t.maxX >> kVisBlockShift) - (t.minX >> kVisBlockShift) + 1);
  const uint32_t bh = uint32_t((t.maxY >> kVisBlockShift) - (t.minY >> kVisBlockShift) + 1);
  return bw * bh;
}

// Occluders (raster_visbuffer.cpp): before the visbuffer raster, the 8x8
// blocks that a raster triangle covers whole lower those blocks' depth bounds
// to the farthest depth it has there, so that the raster skips the items
// behind it whatever order they run in. The setup lists the candidates:
// triangles whose bounding box holds a whole block and whose area could hold
// one (a triangle containing an 8x8 square has an area of at least 128
// pixels; 120 leaves room for the rounding of invArea).
constexpr float kOccluderMinArea = 120.0f;
struct WholeBlocks {
  int32_t bx0, by0, nx, ny;  // blocks [bx0, bx0 + nx) x [by0, by0 + ny)
};
KOKKOS_INLINE_FUNCTION WholeBlocks wholeBlocksOf(const RasterTri& t) {
  constexpr int32_t kSide = 1 << kVisBlockShift;
  const int32_t bx0 = (t.minX + kSide - 1) >> kVisBlockShift, bx1 = ((t.maxX + 1) >> kVisBlockShift) - 1;
  const int32_t by0 = (t.minY + kSide - 1) >> kVisBlockShift, by1 = ((t.maxY + 1) >> kVisBlockShift) - 1;
  return {bx0, by0, bx1 >= bx0 ? bx1 - bx0 + 1 : 0, by1 >= by0 ? by1 - by0 + 1 : 0};
}
// The blocks a triangle offers as an occluder (0: not a candidate).
KOKKOS_INLINE_FUNCTION bool occluderCandidate(const RasterTri& t) {
  // invArea = 1 / (2 * area * 256^2): the area test without a division.
  return t.invArea * (2.0f * kOccluderMinArea * float(kSubOne) * float(kSubOne)) <= 1.0f;
}
// The occluder pass takes a candidate's whole blocks in segments of up to
// kOccluderSegment blocks along a row, a work item each: one search for the
// candidate and one set of edge values per segment, stepped from block to
// block (a block a work item searched and set up 196,000 times for one view of
// the milk truck's cab).
constexpr int32_t kOccluderSegment = 16;
KOKKOS_INLINE_FUNCTION uint32_t occluderSegments(const RasterTri& t) {
  if (!occluderCandidate(t)) return 0;
  const WholeBlocks w = wholeBlocksOf(t);
  return uint32_t(w.ny) * uint32_t((w.nx + kOccluderSegment - 1) / kOccluderSegment);
}
// The setup's list of candidates: occCount packs the segments listed so far
// (high word) and the candidates (low word), so that one atomic addition gives
// a candidate both its slot and its first segment, and the starts increase
// with the slot (a binary search finds a segment's candidate). The order of the
// list depends on scheduling; the bounds it yields (minima) do not.
struct OccluderList {
  uint64_t* count = nullptr;  // null: no list this frame
  uint32_t* start = nullptr;
  uint32_t* tri = nullptr;
  uint32_t capacity = 0;
  KOKKOS_INLINE_FUNCTION void add(const RasterTri& t, uint32_t index) const {
    if (!count) return;
    const uint32_t n = occluderSegments(t);
    if (n == 0) return;
    const uint64_t old = Kokkos::atomic_fetch_add(count, uint64_t(n) << 32 | 1u);
    const uint32_t j = uint32_t(old);
    if (j < capacity) {  // always: each stored raster triangle is added once
      start[j] = uint32_t(old >> 32);
      tri[j] = index;
    }
  }
};

// The edge values at the four corner pixel centres of an 8x8 block (edge i,
// corner k: lower left, lower right, upper left, upper right), stepped from
// block to block along a row (exact: integers).
struct BlockCorners {
  int64_t v[3][4];
  KOKKOS_INLINE_FUNCTION BlockCorners(const Edges& e, int32_t bx, int32_t by) {
    const int32_t x0 = bx << kVisBlockShift, x1 = x0 + (1 << kVisBlockShift) - 1;
    const int32_t y0 = by << kVisBlockShift, y1 = y0 + (1 << kVisBlockShift) - 1;
    for (int i = 0; i < 3; ++i) {
      v[i][0] = e.eval(i, x0, y0);
      v[i][1] = e.eval(i, x1, y0);
      v[i][2] = e.eval(i, x0, y1);
      v[i][3] = e.eval(i, x1, y1);
    }
  }
  KOKKOS_INLINE_FUNCTION void stepRight(const Edges& e) {
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 4; ++k) v[i][k] += e.A[i] * (1 << kVisBlockShift);
  }
};

// Whether a triangle covers a block whole, and if so a bound (float bits) on
// the depth of its every pixel there, from the block's corner edge values.
// Whole: the four corner pixel centres lie inside (exact edge values, with the
// fill rule's bias), so every centre between does. The bound: depth is a
// plane, so its largest value over the block is at a corner; depthAt() rounds
// each pixel's within a few ulps of |z0| + |d1| + |d2| (its weights lie in
// [0, 1] inside), and the margin, 2e-6 of that, is several times as much.
// False too when the bound is no nearer than the clear depth, or NaN.
KOKKOS_INLINE_FUNCTION bool occluderBound(const Edges& e, const DepthTerms& dz, const BlockCorners& c, uint32_t& bits) {
  bool whole = true;
  float far = 0.0f;
  for (int k = 0; k < 4; ++k) {
    whole = whole && e.inside(c.v[0][k], c.v[1][k], c.v[2][k]);
    const float z = dz.plane(c.v[0][k], c.v[2][k]);
    far = z > far ? z : far;
  }
  const float az = dz.z0 < 0.0f ? -dz.z0 : dz.z0, a1 = dz.d1 < 0.0f ? -dz.d1 : dz.d1, a2 = dz.d2 < 0.0f ? -dz.d2 : dz.d2;
  const float bound = far + 2e-6f * (1.0f + az + a1 + a2);
  // A depth of -0 (bits above every positive float's) could only come from a
  // z0 of -0: no bound then.
  if (!whole || !(bound < 1.0f) || floatBits(dz.z0) == 0x80000000u) return false;
  bits = floatBits(bound);
  return true;
}
// The same for block (bx, by) of raster triangle t.
KOKKOS_INLINE_FUNCTION bool occluderBound(const RasterTri& t, int32_t bx, int32_t by, uint32_t& bits) {
  const Edges e(t);
  return occluderBound(e, DepthTerms(t), BlockCorners(e, bx, by), bits);
}

// A lower bound on the depth of t's pixels in the rectangle [x0, x1] x
// [y0, y1], when that is nearer than its depth bound: the plane's smallest
// value at the rectangle's corners (where the rectangle's smallest is), less
// a margin for depthAt()'s rounding, which outside the triangle (corners of a
// rectangle it only crosses) grows with the weights there. Tighter than
// depthBounds() for a large sloped triangle, whose nearest corner may lie far
// from the block.
KOKKOS_INLINE_FUNCTION float rectNearest(const Edges& e, const DepthTerms& dz, int32_t x0, int32_t x1, int32_t y0,
                                         int32_t y1) {
  const int32_t cx[4] = {x0, x1, x0, x1}, cy[4] = {y0, y0, y1, y1};
  float lo = 1.0f, weights = 1.0f;
  for (int k = 0; k < 4; ++k) {
    const int64_t e0 = e.eval(0, cx[k], cy[k]), e2 = e.eval(2, cx[k], cy[k]);
    const float z = dz.plane(e0, e2);
    lo = z < lo ? z : lo;
    const float l1 = float(e2) * dz.ia, l2 = float(e0) * dz.ia;
    const float w = (l1 < 0.0f ? -l1 : l1) + (l2 < 0.0f ? -l2 : l2);
    weights = w > weights ? w : weights;
  }
  const float az = dz.z0 < 0.0f ? -dz.z0 : dz.z0, a1 = dz.d1 < 0.0f ? -dz.d1 : dz.d1, a2 = dz.d2 < 0.0f ? -dz.d2 : dz.d2;
  const float bound = lo - 2e-6f * (1.0f + az + (1.0f + weights) * (a1 + a2));
  return bound == bound ? bound : 0.0f;  // NaN: no bound
}

// What rasterRect saw (single sample only): the pixels the triangle covers,
// and a bound on the depth bits of every pixel of the rectangle after it, from
// the keys it read and its own (keys only ever decrease).
struct RectResult {
  uint32_t covered = 0, maxDepthBits = 0;
};

// One row of a single-sample rectangle: pixels 0 .. last (at most
// kRasterRowGroup) from `row` on, whose keys `cur` holds, with the edge values
// e0, e1, e2 at the first. Inside means E_i + bias_i > 0, that is
// E_i > nb_i = -bias_i: compared against that, no bias is added to the 64-bit
// values at every pixel.
KOKKOS_FORCEINLINE_FUNCTION void rasterRow(const Edges& e, const DepthTerms& dz, const int64_t (&nb)[3], uint32_t index,
                                           int64_t e0, int64_t e1, int64_t e2, int32_t last,
                                           const uint64_t (&cur)[kRasterRowGroup], uint64_t* row, RectResult& res) {
  for (int k = 0; k < kRasterRowGroup; ++k) {
    if (k > last) break;
    uint64_t after = cur[k];
    if (e0 > nb[0] && e1 > nb[1] && e2 > nb[2]) {  // e.inside(e0, e1, e2)
      const uint64_t key = visKey(dz.at(e0, e2), index);
      // The plain read only skips atomics that could not win; the atomic
      // minimum alone decides, so the result is independent of ordering.
      if (key < cur[k]) {
        Kokkos::atomic_fetch_min(&row[k], key);
        after = key;
      }
      ++res.covered;
    }
    const uint32_t bits = uint32_t(after >> 32);
    res.maxDepthBits = bits > res.maxDepthBits ? bits : res.maxDepthBits;
    e0 += e.A[0];
    e1 += e.A[1];
    e2 += e.A[2];
  }
}

// Depth-tests raster triangle `index` against the visibility buffer over the
// pixel rectangle [x0, x1] x [y0, y1] (inside the triangle's bounding box).
// Edge values step incrementally along a row: exact, since they are integers.
// With several samples per pixel the buffer holds `count` keys per pixel, and
// each sample follows the same rules at its own position. Single-sample
// rectangles also report what they saw (RectResult).
KOKKOS_INLINE_FUNCTION RectResult rasterRect(const RasterTri& t, const Edges& e, uint32_t index, int32_t x0, int32_t x1,
                                           int32_t y0, int32_t y1, uint64_t* vis, int32_t width, const SamplePattern& sp) {
  if (sp.count > 1) {
    for (int32_t y = y0; y <= y1; ++y) {
      int64_t e0 = e.eval(0, x0, y), e1 = e.eval(1, x0, y), e2 = e.eval(2, x0, y);
      for (int32_t x = x0; x <= x1; ++x) {
        uint64_t* px = vis + (int64_t(y) * width + x) * sp.count;
        for (int s = 0; s < sp.count; ++s) {
          const int64_t s0 = e.atSample(0, e0, sp.ox[s], sp.oy[s]), s1 = e.atSample(1, e1, sp.ox[s], sp.oy[s]),
                        s2 = e.atSample(2, e2, sp.ox[s], sp.oy[s]);
          if (e.inside(s0, s1, s2)) {
            const uint64_t key = visKey(depthAt(t, s0, s1, s2), index);
            if (key < px[s]) Kokkos::atomic_fetch_min(&px[s], key);
          }
        }
        e0 += e.A[0];
        e1 += e.A[1];
        e2 += e.A[2];
      }
    }
    return RectResult{};
  }
  // Rows go in groups of kRasterRowGroup pixels whose keys are read together
  // before any is tested: on a GPU each read is a trip to L2 or memory, and
  // one at a time they left a thread waiting once per pixel.
  // The rows' first edge values step by B (exact integers, as along a row):
  // three 64-bit multiplications a row were a fifth of the raster's
  // instructions on a plain model (Nsight Compute, H100).
  RectResult res;
  const DepthTerms dz(t);
  const int64_t nb[3] = {-e.bias[0], -e.bias[1], -e.bias[2]};
  int64_t r0 = e.eval(0, x0, y0), r1 = e.eval(1, x0, y0), r2 = e.eval(2, x0, y0);
  for (int32_t y = y0; y <= y1; ++y, r0 += e.B[0], r1 += e.B[1], r2 += e.B[2]) {
    int64_t e0 = r0, e1 = r1, e2 = r2;
    uint64_t* row = vis + int64_t(y) * width;
    for (int32_t xs = x0; xs <= x1; xs += kRasterRowGroup) {
      uint64_t cur[kRasterRowGroup];
      for (int k = 0; k < kRasterRowGroup; ++k) cur[k] = xs + k <= x1 ? row[xs + k] : 0u;
      rasterRow(e, dz, nb, index, e0, e1, e2, x1 - xs, cur, row + xs, res);
      e0 += e.A[0] * kRasterRowGroup;
      e1 += e.A[1] * kRasterRowGroup;
      e2 += e.A[2] * kRasterRowGroup;
    }
  }
  return res;
}

// rasterRect for a single-sample rectangle no wider than a row group (one
// 8x8 block of the visbuffer raster), whose next row's keys are read before
// this row's are tested: a thread then waits for memory once per block, not
// once per row (large triangles' blocks are eight rows of loads that hit L2).
KOKKOS_INLINE_FUNCTION RectResult rasterNarrowRect(const RasterTri& t, const Edges& e, uint32_t index, int32_t x0,
                                                 int32_t x1, int32_t y0, int32_t y1, uint64_t* vis, int32_t width) {
  RectResult res;
  const DepthTerms dz(t);
  const int64_t nb[3] = {-e.bias[0], -e.bias[1], -e.bias[2]};
  const int32_t last = x1 - x0;  // below kRasterRowGroup
  int64_t r0 = e.eval(0, x0, y0), r1 = e.eval(1, x0, y0), r2 = e.eval(2, x0, y0);
  uint64_t* row = vis + int64_t(y0) * width + x0;
  uint64_t cur[kRasterRowGroup];
  for (int k = 0; k < kRasterRowGroup; ++k) cur[k] = k <= last ? row[k] : 0u;
  for (int32_t y = y0; y <= y1; ++y, r0 += e.B[0], r1 += e.B[1], r2 += e.B[2]) {
    uint64_t* next = row + width;
    uint64_t ahead[kRasterRowGroup];
    for (int k = 0; k < kRasterRowGroup; ++k) ahead[k] = y < y1 && k <= last ? next[k] : 0u;
    rasterRow(e, dz, nb, index, r0, r1, r2, last, cur, row, res);
    for (int k = 0; k < kRasterRowGroup; ++k) cur[k] = ahead[k];
    row = next;
  }
  return res;
}

}  // namespace rast
