// Primitive assembly and triangle setup: fetch indices, clip in homogeneous
// space, cull, snap, and write the raster triangles in primitive order.
//
// The output is compact and ordered without atomics, by a reduce-then-scan over
// chunks of kSetupChunk drawn triangles:
//   count  one team per chunk: how many raster triangles the chunk yields (each
//          drawn triangle gives 0 when culled, degenerate, non-finite or
//          off-screen, 1 when it needs no clipping, up to kMaxClipVerts-2 when
//          clipped; a clipped triangle's count is kept for the write pass, so
//          that it is clipped twice rather than three times);
//   scan   exclusive scan over the chunk totals (a few thousand numbers), by
//          the count pass's last team to finish: one launch, not three (a
//          count kernel and Kokkos' two-kernel scan);
//   write  one team per chunk redoes the setup into team scratch, scans the
//          per-triangle counts within the chunk, and copies the chunk's
//          triangles out word by word, so that neighbouring threads write
//          neighbouring words.
// The last step matters on a GPU: a thread storing its own 96-byte triangle
// sends 24 scattered 4-byte stores per warp instruction to L2, which made the
// write pass six times slower than the count pass on the H100 (0.31 vs 0.03 ms
// for a million triangles). The total goes to counters(kRasterTris) on the
// device, so no host round trip is needed inside the frame.
//
// For the visbuffer method the write pass also numbers its work items (8x8
// blocks of each triangle's box, raster_common.h): each raster triangle's
// first item within its chunk (workOffset), each chunk's first item
// (chunkBlocks, scanned by the write pass's last team) and the total
// (counters(kRasterWork)). That replaced a two-kernel scan over all raster
// triangles; the raster finds an item's triangle by its chunk first.
#include <cstring>
#include <type_traits>

#include "raster_common.h"
#include "stages.h"

namespace rast {
namespace {

struct SetupCommon {
  DView<DrawGPU> draws;
  DView<uint32_t> drawTriStart;
  DView<uint32_t> indices;
  DView<float4> clip;
  DView<SnapVert> snap;
  uint32_t numDraws;
  Viewport vp;
  float gx, gy;
  int32_t cullBack;

  // Drawn-vertex indices of drawn triangle t's corners.
  KOKKOS_INLINE_FUNCTION void corners(uint32_t t, uint32_t (&vi)[3], bool& frontCCW) const {
    const uint32_t d = findRange(drawTriStart, numDraws, t);
    const DrawGPU& dr = draws(d);
    const uint32_t base = 3 * (dr.srcTri + (t - dr.dstTri));
    for (int k = 0; k < 3; ++k) vi[k] = dr.dstVertex + indices(base + k);
    frontCCW = dr.mirrored == 0;
  }

