// Visibility-buffer rasterisation with bounded work items: each raster
// triangle's bounding box is cut along a fixed 8x8-pixel grid, and every
// (triangle, block) pair is one work item. A full-screen triangle becomes
// thousands of small items instead of one thread walking two million pixels;
// a box of at most 8x8 pixels is one item, whatever blocks it straddles
// (smallBox, visbuffer_blocks.h). Depth is resolved by the 64-bit atomic
// minimum of visKey, so the result does not depend on scheduling.
//
// The items are numbered by the setup as it writes the triangles
// (primitive_setup.cpp): each triangle's first item, in workOffset; an item
// finds its triangle by a binary search there, between the search hints
// (workHint, visbuffer_blocks.h) around it. A block's rows are tested by
// rasterNarrowRect, which reads the next row's keys before it tests a row's.
//
// Seen from inside a dense model, most (triangle, block) items lie behind
// walls drawn earlier. Each 8x8 block keeps a bound on the depth of all its
// pixels (f.blockDepth, float bits): an item whose triangle cannot come
// nearer than the bound is skipped whole. An item whose rectangle is the whole
// block lowers the bound to the farthest depth it left there, from the keys
// it read and its own (keys only decrease, so that holds from then on): the
// block's bound tightens as triangles fill it, not only when one covers it.
// For frames of layered large triangles the renderer also asks for the
// occluder pass (OccluderBounds): before any item, the blocks such triangles
// cover whole take their farthest depth there as the bound.
// The bound only ever holds for every pixel, so a skipped item is one whose
// every fragment would lose its depth test: the keys are those of the full
// pass, whatever the order items run in. (Single-sample frames only.) The
// bounds are reset for the next frame where the keys are cleared (the
// shading pass, or clearVisibility): FrameBuffers::visClear covers both.
//
// On GPUs, frames of large triangles take another layout of the same work
// (RasterBlockRows): a block's row on eight consecutive lanes, so that each
// key read and each atomic minimum of a row is one coalesced access of 64
// bytes instead of eight lanes' scattered ones. An item's search and tests
// then cost eight lanes instead of one, so the renderer asks for it only
// where items are few and full (rowLanes, backends/tuning.h).
//
// Each block also records the last frame that wrote a key in it
// (f.blockFrame): shading reads no keys of a block this frame left alone
// (they are clear), which is most of the screen for a model in front of a
// background.
#include "pipeline/rules/raster_rules.h"
#include "pipeline/rules/visbuffer_blocks.h"
#include "pipeline/raster/raster.h"

#include <algorithm>

namespace rast {
namespace {

static_assert((1 << kVisBlockShift) <= kRasterRowGroup, "a block's rows fit rasterNarrowRect");
constexpr int kRowLanes = 1 << kVisBlockShift;  // RasterBlockRows: a block row's pixels

// Occluders first (visbuffer_blocks.h): a grid-stride loop over the segments of
// the setup's candidates' whole blocks, each block lowering its depth bound
// to the candidate's farthest depth there when the candidate covers it whole
// (occluderBound). The candidate itself is drawn by the raster, so every pixel
// of the block ends at least that near: items behind it are skipped from the
// start, not only once the raster has filled the block, which in a frame that
// runs all its items in one wave (a view from inside a model) came too late.
struct OccluderBounds {
  DView<RasterTri> tris;
  DView<uint64_t> occCount;
  DView<uint32_t> occStart, occTri, blockDepth;
  int32_t blocksPerRow;
  uint32_t capacity, stride;

  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t thread) const {
    const uint64_t c = occCount(0);
    const uint32_t n = uint32_t(c) < capacity ? uint32_t(c) : capacity, total = uint32_t(c >> 32);
    uint32_t j = 0;  // a thread's segments come in order: its last candidate bounds the search
    for (uint32_t w = thread; w < total && n > 0; w += stride) {
      j = findRange(occStart, n, w, j);
      const RasterTri& t = tris(occTri(j));
      const WholeBlocks wb = wholeBlocksOf(t);
      const uint32_t perRow = uint32_t((wb.nx + kOccluderSegment - 1) / kOccluderSegment);
      const uint32_t local = w - occStart(j), row = perRow ? local / perRow : 0u;
      if (row >= uint32_t(wb.ny)) continue;
      const int32_t s0 = int32_t(local - row * perRow) * kOccluderSegment;
      const int32_t count = wb.nx - s0 < kOccluderSegment ? wb.nx - s0 : kOccluderSegment;
      const int32_t by = wb.by0 + int32_t(row);
      const Edges e(t);
      const DepthTerms dz(t);
      BlockCorners corners(e, wb.bx0 + s0, by);
      for (int32_t k = 0; k < count; ++k, corners.stepRight(e)) {
        uint32_t bits;
        if (!occluderBound(e, dz, corners, bits)) continue;
        const uint32_t b = uint32_t(by) * uint32_t(blocksPerRow) + uint32_t(wb.bx0 + s0 + k);
        if (bits < blockDepth(b)) Kokkos::atomic_fetch_min(&blockDepth(b), bits);
      }
    }
  }
};

// Grid-stride loop over the work items: their number is only known on the
// device, so the launch is sized to fill the machine instead.
struct RasterBlocks {
  DView<RasterTri> tris;
  DView<uint32_t> counters, workOffset, blockDepth, blockFrame;
  DView<uint64_t> workHint;
  DView<FrameUniforms> frame;
  DView<uint64_t> vis;
  int32_t width, blocksPerRow;
  uint32_t capacity, stride;
  SamplePattern samples;
  DView<uint64_t> occCount;  // zeroed here for the next frame's setup (read by OccluderBounds before)
  int32_t occluders;         // the occluder pass ran: test items with their block's nearest depth too

