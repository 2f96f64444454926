// Primitive assembly and triangle setup: fetch indices, clip in homogeneous
// space, cull, snap, and write the raster triangles in primitive order.
//
// The output is compact and ordered without atomics, in chunks of kSetupChunk
// drawn triangles, each drawn triangle giving 0 raster triangles (culled,
// degenerate, non-finite or off-screen), 1 (no clipping) or up to
// kMaxClipVerts-2 (clipped). For the visbuffer method the setup also numbers
// the raster's work items (the 8x8 blocks of each raster triangle's box,
// raster_rules.h): each raster triangle's first (workOffset) and the total
// (counters(kRasterWork)), so the raster needs no scan of its own.
//
// On a GPU, the write pass (WriteChunks): one team per chunk sets its
// triangles up into team scratch, scans their counts, learns where its chunk
// starts, and copies the triangles out word by word, so that neighbouring
// threads write neighbouring words. The copy matters: a thread storing its own
// 96-byte triangle sends 24 scattered 4-byte stores per warp instruction to
// L2, which made the write six times slower than setting up (0.31 vs 0.03 ms
// for a million triangles on the H100). Where a chunk starts: for scenes of
// up to kSetupLookBackMaxChunks chunks, from the chunks before it (a
// single-pass scan with decoupled look-back), in that one launch; for larger
// ones, from a count pass first (CountChunks), whose cost the one pass saves
// smaller scenes.
//
// On a host backend, where a team is one thread: one pass too
// (SetupChunksHost), each chunk set up into a buffer in cache, then copied
// after the chunks before it.
//
// The totals stay on the device, so no host round trip is needed inside the
// frame.
#include <cstring>
#include <thread>
#include <type_traits>

#include "backends/stream_store.h"
#include "pipeline/rules/alpha_items.h"
#include "pipeline/rules/raster_rules.h"
#include "pipeline/rules/visbuffer_blocks.h"
#include "pipeline/geometry/geometry.h"
#include "pipeline/geometry/triangle_setup.h"
#include "pipeline/data/test_hooks.h"