  // Clips drawn triangle t (corners vi) into a convex polygon and sets up its
  // fan; calls emit(rt) for each raster triangle that survives, in order, and
  // returns how many did. kDepth: the pieces' depths are wanted (not when
  // only counting), from the drawn triangle's plane (depth_plane.h).
  template <bool kDepth, class Emit>
  KOKKOS_INLINE_FUNCTION uint32_t clipAndSetUp(uint32_t t, const uint32_t (&vi)[3], bool frontCCW, Emit&& emit) const {
    ClipVert poly[kMaxClipVerts];
    for (int k = 0; k < 3; ++k) poly[k].p = clip(vi[k]);
    poly[0].b1 = 0.0f; poly[0].b2 = 0.0f;
    poly[1].b1 = 1.0f; poly[1].b2 = 0.0f;
    poly[2].b1 = 0.0f; poly[2].b2 = 1.0f;
    const DepthPlane plane = kDepth ? DepthPlane(poly[0].p, poly[1].p, poly[2].p, vp) : DepthPlane();
    const int n = clipTriangle(poly, gx, gy);
    uint32_t k = 0;
    for (int i = 0; i + 2 < n; ++i) {
      RasterTri rt;
      if (!setupTriangle(poly[0], poly[i + 1], poly[i + 2], vp, cullBack != 0, frontCCW, t, rt)) continue;
      if (kDepth) depthFromPlane(rt, plane);
      emit(rt);
      ++k;
    }
    return k;
  }
};

// Exclusive prefix sum in place; the grand total goes to counters(slot).
struct ExclusiveScan {
  DView<uint32_t> data;
  DView<uint32_t> counters;
  uint32_t n;
  int slot;
  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t i, uint32_t& update, const bool final) const {
    const uint32_t v = data(i);
    if (final) {
      data(i) = update;
      if (i + 1 == n) counters(slot) = update + v;
    }
    update += v;
  }
};

constexpr uint32_t kSetupChunk = 256;       // drawn triangles per team
constexpr uint32_t kClippedFlag = 0x80000000u;  // in a scratch count: pieces written later

// Raster triangles drawn triangle t yields, from the vertex stage's snapped
// corners; `clipped` says the triangle crosses a clipping plane, and then the
// count comes from clipping it. The corners' codes classify the triangle as
// clipTriangle would (non-finite or wholly outside one plane: nothing; inside
// every plane: untouched), and an untouched triangle gets the bits
// setupTriangle would give it, so the result equals clipping every triangle.
// `out` holds the raster triangle when the triangle is unclipped and yields one;
// kDepth: with its corner depths on the unsnapped plane (depth_plane.h), which
// only the write pass needs. clipCounts: the count pass's counts of clipped
// triangles, or null to clip and count here.
template <bool kDepth>
KOKKOS_INLINE_FUNCTION uint32_t setupOne(const SetupCommon& c, uint32_t t, RasterTri& out, bool& clipped,
                                         const uint8_t* clipCounts) {
  uint32_t vi[3];
  bool frontCCW;
  c.corners(t, vi, frontCCW);
  SnapVert s[3];
  uint32_t any = 0, all = ~0u;
  for (int k = 0; k < 3; ++k) {
    s[k] = c.snap(vi[k]);
    const uint32_t code = snapCode(s[k]);
    any |= code;
    all &= code;
  }
  clipped = false;
  if (any == 0) {  // the common case: inside every plane, w > 0
    putCorner(out, 0, s[0], 0.0f, 0.0f);
    putCorner(out, 1, s[1], 1.0f, 0.0f);
    putCorner(out, 2, s[2], 0.0f, 1.0f);
    if (kDepth) {
      const int32_t rx[3] = {fineResidual(s[0].x), fineResidual(s[1].x), fineResidual(s[2].x)};
      const int32_t ry[3] = {fineResidual(s[0].y), fineResidual(s[1].y), fineResidual(s[2].y)};
      depthAtSnappedCorners(out, rx, ry);
    }
    return finishTriangle(c.vp, c.cullBack != 0, frontCCW, t, out) ? 1u : 0u;
  }
  if ((any & kCodeNonFinite) || (all & 0x3fu)) return 0;  // not drawable, or wholly outside one plane
  if (!(any & 0x3fu)) return 0;                           // inside every plane, but some w <= 0
  clipped = true;
  if (clipCounts) return clipCounts[t];
  return c.clipAndSetUp<false>(t, vi, frontCCW, [](const RasterTri&) {});
}

KOKKOS_INLINE_FUNCTION uint32_t chunkLength(uint32_t chunk, uint32_t n) {
  const uint32_t first = chunk * kSetupChunk;
  return n - first < kSetupChunk ? n - first : kSetupChunk;
}

struct CountChunks {
  SetupCommon c;
  DView<uint32_t> chunkCount, counters;
  DView<uint8_t> clipCount;
  uint32_t numTris, chunks;
  KOKKOS_INLINE_FUNCTION void operator()(const TeamMember& m) const {
    const uint32_t chunk = uint32_t(m.league_rank()), first = chunk * kSetupChunk;
    uint32_t sum = 0;
    Kokkos::parallel_reduce(
        Kokkos::TeamThreadRange(m, chunkLength(chunk, numTris)),
        [&](const uint32_t i, uint32_t& acc) {
          RasterTri rt;
          bool clipped;
          const uint32_t k = setupOne<false>(c, first + i, rt, clipped, nullptr);
          if (clipped) clipCount(first + i) = uint8_t(k);  // at most kMaxClipVerts - 2
          acc += k;
        },
        sum);
    // Publish the count, then take a ticket: the team that draws the last one
    // sees every count (the fences order each team's count before its ticket)
    // and scans them in place into chunk offsets. Which team that is depends
    // on scheduling; what it writes does not.
    uint32_t last = 0;
    Kokkos::single(
        Kokkos::PerTeam(m),
        [&](uint32_t& isLast) {
          chunkCount(chunk) = sum;
          Kokkos::memory_fence();
          isLast = Kokkos::atomic_fetch_add(&counters(kSetupDone), 1u) == chunks - 1 ? 1u : 0u;
        },
        last);
    if (!last) return;
    Kokkos::memory_fence();
    // Volatile reads: the counts were written by other teams, maybe on other
    // multiprocessors, and must not come from a stale cache line (atomic
    // reads did the same, 30 us slower for tiny's 3,900 chunks on the H100).
    const volatile uint32_t* counts = chunkCount.data();
    const uint32_t lastCount = counts[chunks - 1];
    m.team_barrier();  // read before the scan overwrites it
    Kokkos::parallel_scan(Kokkos::TeamThreadRange(m, chunks), [&](const uint32_t i, uint32_t& upd, const bool final) {
      const uint32_t v = counts[i];
      if (final) chunkCount(i) = upd;
      upd += v;
    });
    m.team_barrier();
    Kokkos::single(Kokkos::PerTeam(m), [&]() {
      counters(kRasterTris) = chunkCount(chunks - 1) + lastCount;
      counters(kSetupDone) = 0;  // for the next frame
    });
  }
};

// A RasterTri is moved as kTriQuads 16-byte pieces.
struct alignas(16) Quad {
  uint32_t w[4];
};
constexpr uint32_t kTriQuads = sizeof(RasterTri) / sizeof(Quad);
static_assert(sizeof(RasterTri) % sizeof(Quad) == 0, "RasterTri is copied in 16-byte pieces");
// Staged triangles sit kStageStride pieces apart in scratch. A 16-byte access
// is served eight threads at a time; at an odd stride those eight touch
// disjoint shared-memory banks (at six pieces, two would share).
constexpr uint32_t kStageStride = kTriQuads + 1;

// The visbuffer method's item numbering (see the top of the file), shared by
// both write passes: `blocks` 0 for the other methods, which need none.
struct BlockNumbering {
  DView<uint32_t> workOffset, chunkBlocks;
  uint32_t chunks;
  int32_t blocks;