  // A work item: its rectangle (a block of its triangle's box, or a small box
  // whole) and the blocks it meets, once its tests let it draw.
  struct Item {
    int32_t x0, x1, y0, y1;
    uint32_t b, bRight, bUp;  // the first block it meets, and the steps to the others (0: none)
    uint32_t bound;           // the farthest of those blocks' depth bounds
    KOKKOS_INLINE_FUNCTION bool wholeBlock() const {
      return x1 - x0 == (1 << kVisBlockShift) - 1 && y1 - y0 == (1 << kVisBlockShift) - 1 && !bRight && !bUp;
    }
  };

  // Item w's raster triangle (into i: a thread's items come in order, its
  // last triangle bounds the search) and rectangle. False for an item of a
  // triangle past the capacity, counted but not stored (the frame is drawn
  // again with a larger buffer): none to draw.
  KOKKOS_INLINE_FUNCTION bool find(uint32_t w, uint32_t total, uint32_t n, uint32_t thisFrame, uint32_t hints, uint32_t& i,
                                   Item& it) const {
    uint32_t hi;
    workHintBounds(workHint.data(), hints, thisFrame, total, n, w, i, hi);
    i = findRange(workOffset, hi, w, i);
    const RasterTri& t = tris(i);
    uint32_t bw;
    const uint32_t local = w - workOffset(i);
    if (local >= visBlocksOf(t, bw)) return false;
    it.x0 = t.minX, it.x1 = t.maxX, it.y0 = t.minY, it.y1 = t.maxY;
    if (!smallBox(t)) {
      const int32_t bx = (t.minX >> kVisBlockShift) + int32_t(local % bw);
      const int32_t by = (t.minY >> kVisBlockShift) + int32_t(local / bw);
      it.x0 = imax(t.minX, bx << kVisBlockShift), it.x1 = imin(t.maxX, ((bx + 1) << kVisBlockShift) - 1);
      it.y0 = imax(t.minY, by << kVisBlockShift), it.y1 = imin(t.maxY, ((by + 1) << kVisBlockShift) - 1);
    }
    return true;
  }

  // One sample per pixel: whether the item can change a key, from its edges
  // and its blocks' depth bounds (the blocks and bound into it).
  KOKKOS_INLINE_FUNCTION bool mayDraw(const RasterTri& t, const Edges& e, Item& it) const {
    if (rectOutside(e, it.x0, it.x1, it.y0, it.y1)) return false;  // the block is in the box, not in the triangle
    // The blocks the rectangle meets: one, or up to two by two for a small box.
    const uint32_t bx0 = uint32_t(it.x0 >> kVisBlockShift), bx1 = uint32_t(it.x1 >> kVisBlockShift);
    const uint32_t by0 = uint32_t(it.y0 >> kVisBlockShift), by1 = uint32_t(it.y1 >> kVisBlockShift);
    it.b = by0 * uint32_t(blocksPerRow) + bx0;
    it.bRight = bx1 > bx0 ? 1u : 0u, it.bUp = by1 > by0 ? uint32_t(blocksPerRow) : 0u;
    const DepthBounds z = depthBounds(t);
    // Skipped only behind every block it meets: the farthest of their bounds.
    uint32_t bound = blockDepth(it.b);
    if (it.bRight) bound = imaxu(bound, blockDepth(it.b + it.bRight));
    if (it.bUp) bound = imaxu(imaxu(bound, blockDepth(it.b + it.bUp)), blockDepth(it.b + it.bUp + it.bRight));
    it.bound = bound;
    if (floatBits(z.lo) > bound) return false;  // behind every pixel of those blocks
    // After the occluder pass, the nearest of the triangle's pixels here: a
    // large sloped triangle's nearest corner may lie far from the block (on
    // the H100: overdraw 0.152 -> 0.144 ms, engine_inside 0.216 -> 0.210;
    // without the pass, engine's raster lost 0.6 us to it).
    if (occluders && bound < kFarDepthBits) {
      const float lo = rectNearest(e, DepthTerms(t), it.x0, it.x1, it.y0, it.y1);
      if (lo > 0.0f && floatBits(lo) > bound) return false;
    }
    return true;
  }

