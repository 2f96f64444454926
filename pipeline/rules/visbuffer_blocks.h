// The visbuffer method's own rules, on top of the exact rules every raster
// method shares (raster_rules.h): the fixed grid of 8x8-pixel blocks that cuts
// a raster triangle's box into work items, the work hints that let the raster
// find an item's triangle, the occluder blocks that lower the blocks' depth
// bounds before the raster, and the depth test over a rectangle of the
// visibility buffer that reports what it saw for those bounds.
//
// They live apart so that raster_rules.h stays the short list of what decides
// coverage and depth, and they live in rules/ because the primitive setup
// (pipeline/geometry: counting items, writing hints, listing occluders) and
// the rasters (pipeline/raster: the visbuffer and naive methods) both use them,
// and neither of those folders may include the other. Shading reads the block
// numbering too (blockDepth, blockFrame: shade_fragment.h).
#pragma once

#include "pipeline/rules/raster_rules.h"
#include "backends/tuning.h"  // kRasterRowGroup

namespace rast {

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