  // A chunk's item total: with one chunk it is the total; otherwise the team
  // that finishes last (a ticket, as CountChunks) scans the chunks' totals
  // into their first items. Call from one thread of the team.
  KOKKOS_INLINE_FUNCTION bool publish(const DView<uint32_t>& counters, uint32_t chunk, uint32_t total) const {
    if (chunks == 1) {
      chunkBlocks(0) = 0;
      counters(kRasterWork) = total;
      return false;
    }
    chunkBlocks(chunk) = total;
    Kokkos::memory_fence();
    return Kokkos::atomic_fetch_add(&counters(kSetupDone), 1u) == chunks - 1;
  }
  // The last team's scan over the chunks, by all its threads (volatile
  // reads: the totals were written by other teams; see CountChunks).
  template <class Member>
  KOKKOS_INLINE_FUNCTION void scanChunks(const Member& m, const DView<uint32_t>& counters) const {
    Kokkos::memory_fence();
    const volatile uint32_t* t = chunkBlocks.data();
    const uint32_t lastTotal = t[chunks - 1];
    m.team_barrier();  // read before the scan overwrites it
    Kokkos::parallel_scan(Kokkos::TeamThreadRange(m, chunks), [&](const uint32_t i, uint32_t& upd, const bool final) {
      const uint32_t v = t[i];
      if (final) chunkBlocks(i) = upd;
      upd += v;
    });
    m.team_barrier();
    Kokkos::single(Kokkos::PerTeam(m), [&]() {
      counters(kRasterWork) = chunkBlocks(chunks - 1) + lastTotal;
      counters(kSetupDone) = 0;  // for the next frame's count pass
    });
  }
};

struct WriteChunks {
  SetupCommon c;
  DView<uint32_t> chunkOffset, counters;
  DView<uint8_t> clipCount;  // the count pass's (unused with one chunk)
  DView<RasterTri> tris;
  uint32_t capacity, numTris;
  // One chunk only: its offset is 0 and its own count is the total, so the
  // count and scan kernels are skipped and this one writes the total.
  int32_t single;
  BlockNumbering bn;