  // Every writer stores the same tag, unconditionally: reading it first
  // left each item waiting for that load at its end (5% of milktruck_cab's
  // raster stall samples). A block tagged without a key costs shading a read.
  KOKKOS_INLINE_FUNCTION void tag(const Item& it, uint32_t thisFrame) const {
    blockFrame(it.b) = thisFrame;
    if (it.bRight) blockFrame(it.b + it.bRight) = thisFrame;
    if (it.bUp) blockFrame(it.b + it.bUp) = thisFrame;
    if (it.bUp && it.bRight) blockFrame(it.b + it.bUp + it.bRight) = thisFrame;
  }

  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t thread) const {
    if (thread == 0 && occCount.data()) occCount(0) = 0;
    const uint32_t total = counters(kRasterWork);
    const uint32_t n = counters(kRasterTris) < capacity ? counters(kRasterTris) : capacity;
    const uint32_t thisFrame = frame(0).frame;
    const uint32_t hints = uint32_t(workHint.extent(0));
    uint32_t i = 0;
    for (uint32_t w = thread; w < total; w += stride) {
      Item it;
      if (!find(w, total, n, thisFrame, hints, i, it)) continue;
      const RasterTri& t = tris(i);
      if (samples.count > 1) {
        rasterRect(t, Edges(t), i, it.x0, it.x1, it.y0, it.y1, vis.data(), width, samples);
        continue;
      }
      const Edges e(t);
      if (!mayDraw(t, e, it)) continue;
      const RectResult r = rasterNarrowRect(t, e, i, it.x0, it.x1, it.y0, it.y1, vis.data(), width);
      if (r.covered) tag(it, thisFrame);
      // Whole blocks only: the bound must hold for all 64 pixels of block b.
      // `bound` is b's as read before the item (a whole block meets no other
      // block): when it has fallen since, the atomic changes nothing.
      if (it.wholeBlock() && r.maxDepthBits < it.bound) Kokkos::atomic_fetch_min(&blockDepth(it.b), r.maxDepthBits);
    }
  }
};

// RasterBlocks' work with a block's row on consecutive lanes: a team member
// of kRowLanes vector lanes takes an item, every lane runs its search and
// tests (the same loads, served once to the warp), then lane k walks column k
// of the item's rectangle (at most 8 wide: a block, or a small box whole) up
// its rows with rasterRow's per-pixel tests. On the H100 a pass of 64-bit
// atomic minima over a 1080p buffer took 35 us with a lane per block, as
// RasterBlocks walks it, and 12 us with a block row's pixels on consecutive
// lanes (docs/journal/performance-2026-11-*.md).
struct RasterBlockRows {
  RasterBlocks r;
  uint32_t members;  // team members in the launch: the items' stride