namespace rast {
namespace {

using namespace triangle_setup;

// The GPU's count pass, for scenes of more than kSetupLookBackMaxChunks
// chunks: one team per chunk counts its raster triangles (and, with blocks,
// visbuffer items), keeping each clipped triangle's counts for the write
// pass; the team that finishes last (a ticket: the fences order each team's
// totals before its ticket) scans the chunks' totals, by all its threads.
struct CountChunks {
  SetupCommon c;
  DView<uint32_t> chunkCount, chunkBlocks, counters, clipBlocks;
  DView<uint8_t> clipCount;
  uint32_t numTris, chunks;
  int32_t blocks;
  KOKKOS_INLINE_FUNCTION void operator()(const TeamMember& m) const {
    const uint32_t chunk = uint32_t(m.league_rank()), first = chunk * kSetupChunk;
    // Raster triangles above bit 40, items below: a chunk has fewer than 2^12
    // of the one and 2^36 of the other.
    uint64_t sum = 0;
    Kokkos::parallel_reduce(
        Kokkos::TeamThreadRange(m, chunkLength(chunk, numTris)),
        [&](const uint32_t i, uint64_t& acc) {
          RasterTri rt;
          bool clipped;
          uint32_t b = 0;
          const uint32_t k = setupOne<false>(c, first + i, rt, clipped, nullptr, blocks ? &b : nullptr);
          if (clipped) {
            clipCount(first + i) = uint8_t(k);  // at most kMaxClipVerts - 2
            if (blocks) clipBlocks(first + i) = b;
          }
          acc += uint64_t(k) << 40 | b;
        },
        sum);
    uint32_t last = 0;
    Kokkos::single(
        Kokkos::PerTeam(m),
        [&](uint32_t& isLast) {
          chunkCount(chunk) = uint32_t(sum >> 40);
          if (blocks) chunkBlocks(chunk) = uint32_t(sum & ((uint64_t(1) << 40) - 1));
          Kokkos::memory_fence();
          isLast = Kokkos::atomic_fetch_add(&counters(kSetupDone), 1u) == chunks - 1 ? 1u : 0u;
        },
        last);
    if (!last) return;
    Kokkos::memory_fence();
    // Volatile reads: the totals were written by other teams, maybe on other
    // multiprocessors, and must not come from a stale cache line (atomic
    // reads did the same, 30 us slower for tiny's 3,900 chunks on the H100).
    const volatile uint32_t* counts = chunkCount.data();
    const volatile uint32_t* items = chunkBlocks.data();
    const uint32_t lastCount = counts[chunks - 1], lastItems = blocks ? items[chunks - 1] : 0u;
    m.team_barrier();  // read before the scans overwrite them
    Kokkos::parallel_scan(Kokkos::TeamThreadRange(m, chunks), [&](const uint32_t i, uint32_t& upd, const bool final) {
      const uint32_t v = counts[i];
      if (final) chunkCount(i) = upd;
      upd += v;
    });
    if (blocks)
      Kokkos::parallel_scan(Kokkos::TeamThreadRange(m, chunks), [&](const uint32_t i, uint32_t& upd, const bool final) {
        const uint32_t v = items[i];
        if (final) chunkBlocks(i) = upd;
        upd += v;
      });
    m.team_barrier();
    Kokkos::single(Kokkos::PerTeam(m), [&]() {
      counters(kRasterTris) = chunkCount(chunks - 1) + lastCount;
      if (blocks) counters(kRasterWork) = chunkBlocks(chunks - 1) + lastItems;
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

// Chunk status for the write pass's look-back, kStatusWords 64-bit words per
// chunk: its raster triangles and visbuffer items alone (aggregate), then
// through the chunk (inclusive). A word holds the frame number
// (FrameUniforms::frame) it was published in above its 32-bit value, so that
// one load reads a value and whether it is this frame's (no fence between a
// flag and its value, and the loads of several words need not wait for each
// other), and nothing is reset between frames; the buffer starts zeroed and
// frames count from 1.
constexpr uint32_t kStatusWords = 4;
enum : uint32_t { kAggTris = 0, kAggItems, kIncTris, kIncItems };
KOKKOS_INLINE_FUNCTION uint64_t statusWord(uint32_t tag, uint32_t value) { return uint64_t(tag) << 32 | value; }
// Frames whose setup numbers the BLEND class's work items (setupNumbersBlendItems)
// publish their 64-bit counts too, each as two words of 32 bits (low, high),
// kBlendWords a chunk after every chunk's kStatusWords: frames without BLEND
// materials read what they did.
constexpr uint32_t kBlendWords = 4;
// A chunk's raster triangles and BLEND items in one 64-bit scan (WriteChunks):
// the one above bit kPieceShift, the other below. A drawn triangle yields at
// most kMaxClipVerts - 2 raster triangles, each of at most
// (kMaxFramebufferSide / 8)^2 items.
constexpr int kPieceShift = 40;
static_assert(uint64_t(kSetupChunk) * (kMaxClipVerts - 2) < (uint64_t(1) << (64 - kPieceShift)) &&
                  uint64_t(kSetupChunk) * (kMaxClipVerts - 2) * uint64_t(kMaxFramebufferSide >> kBlendBlockShift) *
                          uint64_t(kMaxFramebufferSide >> kBlendBlockShift) < (uint64_t(1) << kPieceShift),
              "a chunk's raster triangles and BLEND items share a 64-bit scan");
enum : uint32_t { kAggBlendLo = 0, kAggBlendHi, kIncBlendLo, kIncBlendHi };
KOKKOS_INLINE_FUNCTION uint64_t halvesValue(uint64_t lo, uint64_t hi) { return uint64_t(uint32_t(hi)) << 32 | uint32_t(lo); }
// Predecessors whose status one look-back step reads at once.
constexpr uint32_t kLookBackBatch = 4;

// The GPU's setup in one pass (Merrill and Garland's single-pass scan with
// decoupled look-back): each team takes the next chunk by ticket, sets up its
// triangles into scratch, publishes the chunk's totals, and sums the totals
// of the chunks before it, waiting only for chunks that drew earlier tickets
// (they are running, and never wait for later ones, so every wait ends).
struct WriteChunks {
  SetupCommon c;
  DView<uint64_t> status;
  DView<uint32_t> counters, workOffset;
  DView<FrameUniforms> frame;
  DView<RasterTri> tris;
  uint32_t capacity, numTris, chunks;
  int32_t blocks;  // number the visbuffer's work items
  // Without look-back: the count pass ran, and gives each chunk's first
  // raster triangle and item, and each clipped triangle's counts.
  int32_t lookBackMode;
  DView<uint32_t> chunkOffset, chunkBlocks, clipBlocks;
  DView<uint8_t> clipCount;
  DView<uint64_t> workHint;  // with blocks (visbuffer_blocks.h)
  OccluderList occ;          // with blocks, single-sample frames (visbuffer_blocks.h)
  // With look-back: number the BLEND class's work items (each raster
  // triangle's first into blendStart, the total into blendTotals(kBlendItems))
  // and clear the frame's other BLEND totals, as the alpha classes' scan
  // does where the setup does not (alpha_passes.cpp).
  int32_t blendItems = 0;
  DView<uint64_t> blendStart, blendTotals;

  static size_t scratchBytes() {
    // Kept under 32 KiB: at 32.1 KiB (a second scan array) the H100's setup
    // took 1-3 us more a frame; a switch of the shared-memory carve-out
    // between kernels is the likely cause, not a measured one.
    // A staged triangle's padding piece (the kTriQuads-th) holds its BLEND
    // items and their scan: no array of its own.
    return sizeof(Quad) * (kSetupChunk * kStageStride + 1) + 3 * sizeof(uint32_t) * (kSetupChunk + 1) + 80;
  }

  // The frame's BLEND work items, and its other BLEND totals cleared for the
  // passes that count into them (the last chunk's thread).
  KOKKOS_INLINE_FUNCTION void frameBlendTotals(uint64_t total) const {
    blendTotals(kBlendItems) = total;
    for (int k = kBlendFrags; k < kNumBlendTotals; ++k) blendTotals(k) = 0;
  }

  // One thread: publish this chunk's totals, add up the chunks before it, and
  // publish the inclusive totals. Returns the exclusive ones. Each step reads
  // the status of kLookBackBatch predecessors with independent loads, then
  // takes them in order: aggregates until the nearest inclusive total; a
  // predecessor with neither is read again in the next step. (One at a time,
  // each step waited a memory round trip.)
  // With blendItems, the chunk's BLEND items (blend) go the same way
  // (baseBlend), in their own words: a predecessor's totals are taken when
  // all of its words are this frame's.
  KOKKOS_INLINE_FUNCTION void lookBack(uint32_t chunk, uint32_t tot, uint32_t items, uint64_t blend,
                                       uint32_t& baseTris, uint32_t& baseItems, uint64_t& baseBlend) const {
    baseTris = 0;
    baseItems = 0;
    baseBlend = 0;
    if (chunks == 1) {  // nobody looks back at it
      counters(kRasterTris) = tot;
      if (blocks) counters(kRasterWork) = items;
      if (blendItems) frameBlendTotals(blend);
      return;
    }
    const uint32_t tag = frame(0).frame;
    volatile uint64_t* st = status.data();
    volatile uint64_t* sb = st + size_t(chunks) * kStatusWords;  // the BLEND items' words
    const bool bl = blendItems != 0;
    auto ready = [tag](uint64_t w) { return uint32_t(w >> 32) == tag; };
    if (chunk > 0) {
      st[chunk * kStatusWords + kAggTris] = statusWord(tag, tot);
      st[chunk * kStatusWords + kAggItems] = statusWord(tag, items);
      if (bl) {
        sb[chunk * kBlendWords + kAggBlendLo] = statusWord(tag, uint32_t(blend));
        sb[chunk * kBlendWords + kAggBlendHi] = statusWord(tag, uint32_t(blend >> 32));
      }
      // Predecessors below p are still to add. Chunk 0 publishes its
      // inclusive totals at once (no aggregate): p never passes it.
      for (uint32_t p = chunk, done = 0; !done;) {
        uint64_t w[kLookBackBatch][kStatusWords], v[kLookBackBatch][kBlendWords];
        for (uint32_t j = 0; j < kLookBackBatch; ++j) {
          for (uint32_t k = 0; k < kStatusWords; ++k) w[j][k] = j < p ? st[(p - 1 - j) * kStatusWords + k] : 0u;
          for (uint32_t k = 0; k < kBlendWords; ++k) v[j][k] = bl && j < p ? sb[(p - 1 - j) * kBlendWords + k] : 0u;
        }
        uint32_t j = 0;
        for (; j < kLookBackBatch && j < p; ++j) {
          if (ready(w[j][kIncTris]) && ready(w[j][kIncItems]) &&
              (!bl || (ready(v[j][kIncBlendLo]) && ready(v[j][kIncBlendHi])))) {
            baseTris += uint32_t(w[j][kIncTris]);
            baseItems += uint32_t(w[j][kIncItems]);
            if (bl) baseBlend += halvesValue(v[j][kIncBlendLo], v[j][kIncBlendHi]);
            done = 1;
            break;
          }
          if (!ready(w[j][kAggTris]) || !ready(w[j][kAggItems]) ||
              (bl && (!ready(v[j][kAggBlendLo]) || !ready(v[j][kAggBlendHi]))))
            break;  // not yet: read it again
          baseTris += uint32_t(w[j][kAggTris]);
          baseItems += uint32_t(w[j][kAggItems]);
          if (bl) baseBlend += halvesValue(v[j][kAggBlendLo], v[j][kAggBlendHi]);
        }
        p -= done ? 0u : j;
      }
    }
    st[chunk * kStatusWords + kIncTris] = statusWord(tag, baseTris + tot);
    st[chunk * kStatusWords + kIncItems] = statusWord(tag, baseItems + items);
    if (bl) {
      sb[chunk * kBlendWords + kIncBlendLo] = statusWord(tag, uint32_t(baseBlend + blend));
      sb[chunk * kBlendWords + kIncBlendHi] = statusWord(tag, uint32_t((baseBlend + blend) >> 32));
    }
    if (chunk + 1 == chunks) {
      counters(kRasterTris) = baseTris + tot;
      if (blocks) counters(kRasterWork) = baseItems + items;
      if (bl) frameBlendTotals(baseBlend + blend);
    }
  }

  KOKKOS_INLINE_FUNCTION void operator()(const TeamMember& m) const {
    auto& shmem = m.team_scratch(0);
    Quad* staged = static_cast<Quad*>(shmem.get_shmem_aligned(sizeof(Quad) * kSetupChunk * kStageStride, sizeof(Quad)));
    uint32_t* count = static_cast<uint32_t*>(shmem.get_shmem_aligned(sizeof(uint32_t) * kSetupChunk, sizeof(uint32_t)));
    uint32_t* offset = static_cast<uint32_t*>(shmem.get_shmem_aligned(sizeof(uint32_t) * kSetupChunk, sizeof(uint32_t)));
    uint32_t* blk = static_cast<uint32_t*>(shmem.get_shmem_aligned(sizeof(uint32_t) * kSetupChunk, sizeof(uint32_t)));
    // [0] ticket, [1] first raster triangle, [2] first item, [3] the last
    // triangle's items, [4..5] first BLEND item (low, high)
    uint32_t* shared = static_cast<uint32_t*>(shmem.get_shmem_aligned(sizeof(uint32_t) * 8, sizeof(uint32_t)));
    // 0. This team's chunk: by ticket, so that earlier chunks are running.
    //    The last ticket's holder resets the counter for the next frame (all
    //    tickets are drawn by then).
    const bool ticket = lookBackMode && chunks > 1;
    if (ticket) {
      Kokkos::single(Kokkos::PerTeam(m), [&]() {
        const uint32_t ch = Kokkos::atomic_fetch_add(&counters(kSetupDone), 1u);
        if (ch + 1 == chunks) counters(kSetupDone) = 0;
        shared[0] = ch;
      });
      m.team_barrier();
    }
    const uint32_t chunk = ticket ? shared[0] : uint32_t(m.league_rank()), first = chunk * kSetupChunk;
    const uint32_t len = chunkLength(chunk, numTris);
    // 1. Set up every triangle of the chunk; unclipped ones land in scratch,
    //    clipped ones are clipped to be counted (and again to be written).
    Kokkos::parallel_for(Kokkos::TeamThreadRange(m, len), [&](const uint32_t i) {
      bool clipped;
      RasterTri rt;
      uint32_t b = 0, bi = 0;
      const uint32_t k = setupOne<true>(c, first + i, rt, clipped, lookBackMode ? nullptr : clipCount.data(),
                                        blocks ? &b : nullptr, lookBackMode || !blocks ? nullptr : clipBlocks.data(),
                                        blendItems ? &bi : nullptr);
      count[i] = clipped ? (k | kClippedFlag) : k;
      if (blendItems) staged[i * kStageStride + kTriQuads].w[0] = bi;
      blk[i] = b;
      if (i + 1 == len) shared[3] = b;  // the scan below overwrites blk in place
      if (k == 1 && !clipped) {
        Quad q[kTriQuads];
        memcpy(q, &rt, sizeof(rt));  // a register copy once compiled
        for (uint32_t j = 0; j < kTriQuads; ++j) staged[i * kStageStride + j] = q[j];
      }
    });
    m.team_barrier();
    // 2. Where each triangle's pieces (and items) go within the chunk's.
    //    With blendItems, one 64-bit scan numbers the pieces (above bit
    //    kPieceShift) and the BLEND items (below), each triangle's first
    //    BLEND item into its padding piece: a second scan cost the frame's
    //    setup a microsecond.
    if (blendItems)
      Kokkos::parallel_scan(Kokkos::TeamThreadRange(m, len), [&](const uint32_t i, uint64_t& upd, const bool final) {
        Quad& q = staged[i * kStageStride + kTriQuads];
        const uint64_t v = uint64_t(count[i] & ~kClippedFlag) << kPieceShift | q.w[0];
        if (final) {
          offset[i] = uint32_t(upd >> kPieceShift);
          const uint64_t b = upd & ((uint64_t(1) << kPieceShift) - 1);
          q.w[2] = uint32_t(b);
          q.w[3] = uint32_t(b >> 32);
        }
        upd += v;
      });
    else
      Kokkos::parallel_scan(Kokkos::TeamThreadRange(m, len), [&](const uint32_t i, uint32_t& upd, const bool final) {
        const uint32_t k = count[i] & ~kClippedFlag;
        if (final) offset[i] = upd;
        upd += k;
      });
    if (blocks)
      Kokkos::parallel_scan(Kokkos::TeamThreadRange(m, len), [&](const uint32_t i, uint32_t& upd, const bool final) {
        const uint32_t v = blk[i];
        if (final) blk[i] = upd;
        upd += v;
      });
    m.team_barrier();
    // A staged triangle's first BLEND item within the chunk's.
    auto blendFirst = [&](uint32_t i) {
      const Quad& q = staged[i * kStageStride + kTriQuads];
      return uint64_t(q.w[3]) << 32 | q.w[2];
    };
    // 3. Where the chunk's go: after the chunks before it.
    Kokkos::single(Kokkos::PerTeam(m), [&]() {
      if (!lookBackMode) {
        shared[1] = chunkOffset(chunk);
        shared[2] = blocks ? chunkBlocks(chunk) : 0u;
        return;
      }
      const uint32_t tot = len ? offset[len - 1] + (count[len - 1] & ~kClippedFlag) : 0u;
      const uint32_t items = blocks && len ? blk[len - 1] + shared[3] : 0u;
      const uint64_t blend = blendItems && len ? blendFirst(len - 1) + staged[(len - 1) * kStageStride + kTriQuads].w[0] : 0u;
      uint64_t baseBlend;
      lookBack(chunk, tot, items, blend, shared[1], shared[2], baseBlend);
      shared[4] = uint32_t(baseBlend);
      shared[5] = uint32_t(baseBlend >> 32);
    });
    m.team_barrier();
    const uint32_t base = shared[1], itemBase = shared[2];
    const uint64_t blendBase = uint64_t(shared[5]) << 32 | shared[4];
    // 4. Unclipped triangles, copied piece by piece: neighbouring threads
    //    write neighbouring 16 bytes (coalesced on a GPU).
    Quad* dst = reinterpret_cast<Quad*>(tris.data());
    Kokkos::parallel_for(Kokkos::TeamThreadRange(m, len * kTriQuads), [&](const uint32_t w) {
      const uint32_t i = w / kTriQuads, j = w - i * kTriQuads;
      if (count[i] != 1u) return;  // culled, or clipped (written below)
      const uint32_t o = base + offset[i];
      if (o < capacity) dst[size_t(o) * kTriQuads + j] = staged[i * kStageStride + j];
    });
    // 5. Each raster triangle's first item (and the hints among them);
    //    clipped triangles (rare) are clipped again and their pieces written
    //    directly.
    const uint32_t hints = uint32_t(workHint.extent(0)), tag = blocks ? frame(0).frame : 0u;
    Kokkos::parallel_for(Kokkos::TeamThreadRange(m, len), [&](const uint32_t i) {
      uint32_t o = base + offset[i];
      uint32_t item = itemBase + (blocks ? blk[i] : 0u);
      uint64_t blendItem = blendItems ? blendBase + blendFirst(i) : 0u;
      if (!(count[i] & kClippedFlag)) {
        if (blendItems && count[i] == 1u && o < capacity) blendStart(o) = blendItem;
        if (blocks && count[i] == 1u && o < capacity) {
          workOffset(o) = item;
          const uint32_t end = itemBase + (i + 1 < len ? blk[i + 1] : blk[len - 1] + shared[3]);
          markWorkHints(workHint.data(), hints, tag, item, end, o);
          occ.add(*reinterpret_cast<const RasterTri*>(&staged[i * kStageStride]), o);
        }
        return;
      }
      uint32_t vi[3];
      bool frontCCW, cull;
      int32_t cls;
      c.corners(first + i, vi, frontCCW, cull, cls);
      c.clipAndSetUp<true>(first + i, vi, frontCCW, cull, cls, [&](const RasterTri& rt) {
        if (o < capacity) {
          tris(o) = rt;
          if (blendItems) blendStart(o) = blendItem;
          uint32_t bw;
          if (blocks) {
            workOffset(o) = item;
            const uint32_t end = item + visBlocksOf(rt, bw);
            markWorkHints(workHint.data(), hints, tag, item, end, o);
            occ.add(rt, o);
            item = end;
          }
        }
        if (blendItems) blendItem += classItems(rt, c.vp, kAlphaBlend);
        ++o;
      });
    });
  }
};

// The setup on a host backend, in one pass, where a team is one thread that
// walks its chunk in order (the single-pass scan of WriteChunks, in a host's
// terms). Each work item takes the next chunk by ticket and sets its
// triangles up into a buffer on its stack (kHostStaged of them: 24 KiB, in
// cache), then waits for the totals through the chunk before, publishes its
// own, and copies the buffer to its place. The wait is short: the chunk
// before drew the previous ticket, so it started earlier, and its holder is
// running and waits only for earlier chunks. A chunk whose raster triangles
// overflow the buffer (clipping makes up to kMaxClipVerts - 2 of one) waits
// for its place then, and writes the rest directly. The same triangles at the
// same offsets as the GPU's setup.
//
// This replaced a count pass over every triangle before a write pass. The
// copy of a large scene's triangles (more than kHostSetupStreamMinBytes) uses
// streaming stores: the raster reads them from memory anyway, and plain
// stores of a whole buffer at once first read every line they write (tiny,
// 1920x1080, two cores: setup 19 ms with the count pass, 20.5-22.9 in one
// pass with plain stores, 16.8-18.0 streamed). Host code only: the waits
// yield the thread.
constexpr uint32_t kHostStaged = kSetupChunk;
struct SetupChunksHost {
  SetupCommon c;
  DView<uint64_t> status;  // per chunk kStatusWords, as WriteChunks' (kIncTris and kIncItems used)
  DView<uint32_t> counters, workOffset;
  DView<RasterTri> tris;
  uint32_t capacity, numTris, chunks;
  int32_t blocks;            // number the visbuffer's work items
  int32_t stream;            // copy the staged triangles with streaming stores
  uint32_t stagedRoom;       // kHostStaged (fewer: TestHooks::hostSetupStaged)
  DView<uint64_t> workHint;  // with blocks (visbuffer_blocks.h)
  DView<FrameUniforms> frame;
  OccluderList occ;          // with blocks, single-sample frames (visbuffer_blocks.h)

  // Raster triangle rt is number o: its work items from `item` on (with
  // blocks). Advances both.
  void number(const RasterTri& rt, uint32_t& o, uint32_t& item, uint32_t tag) const {
    if (blocks) {
      uint32_t bw;
      const uint32_t end = item + visBlocksOf(rt, bw);
      if (o < capacity) {
        workOffset(o) = item;
        markWorkHints(workHint.data(), uint32_t(workHint.extent(0)), tag, item, end, o);
        occ.add(rt, o);
      }
      item = end;
    }
    ++o;
  }

  // Raster triangle rt stored as number o (within the capacity), and numbered.
  void write(const RasterTri& rt, uint32_t& o, uint32_t& item, uint32_t tag) const {
    if (o < capacity) tris(o) = rt;
    number(rt, o, item, tag);
  }

  // The raster triangles and work items before chunk `chunk`: the totals
  // through the chunk before, once published this frame.
  void waitBase(uint32_t chunk, uint32_t tag, uint32_t& o, uint32_t& item) const {
    o = 0;
    item = 0;
    if (chunk == 0) return;
    const uint64_t* st = status.data() + size_t(chunk - 1) * kStatusWords;
    for (uint32_t spins = 0;; ++spins) {
      const uint64_t t = __atomic_load_n(st + kIncTris, __ATOMIC_ACQUIRE);
      const uint64_t w = __atomic_load_n(st + kIncItems, __ATOMIC_ACQUIRE);
      if (uint32_t(t >> 32) == tag && uint32_t(w >> 32) == tag) {
        o = uint32_t(t);
        item = uint32_t(w);
        return;
      }
      if (spins >= 64) std::this_thread::yield();  // its holder may be off the core
    }
  }

  // The totals through chunk `chunk`: for the chunk after it, or (the last)
  // the frame's.
  void publish(uint32_t chunk, uint32_t tag, uint32_t o, uint32_t item) const {
    if (chunk + 1 == chunks) {
      counters(kRasterTris) = o;
      if (blocks) counters(kRasterWork) = item;
      return;
    }
    uint64_t* st = status.data() + size_t(chunk) * kStatusWords;
    __atomic_store_n(st + kIncItems, statusWord(tag, item), __ATOMIC_RELEASE);
    __atomic_store_n(st + kIncTris, statusWord(tag, o), __ATOMIC_RELEASE);
  }

  void operator()(const uint32_t) const {
    // This item's chunk: by ticket, so that earlier chunks are running. The
    // last ticket's holder resets the counter for the next frame.
    uint32_t chunk = 0;
    if (chunks > 1) {
      chunk = Kokkos::atomic_fetch_add(&counters(kSetupDone), 1u);
      if (chunk + 1 == chunks) counters(kSetupDone) = 0;
    }
    const uint32_t first = chunk * kSetupChunk, len = chunkLength(chunk, numTris);
    const uint32_t tag = frame(0).frame;
    RasterTri staged[kHostStaged];
    const uint32_t room = stagedRoom;
    uint32_t n = 0, stagedItems = 0;
    bool direct = false;  // the chunk's place is known: write at o, item
    uint32_t o = 0, item = 0;
    auto emit = [&](const RasterTri& rt) {
      if (!direct) {
        if (n < room) {
          staged[n++] = rt;
          uint32_t bw;
          if (blocks) stagedItems += visBlocksOf(rt, bw);
          return;
        }
        waitBase(chunk, tag, o, item);  // the buffer is full: write it, then go on directly
        for (uint32_t i = 0; i < n; ++i) write(staged[i], o, item, tag);
        direct = true;
      }
      write(rt, o, item, tag);
    };
    for (uint32_t i = 0; i < len; ++i) {
      bool clipped;
      RasterTri spare;
      const bool inPlace = !direct && n < room;  // the common case: set up straight into the buffer
      RasterTri& rt = inPlace ? staged[n] : spare;
      const uint32_t k = setupOne<true, false>(c, first + i, rt, clipped, nullptr);
      if (!clipped) {
        if (k == 1 && inPlace) {
          ++n;
          uint32_t bw;
          if (blocks) stagedItems += visBlocksOf(rt, bw);
        } else if (k == 1) {
          emit(rt);
        }
        continue;
      }
      uint32_t vi[3];  // clipped (rare)
      bool frontCCW, cull;
      int32_t cls;
      c.corners(first + i, vi, frontCCW, cull, cls);
      c.clipAndSetUp<true>(first + i, vi, frontCCW, cull, cls, emit);
    }
    if (!direct) {
      waitBase(chunk, tag, o, item);
      const uint32_t end = o + n, endItems = item + stagedItems;
      publish(chunk, tag, end, endItems);  // before the copy: the next chunk need not wait for it
      const uint32_t fit = o < capacity ? (capacity - o < n ? capacity - o : n) : 0u;
      if (stream) {
        streamCopy16(tris.data() + o, staged, size_t(fit) * kTriQuads);
        streamFence();
      } else {
        for (uint32_t i = 0; i < fit; ++i) tris(o + i) = staged[i];
      }
      if (blocks)
        for (uint32_t i = 0; i < n; ++i) number(staged[i], o, item, tag);
      return;
    }
    publish(chunk, tag, o, item);
  }
};


// Launches the setup: one pass of WriteChunks' teams of teamSize threads on
// GPUs (and on host backends under TestHooks::gpuSetupOnHostTeam); one pass of
// SetupChunksHost on host backends (not built for GPUs).
template <bool kHost>
void launchSetup(const SetupCommon& c, FrameBuffers& f, uint32_t chunks, uint32_t numTris, bool blocks, int teamSize,
                 const OccluderList& occ, bool blendItems) {
  if constexpr (kHost) {
    using Host = std::conditional_t<kHost, SetupChunksHost, void>;  // dependent: not built for GPUs
    const int32_t stream = testHooks().hostSetupStream != 0 ? testHooks().hostSetupStream > 0
                                                        : size_t(numTris) * sizeof(RasterTri) > kHostSetupStreamMinBytes;
    const uint32_t room = testHooks().hostSetupStaged > 0 && testHooks().hostSetupStaged < int(kHostStaged)
                              ? uint32_t(testHooks().hostSetupStaged) : kHostStaged;
    if (chunks > 1 && f.setupStatus.extent(0) < size_t(chunks) * kStatusWords)  // zeroed: no frame's tag yet
      f.setupStatus = allocZeroed<uint64_t>("frame.setupStatus", size_t(chunks) * kStatusWords);
    Kokkos::parallel_for("rast::setup::write", Kokkos::RangePolicy<Exec, Kokkos::IndexType<uint32_t>>(0, chunks),
                         Host{c, f.setupStatus, f.counters, f.workOffset, f.tris, f.triCapacity, numTris, chunks,
                              blocks ? 1 : 0, stream, room, f.workHint, f.uniforms, occ});
  } else {
    // The look-back's wait grows with the number of chunks (one thread walks
    // back, kLookBackBatch chunks a step): beyond kSetupLookBackMaxChunks a
    // count pass first.
    const bool lookBack = chunks <= kSetupLookBackMaxChunks;
    ensureCapacity(f.chunkOffset, "frame.setupChunkOffset", chunks);
    const size_t words = size_t(chunks) * (kStatusWords + kBlendWords);
    if (lookBack && f.setupStatus.extent(0) < words)  // zeroed: no flag of a frame yet
      f.setupStatus = allocZeroed<uint64_t>("frame.setupStatus", words);
    if (!lookBack) {
      ensureCapacity(f.clipCount, "frame.setupClipCount", numTris);
      ensureCapacity(f.chunkBlocks, "frame.setupChunkBlocks", chunks);
      if (blocks) ensureCapacity(f.clipBlocks, "frame.setupClipBlocks", numTris);
      Kokkos::parallel_for("rast::setup::count", lightweight(TeamPolicy(int(chunks), teamSize)),
                           CountChunks{c, f.chunkOffset, f.chunkBlocks, f.counters, f.clipBlocks, f.clipCount, numTris,
                                       chunks, blocks ? 1 : 0});
    }
    Kokkos::parallel_for("rast::setup::write",
                         lightweight(TeamPolicy(int(chunks), teamSize))
                             .set_scratch_size(0, Kokkos::PerTeam(WriteChunks::scratchBytes())),
                         WriteChunks{c, f.setupStatus, f.counters, f.workOffset, f.uniforms, f.tris, f.triCapacity, numTris,
                                     chunks, blocks ? 1 : 0, lookBack ? 1 : 0, f.chunkOffset, f.chunkBlocks, f.clipBlocks,
                                     f.clipCount, blocks ? f.workHint : DView<uint64_t>(), occ, blendItems ? 1 : 0,
                                     f.blend.blendStart, f.blend.totals});
  }
}

}  // namespace

bool setupNumbersBlendItems(uint32_t numTris) {
  const uint32_t chunks = (numTris + kSetupChunk - 1) / kSetupChunk;
  const bool writeChunks = kOnDevice || testHooks().gpuSetupOnHostTeam > 0;  // primitiveSetup's choice
  return writeChunks && chunks > 0 && chunks <= kSetupLookBackMaxChunks;
}

void primitiveSetup(const DeviceScene& s, FrameBuffers& f, CullFaces cull, bool numberBlocks, bool occluders,
                    bool blend) {
  const uint32_t chunks = (s.numTris + kSetupChunk - 1) / kSetupChunk;
  const bool blendItems = blend && setupNumbersBlendItems(s.numTris);
  if (blendItems) {
    if (!f.blend.totals.data()) f.blend.totals = allocZeroed<uint64_t>("blend.totals", kNumBlendTotals);
    ensureCapacity(f.blend.blendStart, "blend.blendStart", f.triCapacity);
  }
  if (numberBlocks) {
    ensureCapacity(f.workOffset, "frame.workOffset", f.triCapacity);
    // A hint per raster triangle, and a few more for scenes of large ones;
    // zeroed: no frame's tag yet.
    if (f.workHint.extent(0) < size_t(f.triCapacity) + 256)
      f.workHint = allocZeroed<uint64_t>("frame.workHint", size_t(f.triCapacity) + 256);
  }
  // The occluder candidates of a single-sample visbuffer frame (visbuffer_blocks.h);
  // the raster zeroes the count for the next frame.
  OccluderList occ;
  if (numberBlocks && occluders && f.vp.samples.count == 1) {
    if (!f.occCount.data()) f.occCount = allocZeroed<uint64_t>("frame.occCount", 1);
    ensureCapacity(f.occStart, "frame.occStart", f.triCapacity);
    ensureCapacity(f.occTri, "frame.occTri", f.triCapacity);
    occ = OccluderList{f.occCount.data(), f.occStart.data(), f.occTri.data(), f.triCapacity};
  }
  SetupCommon c{s.draws, s.drawTriStart, s.triDraw, s.indices, f.clip, f.snap, s.numDraws, f.vp,
                guardBand(f.vp.width), guardBand(f.vp.height), int32_t(cull), s.alphaDraws,
                s.hasAlphaClasses() ? 1 : 0};
  const int gpuTeamOnHost = testHooks().gpuSetupOnHostTeam;
  if (chunks > 0 && !kOnDevice && gpuTeamOnHost > 0) {
    launchSetup<false>(c, f, chunks, s.numTris, numberBlocks, gpuTeamOnHost, occ, blendItems);
  } else if (chunks > 0) {
    launchSetup<!kOnDevice>(c, f, chunks, s.numTris, numberBlocks, kTeamSize, occ, blendItems);
  } else {  // no triangles: no raster triangles or items
    auto counters = f.counters;
    Kokkos::parallel_for("rast::setup::none", Range(0, 1), KOKKOS_LAMBDA(const int) {
      counters(kRasterTris) = 0;
      counters(kRasterWork) = 0;
    });
  }
}

}  // namespace rast