  static size_t scratchBytes() {
    return sizeof(Quad) * (kSetupChunk * kStageStride + 1) + 4 * sizeof(uint32_t) * (kSetupChunk + 1);
  }

  KOKKOS_INLINE_FUNCTION void operator()(const TeamMember& m) const {
    const uint32_t chunk = uint32_t(m.league_rank()), first = chunk * kSetupChunk;
    const uint32_t len = chunkLength(chunk, numTris);
    auto& shmem = m.team_scratch(0);
    Quad* staged = static_cast<Quad*>(shmem.get_shmem_aligned(sizeof(Quad) * kSetupChunk * kStageStride, sizeof(Quad)));
    uint32_t* count = static_cast<uint32_t*>(shmem.get_shmem_aligned(sizeof(uint32_t) * kSetupChunk, sizeof(uint32_t)));
    uint32_t* offset = static_cast<uint32_t*>(shmem.get_shmem_aligned(sizeof(uint32_t) * kSetupChunk, sizeof(uint32_t)));
    uint32_t* blk = static_cast<uint32_t*>(shmem.get_shmem_aligned(sizeof(uint32_t) * kSetupChunk, sizeof(uint32_t)));
    uint32_t* blkOffset = static_cast<uint32_t*>(shmem.get_shmem_aligned(sizeof(uint32_t) * kSetupChunk, sizeof(uint32_t)));
    // 1. Set up every triangle of the chunk; unclipped ones land in scratch.
    Kokkos::parallel_for(Kokkos::TeamThreadRange(m, len), [&](const uint32_t i) {
      bool clipped;
      RasterTri rt;
      const uint32_t k = setupOne<true>(c, first + i, rt, clipped, single ? nullptr : clipCount.data());
      count[i] = clipped ? (k | kClippedFlag) : k;
      uint32_t bw;
      blk[i] = bn.blocks && k == 1 && !clipped ? visBlocksOf(rt, bw) : 0u;
      if (k == 1 && !clipped) {
        Quad q[kTriQuads];
        memcpy(q, &rt, sizeof(rt));  // a register copy once compiled
        for (uint32_t j = 0; j < kTriQuads; ++j) staged[i * kStageStride + j] = q[j];
      }
    });
    m.team_barrier();
    // 2. Where each triangle's pieces go within the chunk's output.
    Kokkos::parallel_scan(Kokkos::TeamThreadRange(m, len), [&](const uint32_t i, uint32_t& upd, const bool final) {
      const uint32_t k = count[i] & ~kClippedFlag;
      if (final) offset[i] = upd;
      upd += k;
    });
    m.team_barrier();
    const uint32_t base = single ? 0u : chunkOffset(chunk);
    if (single)
      Kokkos::single(Kokkos::PerTeam(m), [&]() {
        counters(kRasterTris) = len ? offset[len - 1] + (count[len - 1] & ~kClippedFlag) : 0u;
      });
    // 3. Unclipped triangles, copied piece by piece: neighbouring threads
    //    write neighbouring 16 bytes (coalesced on a GPU).
    Quad* dst = reinterpret_cast<Quad*>(tris.data());
    Kokkos::parallel_for(Kokkos::TeamThreadRange(m, len * kTriQuads), [&](const uint32_t w) {
      const uint32_t i = w / kTriQuads, j = w - i * kTriQuads;
      if (count[i] != 1u) return;  // culled, or clipped (written below)
      const uint32_t o = base + offset[i];
      if (o < capacity) dst[size_t(o) * kTriQuads + j] = staged[i * kStageStride + j];
    });
    // 4. Clipped triangles (rare): clip again and write the pieces directly
    //    (with their first items relative to the drawn triangle's).
    Kokkos::parallel_for(Kokkos::TeamThreadRange(m, len), [&](const uint32_t i) {
      if (!(count[i] & kClippedFlag)) {
        if (base + offset[i] >= capacity) blk[i] = 0;  // not stored: no items
        return;
      }
      uint32_t vi[3];
      bool frontCCW;
      c.corners(first + i, vi, frontCCW);
      uint32_t o = base + offset[i], items = 0;
      c.clipAndSetUp<true>(first + i, vi, frontCCW, [&](const RasterTri& rt) {
        if (o < capacity) {
          tris(o) = rt;
          if (bn.blocks) {
            uint32_t bw;
            bn.workOffset(o) = items;
            items += visBlocksOf(rt, bw);
          }
        }
        ++o;
      });
      blk[i] = items;
    });
    if (!bn.blocks) return;
    m.team_barrier();
    // 5. The visbuffer's items: each triangle's first within the chunk.
    Kokkos::parallel_scan(Kokkos::TeamThreadRange(m, len), [&](const uint32_t i, uint32_t& upd, const bool final) {
      if (final) blkOffset[i] = upd;
      upd += blk[i];
    });
    m.team_barrier();
    Kokkos::parallel_for(Kokkos::TeamThreadRange(m, len), [&](const uint32_t i) {
      const uint32_t o = base + offset[i];
      if (count[i] == 1u) {
        if (o < capacity) bn.workOffset(o) = blkOffset[i];
      } else if (count[i] & kClippedFlag) {
        const uint32_t pieces = count[i] & ~kClippedFlag;
        for (uint32_t j = 0; j < pieces && o + j < capacity; ++j) bn.workOffset(o + j) += blkOffset[i];
      }
    });
    uint32_t last = 0;
    Kokkos::single(
        Kokkos::PerTeam(m),
        [&](uint32_t& isLast) {
          isLast = bn.publish(counters, chunk, len ? blkOffset[len - 1] + blk[len - 1] : 0u) ? 1u : 0u;
        },
        last);
    if (last) bn.scanChunks(m, counters);
  }
};

// The write pass on a host backend, where a team is one thread that walks
// its chunk in order: each raster triangle goes straight to its place, the
// running offset standing in for the scan over scratch, and nothing is staged
// (WriteChunks' scratch and 16-byte copies serve a GPU's coalescing). The
// same triangles at the same offsets.
struct WriteChunksHost {
  SetupCommon c;
  DView<uint32_t> chunkOffset, counters;
  DView<uint8_t> clipCount;  // the count pass's (unused with one chunk)
  DView<RasterTri> tris;
  uint32_t capacity, numTris;
  int32_t single;  // one chunk: offset 0, and its count is the total (as WriteChunks)
  BlockNumbering bn;

  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t chunk) const {
    const uint32_t first = chunk * kSetupChunk, len = chunkLength(chunk, numTris);
    const uint32_t base = single ? 0u : chunkOffset(chunk);
    uint32_t o = base, items = 0;
    auto store = [&](const RasterTri& rt) {
      if (o < capacity) {
        tris(o) = rt;
        if (bn.blocks) {
          uint32_t bw;
          bn.workOffset(o) = items;
          items += visBlocksOf(rt, bw);
        }
      }
      ++o;
    };
    for (uint32_t i = 0; i < len; ++i) {
      bool clipped;
      RasterTri rt;
      const uint32_t k = setupOne<true>(c, first + i, rt, clipped, single ? nullptr : clipCount.data());
      if (!clipped) {
        if (k == 1) store(rt);
        continue;
      }
      uint32_t vi[3];  // clipped (rare): clip again and write the pieces, as WriteChunks does
      bool frontCCW;
      c.corners(first + i, vi, frontCCW);
      c.clipAndSetUp<true>(first + i, vi, frontCCW, store);
    }
    if (single) counters(kRasterTris) = o - base;
    if (bn.blocks && bn.publish(counters, chunk, items)) {
      Kokkos::memory_fence();
      uint32_t sum = 0;
      for (uint32_t i = 0; i < bn.chunks; ++i) {
        const uint32_t v = bn.chunkBlocks(i);
        bn.chunkBlocks(i) = sum;
        sum += v;
      }
      counters(kRasterWork) = sum;
      counters(kSetupDone) = 0;
    }
  }
};