  KOKKOS_INLINE_FUNCTION void operator()(const TeamMember& m) const {
    const uint32_t me = uint32_t(m.league_rank()) * uint32_t(m.team_size()) + uint32_t(m.team_rank());
    if (me == 0 && r.occCount.data()) Kokkos::single(Kokkos::PerThread(m), [&]() { r.occCount(0) = 0; });
    const uint32_t total = r.counters(kRasterWork);
    const uint32_t n = r.counters(kRasterTris) < r.capacity ? r.counters(kRasterTris) : r.capacity;
    const uint32_t thisFrame = r.frame(0).frame;
    const uint32_t hints = uint32_t(r.workHint.extent(0));
    uint32_t i = 0;
    for (uint32_t w = me; w < total; w += members) {
      // RasterBlocks' search and tests, on every lane.
      RasterBlocks::Item it;
      if (!r.find(w, total, n, thisFrame, hints, i, it)) continue;
      const RasterTri& t = r.tris(i);
      const Edges e(t);
      if (!r.mayDraw(t, e, it)) continue;
      const int32_t x0 = it.x0, y0 = it.y0, y1 = it.y1;
      const DepthTerms dz(t);
      const int64_t nb0 = -e.bias[0], nb1 = -e.bias[1], nb2 = -e.bias[2];
      const int32_t last = it.x1 - x0;
      const int64_t c0 = e.eval(0, x0, y0), c1 = e.eval(1, x0, y0), c2 = e.eval(2, x0, y0);
      uint64_t* const base = r.vis.data() + int64_t(y0) * r.width + x0;
      // The farthest key left in the rectangle (RectResult::maxDepthBits).
      uint32_t maxBits = 0;
      Kokkos::parallel_reduce(
          Kokkos::ThreadVectorRange(m, kRowLanes),
          [&](const int k, uint32_t& farthest) {
            if (k > last) return;
            int64_t e0 = c0 + e.A[0] * k, e1 = c1 + e.A[1] * k, e2 = c2 + e.A[2] * k;
            uint64_t* px = base + k;
            uint64_t cur = *px;
            bool covered = false;
            for (int32_t y = y0; y <= y1; ++y, e0 += e.B[0], e1 += e.B[1], e2 += e.B[2]) {
              const uint64_t ahead = y < y1 ? px[r.width] : 0u;  // the next row's key, read early
              uint64_t after = cur;
              if (e0 > nb0 && e1 > nb1 && e2 > nb2) {  // e.inside(e0, e1, e2)
                const uint64_t key = visKey(dz.at(e0, e2), i);
                if (key < cur) {  // the atomic minimum alone decides
                  Kokkos::atomic_fetch_min(px, key);
                  after = key;
                }
                covered = true;
              }
              const uint32_t bits = uint32_t(after >> 32);
              farthest = bits > farthest ? bits : farthest;
              px += r.width;
              cur = ahead;
            }
            // The tags, stored by every lane that met the triangle (the same
            // values: a warp's stores to one word merge).
            if (covered) r.tag(it, thisFrame);
          },
          Kokkos::Max<uint32_t>(maxBits));
      if (it.wholeBlock() && maxBits < it.bound)
        Kokkos::single(Kokkos::PerThread(m), [&]() { Kokkos::atomic_fetch_min(&r.blockDepth(it.b), maxBits); });
    }
  }
};

}  // namespace

void rasterVisBuffer(FrameBuffers& f, bool occluders, bool rowLanes) {
  int32_t bx;
  const uint32_t numBlocks = visBlocks(f.vp, bx);
  // The bounds start far. The shading pass that clears the keys resets them
  // for the next frame (visClear covers both); otherwise, or when they are
  // new, here.
  if (ensureCapacity(f.blockDepth, "frame.blockDepth", numBlocks) || !f.visClear)
    Kokkos::deep_copy(Exec(), Kokkos::subview(f.blockDepth, std::make_pair(size_t(0), size_t(numBlocks))), kFarDepthBits);
  ensureCapacity(f.blockFrame, "frame.blockFrame", numBlocks);  // stale tags only make shading read clear keys
  using Policy = Kokkos::RangePolicy<Exec, Kokkos::IndexType<uint32_t>>;
  const uint32_t threads = persistentThreads();
  const bool pass = occluders && f.vp.samples.count == 1 && f.occCount.data();  // the setup listed them (primitiveSetup)
  if (pass)
    Kokkos::parallel_for("rast::raster::visbuffer::occluders", lightweight(Policy(0, threads)),
                         OccluderBounds{f.tris, f.occCount, f.occStart, f.occTri, f.blockDepth, bx, f.triCapacity, threads});
  // Blocks of one SIMD group (kRasterLaunchBounds, backends/tuning.h).
  using BlockPolicy = Kokkos::RangePolicy<Exec, Kokkos::IndexType<uint32_t>,
                                          Kokkos::LaunchBounds<kRasterLaunchBounds[0], kRasterLaunchBounds[1]>>;
  const RasterBlocks blocks{f.tris, f.counters, f.workOffset, f.blockDepth, f.blockFrame, f.workHint, f.uniforms, f.vis,
                            f.vp.width, bx, f.triCapacity, threads, f.vp.samples, f.occCount, pass ? 1 : 0};
  if (rowLanes && f.vp.samples.count == 1) {
    // A team member a block row (kRowLanes lanes), as many as the machine
    // has thread slots for (kRowTeam members a team).
    const uint32_t members = std::max(1u, threads / uint32_t(kRowLanes)) / kRowTeam * kRowTeam;
    Kokkos::parallel_for("rast::raster::visbuffer::block_rows",
                         lightweight(TeamPolicy(int(std::max(1u, members / kRowTeam)), int(kRowTeam), kRowLanes)),
                         RasterBlockRows{blocks, std::max(1u, members / kRowTeam) * kRowTeam});
  } else {
    Kokkos::parallel_for("rast::raster::visbuffer::blocks", lightweight(BlockPolicy(0, threads)), blocks);
  }
}

}  // namespace rast