// Launches the write pass: WriteChunks' teams on GPUs, WriteChunksHost on
// host backends (not built for GPUs).
template <bool kHost>
void launchWrite(const SetupCommon& c, FrameBuffers& f, uint32_t chunks, uint32_t numTris, bool single,
                 const BlockNumbering& bn) {
  if constexpr (kHost) {
    using Host = std::conditional_t<kHost, WriteChunksHost, void>;  // dependent: not built for GPUs
    Kokkos::parallel_for("rast::setup::write", Kokkos::RangePolicy<Exec, Kokkos::IndexType<uint32_t>>(0, chunks),
                         Host{c, f.chunkOffset, f.counters, f.clipCount, f.tris, f.triCapacity, numTris, single ? 1 : 0, bn});
  } else {
    Kokkos::parallel_for("rast::setup::write",
                         lightweight(TeamPolicy(int(chunks), kTeamSize))
                             .set_scratch_size(0, Kokkos::PerTeam(WriteChunks::scratchBytes())),
                         WriteChunks{c, f.chunkOffset, f.counters, f.clipCount, f.tris, f.triCapacity, numTris, single ? 1 : 0, bn});
  }
}

}  // namespace

void scanExclusive(const char* label, const DView<uint32_t>& data, uint32_t n, const DView<uint32_t>& counters, int slot) {
  if (n == 0) {
    Kokkos::parallel_for(label, Range(0, 1), KOKKOS_LAMBDA(const int) { counters(slot) = 0; });
    return;
  }
  Kokkos::parallel_scan(label, Kokkos::RangePolicy<Exec, Kokkos::IndexType<uint32_t>>(0, n),
                        ExclusiveScan{data, counters, n, slot});
}

void primitiveSetup(const DeviceScene& s, FrameBuffers& f, bool cullBack, bool numberBlocks) {
  const uint32_t chunks = (s.numTris + kSetupChunk - 1) / kSetupChunk;
  f.setupChunks = chunks;
  ensureCapacity(f.chunkOffset, "frame.setupChunkOffset", chunks > 0 ? chunks : 1);
  BlockNumbering bn{f.workOffset, f.chunkBlocks, chunks, numberBlocks ? 1 : 0};
  if (numberBlocks) {
    ensureCapacity(f.workOffset, "frame.workOffset", f.triCapacity);
    ensureCapacity(f.chunkBlocks, "frame.setupChunkBlocks", chunks > 0 ? chunks : 1);
    bn.workOffset = f.workOffset;
    bn.chunkBlocks = f.chunkBlocks;
  }
  SetupCommon c{s.draws, s.drawTriStart, s.indices, f.clip, f.snap, s.numDraws, f.vp,
                guardBand(f.vp.width), guardBand(f.vp.height), cullBack ? 1 : 0};
  // Small scenes (one chunk) take one launch instead of two: launches, not
  // work, are most of their frame on a GPU.
  const bool single = chunks == 1;
  if (chunks > 1) {
    ensureCapacity(f.clipCount, "frame.setupClipCount", s.numTris);
    Kokkos::parallel_for("rast::setup::count", lightweight(TeamPolicy(int(chunks), kTeamSize)),
                         CountChunks{c, f.chunkOffset, f.counters, f.clipCount, s.numTris, chunks});
  }
  if (chunks > 0) {
    launchWrite<!kOnDevice>(c, f, chunks, s.numTris, single, bn);
  } else {  // no triangles: no raster triangles or items
    auto counters = f.counters;
    Kokkos::parallel_for("rast::setup::none", Range(0, 1), KOKKOS_LAMBDA(const int) {
      counters(kRasterTris) = 0;
      counters(kRasterWork) = 0;
    });
  }
}

}  // namespace rast
