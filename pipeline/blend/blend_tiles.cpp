// The BLEND methods that walk tile lists (docs/transparency.md, "exact and
// sorted: tile lists, peeled in registers"; weighted too): no fragment is
// stored. Before shading (the opaque depth is still in the visibility buffer):
//   tiles_count, tiles_layout, tiles_fill: a counted two-pass layout of the
//     BLEND work items (raster triangle, 8x8 block): per block the list of
//     the triangles that cover a sample of it, 4 bytes an entry; an item whose
//     triangle covers no sample of its block is left out (exact test on the
//     block's corner samples). The order inside a list depends on the thread
//     schedule; exact's and sorted's results do not (their keys order them);
//   opaque_depth: the opaque depth of every sample, which shading clears
//     (unless the shade stage writes it: BlendPlan::shadeDepth).
// Where the last frame's lists were short (listStrideFor), each block's list
// has fixed room at block x stride instead: tiles_fill alone writes it (its
// cursor the block's count), and tiles_longest finds the longest (the glTF
// shading's team form: its classification, uniform_blocks.h); a list
// that outgrows its room makes the frame be drawn again, counted.
// After shading, tiles_sort (weighted): each list that the resolve walks in
// place put in raster-index order, the order its sums add their terms in
// (the team form ranks the lists that fit its scratch; the longest list is
// known by then, so a frame with none longer sorts nothing); then resolve:
// per sample its block's list walked and its
// fragments composited front to back, peeled K at a time, or summed
// (weighted) (peel.h); on a GPU a team a block (peel_team.h). This file
// launches the frame's instance.
#include "pipeline/blend/peel_block.h"
#include "pipeline/blend/peel_team.h"
#include "pipeline/data/test_hooks.h"

namespace rast {
namespace blending {
namespace {

// tiles_sort: lists up to this long are insertion-sorted by a CPU thread;
// a GPU warp ranks lists up to kBlendSortScratchEntries in scratch (4 KiB).
constexpr uint32_t kBlendSortInsertionMax = 64, kBlendSortScratchEntries = 1024;

// A listed triangle's set-up for its items: edges, box, and per edge the
// largest step from a pixel centre to one of its samples, with the bias.
struct ItemTri {
  uint32_t index = ~0u;
  Edges e{};
  ItemBox b{};
  int64_t reach[3] = {0, 0, 0};
};

// Whether the triangle covers no sample of the pixels [x0, x1] x [y0, y1]:
// some edge is not positive (with its bias) at any of their samples. An edge
// function is linear: its largest value over the pixel centres is at the
// corner its signs point to, and a sample adds the same offset in every
// pixel, so the largest over the samples is that corner's value plus the
// edge's largest offset (reach): exact, no fragment is lost.
KOKKOS_INLINE_FUNCTION bool blockMissed(const ItemTri& it, int32_t x0, int32_t x1, int32_t y0, int32_t y1) {
  for (int i = 0; i < 3; ++i)
    if (it.e.eval(i, it.e.A[i] > 0 ? x1 : x0, it.e.B[i] > 0 ? y1 : y0) + it.reach[i] <= 0) return true;
  return false;
}

// tiles_count (pass 0) and tiles_fill (pass 1): each BLEND work item whose
// triangle covers a sample of its block, counted into the block's count, then
// written at its block's cursor (tileEnd, the scan's start before the fill).
// A GPU thread takes every threads-th item (neighbouring threads, neighbouring
// items). A CPU thread takes a band of block rows where the items are many
// against the triangles (large ones: layers), every triangle's items in its
// band: no two threads count into or fill one block, so no atomics (two
// threads adding to the same blocks' counts at once made the stage three
// times slower on 2 cores than on one), and each list comes out in
// raster-index order. Else (many small triangles, which seldom share a
// block) a contiguous share of the items, so that their owner is found by
// stepping and set up once per triangle.
struct TileItems {
  DView<RasterTri> tris;
  DView<uint64_t> start, totals;
  DView<uint32_t> counters, tileCount, tileEnd, tileTris;
  Viewport vp;
  uint32_t capacity, threads, blocksX, blocksY;
  uint64_t tileCapacity;
  int32_t fill;
  uint32_t stride;  // the strided layout's (fill only; else 0)
  KOKKOS_INLINE_FUNCTION void prepare(uint32_t i, ItemTri& it) const {
    const RasterTri& t = tris(i);
    it.index = i;
    it.e = Edges(t);
    it.b = itemBox(t, vp);
    const SamplePattern& sp = vp.samples;
    for (int k = 0; k < 3; ++k) {
      int64_t m = it.e.atSample(k, 0, sp.ox[0], sp.oy[0]);
      for (int s = 1; s < sp.count; ++s) {
        const int64_t v = it.e.atSample(k, 0, sp.ox[s], sp.oy[s]);
        m = v > m ? v : m;
      }
      it.reach[k] = m + it.e.bias[k];
    }
  }
  template <bool kOwned = false>  // kOwned: no other thread counts into or fills the item's block
  KOKKOS_INLINE_FUNCTION void item(uint64_t w, const ItemTri& it) const {
    const ItemBox& b = it.b;
    const uint32_t local = uint32_t(w - start(it.index));
    const int32_t bx = b.bx0 + int32_t(local % uint32_t(b.bw)), by = b.by0 + int32_t(local / uint32_t(b.bw));
    const int32_t x0 = b.minX > (bx << kItemShift) ? b.minX : (bx << kItemShift);
    const int32_t x1 = b.maxX < ((bx + 1) << kItemShift) - 1 ? b.maxX : ((bx + 1) << kItemShift) - 1;
    const int32_t y0 = b.minY > (by << kItemShift) ? b.minY : (by << kItemShift);
    const int32_t y1 = b.maxY < ((by + 1) << kItemShift) - 1 ? b.maxY : ((by + 1) << kItemShift) - 1;
    if (blockMissed(it, x0, x1, y0, y1)) return;
    const uint32_t block = uint32_t(by) * blocksX + uint32_t(bx);
    if (stride) {  // the block's count is its cursor
      const uint32_t slot = kOwned ? tileCount(block)++ : Kokkos::atomic_fetch_add(&tileCount(block), 1u);
      if (slot < stride)
        tileTris(uint64_t(block) * stride + slot) = it.index;
      else
        totals(kBlendListed) = tileCapacity + 1;  // not read: the frame is drawn again, counted (lastFrameFit)
      return;
    }
    if (!fill) {
      if (kOwned)
        ++tileCount(block);
      else
        Kokkos::atomic_fetch_add(&tileCount(block), 1u);
      return;
    }
    const uint32_t slot = kOwned ? tileEnd(block)++ : Kokkos::atomic_fetch_add(&tileEnd(block), 1u);
    if (slot < tileCapacity) tileTris(slot) = it.index;  // else the frame is drawn again with more room (lastFrameFit)
  }
  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t th) const {
    const uint64_t total = totals(kBlendItems);
    const uint32_t n = counters(kRasterTris) < capacity ? counters(kRasterTris) : capacity;
    ItemTri it;
    if (kOnDevice) {
      for (uint64_t w = th; w < total; w += threads) {
        const uint32_t i = itemOwner(start, n, w);
        if (i != it.index) prepare(i, it);
        item(w, it);
      }
      return;
    }
    if (total >= uint64_t(n) * threads * 4) {  // bands: every thread reads every triangle's item count
      const int32_t by0 = int32_t(uint64_t(blocksY) * th / threads), by1 = int32_t(uint64_t(blocksY) * (th + 1) / threads);
      for (uint32_t i = 0; i < n; ++i) {
        const uint64_t w0 = start(i), w1 = i + 1 < n ? start(i + 1) : total;
        if (w1 == w0) continue;  // not BLEND, or off the frame
        prepare(i, it);
        const ItemBox& b = it.b;
        const int32_t bh = int32_t((w1 - w0) / uint64_t(b.bw));
        const int32_t r0 = b.by0 > by0 ? b.by0 : by0, r1 = b.by0 + bh < by1 ? b.by0 + bh : by1;
        for (int32_t by = r0; by < r1; ++by)
          for (int32_t c = 0; c < b.bw; ++c) item<true>(w0 + uint64_t(by - b.by0) * uint64_t(b.bw) + uint64_t(c), it);
      }
      return;
    }
    const uint64_t share = (total + threads - 1) / threads, w0 = share * th;
    const uint64_t w1 = w0 + share < total ? w0 + share : total;
    uint32_t i = w0 < w1 ? itemOwner(start, n, w0) : 0;
    for (uint64_t w = w0; w < w1; ++w) {
      while (i + 1 < n && start(i + 1) <= w) ++i;  // itemOwner's answer, stepping
      if (i != it.index) prepare(i, it);
      item(w, it);
    }
  }
};

// tiles_layout: exclusive scan of the block counts into tileEnd (the fill's
// cursors), the 64-bit total into totals(kBlendListed): a total beyond any
// capacity is seen as such and never wraps.
struct TileScan {
  DView<uint32_t> tileCount, tileEnd;
  DView<uint64_t> totals;
  uint32_t n;
  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t i, uint64_t& upd, const bool final) const {
    const uint32_t v = tileCount(i);
    if (final) {
      raiseTotal(totals(kBlendLongest), v);
      tileEnd(i) = uint32_t(upd);
      if (i + 1 == n) totals(kBlendListed) = upd + v;
    }
    upd += v;
  }
};

// tiles_sort: a block's list in raster-index order (weighted), in place. A
// CPU thread takes a block: an insertion sort for short lists (mostly in
// order already: a thread fills a contiguous share of the items), a heap sort
// for long ones (a block may list any number of triangles). A GPU takes a
// warp a block: each entry's rank counted in scratch (a thread's sort of a
// list in global memory cost 0.5 ms for 64 layers on the H100), the heap
// sort past the scratch.
KOKKOS_INLINE_FUNCTION void siftDown(uint32_t* v, uint64_t root, const uint64_t n) {
  for (;;) {
    uint64_t c = 2 * root + 1;
    if (c >= n) return;
    if (c + 1 < n && v[c + 1] > v[c]) ++c;
    if (!(v[c] > v[root])) return;
    const uint32_t t = v[c];
    v[c] = v[root];
    v[root] = t;
    root = c;
  }
}
KOKKOS_INLINE_FUNCTION void sortList(uint32_t* v, const uint32_t n) {
  if (n <= kBlendSortInsertionMax) {
    for (uint32_t k = 1; k < n; ++k) {
      const uint32_t x = v[k];
      uint32_t j = k;
      for (; j > 0 && v[j - 1] > x; --j) v[j] = v[j - 1];
      v[j] = x;
    }
    return;
  }
  for (uint64_t i = n / 2; i-- > 0;) siftDown(v, i, n);
  for (uint64_t e = n; e-- > 1;) {
    const uint32_t t = v[0];
    v[0] = v[e];
    v[e] = t;
    siftDown(v, 0, e);
  }
}
struct TileSort {
  DView<uint32_t> tileCount, tileEnd, tileTris;
  DView<uint64_t> totals;
  uint64_t tileCapacity;
  uint32_t longer;  // the lists sorted: those longer (the team form ranks the others itself)
  uint32_t stride;  // listStrideFor
  // Whether no list this frame is longer than `longer` (or the lists are
  // not read: the frame is drawn again). Every layout has found the longest
  // list before the resolve sorts (TileScan, tiles_longest or the uniform
  // blocks' classification), so a GPU's warps skip the frame's 32,400
  // blocks' counts when all of them are ranked in scratch.
  KOKKOS_INLINE_FUNCTION bool none() const {
    return totals(kBlendListed) > tileCapacity || totals(kBlendLongest) <= longer;
  }
  KOKKOS_INLINE_FUNCTION uint32_t* list(const uint32_t block, uint32_t& n) const {
    n = tileCount(block);
    if (none() || n <= longer) {  // not read, or ranked
      n = 0;
      return nullptr;
    }
    return tileTris.data() + listBegin(tileEnd, stride, block, n);
  }
  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t block) const {
    uint32_t n;
    uint32_t* v = list(block, n);
    if (n > 1) sortList(v, n);
  }
};
// A team takes every league_size-th block (a team a block cost 22 us for
// the 32,400 blocks of a 1920x1080 frame even where no list needed sorting).
struct TileSortTeam : TileSort {
  uint32_t blocks;
  KOKKOS_INLINE_FUNCTION void operator()(const TeamMember& m) const {
    uint32_t* s =
        inTeamScratch(static_cast<uint32_t*>(m.team_scratch(0).get_shmem(kBlendSortScratchEntries * sizeof(uint32_t))));
    if (none()) return;
    for (uint32_t block = uint32_t(m.league_rank()); block < blocks; block += uint32_t(m.league_size())) {
      uint32_t n;
      uint32_t* v = list(block, n);  // the same n for the whole team
      if (n < 2) continue;
      if (n > kBlendSortScratchEntries) {
        if (m.team_rank() == 0) sortList(v, n);
        continue;
      }
      for (uint32_t j = uint32_t(m.team_rank()); j < n; j += uint32_t(m.team_size())) s[j] = v[j];
      m.team_barrier();
      for (uint32_t j = uint32_t(m.team_rank()); j < n; j += uint32_t(m.team_size())) {
        uint32_t r = 0;
        for (uint32_t k = 0; k < n; ++k) r += s[k] < s[j] ? 1u : 0u;  // the entries are unique
        v[r] = s[j];
      }
      m.team_barrier();  // the scratch is the next block's
    }
  }
};

// tiles_longest (the strided layout): the longest list into
// totals(kBlendLongest), a team's maximum a chunk of blocks and one atomic
// a team (no reduction into device memory: the frame is recorded as a graph).
struct TileLongest {
  static constexpr uint32_t kChunk = 2048;
  DView<uint32_t> tileCount;
  DView<uint64_t> totals;
  uint32_t blocks;
  KOKKOS_INLINE_FUNCTION void operator()(const TeamMember& m) const {
    const uint32_t b0 = uint32_t(m.league_rank()) * kChunk, b1 = b0 + kChunk < blocks ? b0 + kChunk : blocks;
    uint32_t most = 0;
    Kokkos::parallel_reduce(
        Kokkos::TeamThreadRange(m, b0, b1), [&](const uint32_t b, uint32_t& v) { v = tileCount(b) > v ? tileCount(b) : v; },
        Kokkos::Max<uint32_t>(most));
    if (m.team_rank() == 0 && most) raiseTotal(totals(kBlendLongest), most);
  }
};
void longestList(const DView<uint32_t>& tileCount, const DView<uint64_t>& totals, const uint32_t blocks) {
  Kokkos::parallel_for("rast::blend::tiles_longest",
                       lightweight(TeamPolicy(int((blocks + TileLongest::kChunk - 1) / TileLongest::kChunk),
                                              kOnDevice ? 256 : 1)),
                       TileLongest{tileCount, totals, blocks});
}

// Whether the last frame had lists longer than the team form ranks itself.
bool sortsLongLists(const FrameBuffers& f) { return f.blend.longestList > kTeamEntriesAlways; }

// tiles_sort, launched by the resolve just before its walk (weighted):
// by then the longest list is known however the lists were laid out, and
// nothing before the walk reads their order (the uniform blocks' classifi-
// cation ranks its entries itself). The team form resolves a list that fits
// its scratch in raster-index order whatever the list's: only longer ones,
// which it walks in place, are sorted.
void sortTileLists(const FrameBuffers& f, const FragFamily fam) {
  const BlendBuffers& bb = f.blend;
  const uint32_t blocks = uint32_t(blendBlocks(f.vp.width)) * uint32_t(blendBlocks(f.vp.height));
  const uint32_t longer = fam != kFragGeneral && teamForm() ? kTeamEntriesAlways : 0;
  const TileSort sort{bb.tileCount, bb.tileEnd, bb.tileTris, bb.totals, bb.tileCapacity, longer, bb.listStride};
  if constexpr (kOnDevice) {
    // The persistent threads' warps where the last frame had lists to sort,
    // else a warp a multiprocessor: 8,448 warps that stopped at the longest
    // list's count still cost the H200's frame 7 us. Either count sorts every
    // list (a warp strides through the blocks); blendLaunchKey keys it.
    const uint32_t warps = sortsLongLists(f) ? persistentThreads() / 32 : persistentThreads() / kThreadsPerMultiprocessor;
    Kokkos::parallel_for("rast::blend::tiles_sort",
                         TeamPolicy(int(std::min<uint32_t>(blocks, std::max<uint32_t>(1, warps))), 32)
                             .set_scratch_size(0, Kokkos::PerTeam(kBlendSortScratchEntries * sizeof(uint32_t))),
                         TileSortTeam{sort, blocks});
  } else {
    Kokkos::parallel_for("rast::blend::tiles_sort", Kokkos::RangePolicy<Exec, Kokkos::IndexType<uint32_t>>(0, blocks),
                         sort);
  }
}

// peelResolve's launch of the frame's instance (withFragPath).
struct PeelLaunch {
  const FragShade& fs;
  const FrameBuffers& f;
  const Kokkos::Sum<uint64_t, Mem>& result;
  int64_t items;
  int32_t blocksX, sorted, weighted;
  const BlendPlan& plan;
  const DView<uint32_t>& packed;  // the sRGB encoder's table, where the resolve encodes (plan.encode)
  // Where set, the uniform blocks' classification alone, before shading,
  // from these keys' depth (plan.shadeComposite); else the resolve.
  DView<uint64_t> keys;
  template <unsigned kThreads, unsigned kTeams, class Team>
  static void launchTeams(const char* name, const Team& team, const bool strided) {
    using Policy = Kokkos::TeamPolicy<Exec, Kokkos::LaunchBounds<kThreads, kTeams>>;
    const int teamSize = kOnDevice ? Team::kPixels : 1;
    // Where the team walks only the listed blocks (their number known on
    // the device alone; often none), or the long lists' kernel looks for its
    // few in every block, a GPU launches the teams its multiprocessors hold
    // at once, each striding through the blocks: the persistent threads'
    // count started three waves of teams that found nothing to do.
    const int64_t most = kOnDevice && strided ? int64_t(persistentThreads() / kThreadsPerMultiprocessor) * kTeams
                                              : int64_t(persistentThreads() / teamSize);
    const int64_t teams = std::min<int64_t>(team.blocks, std::max<int64_t>(1, most));
    Kokkos::parallel_for(
        name,
        lightweight(Policy(int(teams), teamSize).set_scratch_size(0, Kokkos::PerTeam(Team::scratchFor(team.entries)))),
        team);
  }
  template <int kFam, int kFeat>
  void run() const {
    static_assert(kFam != kFragPbr || uniformBlocksFor<kFam, kFeat>(),
                  "the glTF shading's team form classifies every block, which finds the longest list (tileLists)");
    const BlendBuffers& bb = f.blend;
    Peel<kFam, kFeat> peel{fs, f.post.hdr, bb.tileCount, bb.tileEnd, bb.tileTris, bb.opaque, bb.totals,
                           bb.tileCapacity, f.vp.width, f.vp.height, blocksX, sorted,
                           fs.sh.p.mode == ShadingMode::Lambert && fs.sh.p.headlight ? 1 : 0, weighted,
                           f.color, packed, plan.encode ? 1 : 0, plan.raw ? 1 : 0, plan.straight ? 1 : 0};
    // The specialised resolves keep everything inline (nothing takes a
    // local's address) and launch lightweight, as the shade stage's lit and
    // glTF kernels; the general one calls the general fragment maths out
    // of line on a GPU and launches heavyweight (pipeline/data/device.h).
    peel.stride = bb.listStride;
    static_assert(!kOnDevice || sizeof(peel) <= 4000, "a lightweight launch carries its functor in 4 KiB of parameters");
    // (Classifying alone is asked only of the team form's glTF instances: blendShadeComposites.)
    if (keys.data() && !(uniformBlocksFor<kFam, kFeat>() && teamForm())) return;
    if constexpr (kFam == kFragGeneral) {
      if (weighted) sortTileLists(f, FragFamily(kFam));
      Kokkos::parallel_reduce("rast::blend::resolve", heavyweight(Range(0, items)), peel, result);
    } else if (teamForm()) {
      using Team = PeelTeam<kFam, kFeat>;
      const int64_t blocks = kPeelRun == 1 ? items >> (2 * kItemShift) : items;
      if constexpr (uniformBlocksFor<kFam, kFeat>()) {
        peel.blockComposite = bb.blockComposite;  // (allocated by tileLists)
        peel.blockFrags = bb.blockFrags;
        peel.walkedBlocks = bb.walkedBlocks;
        // Classified before shading, which composited their pixels
        // (plan.shadeComposite), or here, their pixels by a pass of their own.
        if (keys.data() || !plan.shadeComposite) {
          using Class = UniformBlocks<kFam, kFeat>;
          Kokkos::parallel_for("rast::blend::uniform_blocks",
                               lightweight(TeamPolicy(int((blocks + kClassBlocks - 1) / kClassBlocks),
                                                      kOnDevice ? kClassBlocks * kClassLanes : 1)
                                               .set_scratch_size(0, Kokkos::PerTeam(Class::kScratch))),
                               Class{peel, blocks, keys});
        }
        if (keys.data()) return;
        if (!plan.shadeComposite)
          Kokkos::parallel_for("rast::blend::uniform_pixels",
                               lightweight(Range(0, int64_t(f.vp.width) * f.vp.height)), UniformPixels<kFam, kFeat>{peel});
      }
      if (weighted) sortTileLists(f, FragFamily(kFam));  // after the classification, which found the longest list
      const uint32_t entries = Team::entriesFor(bb.longestList);
      // Where the last frame's longest list outgrew the larger scratch,
      // exact's lists longer than its entries are the long lists' kernel's,
      // launched after the team's (the rest of the frame's blocks). sorted's
      // and weighted's stay in the team's kernel: the long kernel would walk
      // them the same way, after the rest instead of among it (7-9% slower
      // frames on the H200 for 64 and 48 coplanar glTF-shaded layers).
      const bool defer = !sorted && !weighted && Team::defersLong(bb.longestList);
      // The family's larger scratch under launch bounds that let its teams
      // fit a multiprocessor (Kokkos refuses a scratch that does not). Host
      // backends ignore launch bounds: one instance of the team kernel.
      constexpr bool kWalked = uniformBlocksFor<kFam, kFeat>();
      const Team team{peel, blocks, entries, defer ? 1 : 0};
      if (!kOnDevice || entries <= Team::entriesIn(kBlendTeamScratchBytes))
        launchTeams<kBlendTeamLaunchBounds[0], kBlendTeamLaunchBounds[1]>("rast::blend::resolve", team, kWalked);
      else if constexpr (kOnDevice)
        launchTeams<Team::kDeepThreads, Team::kDeepTeams>("rast::blend::resolve", team, kWalked);
      if (defer)
        launchTeams<Team::kDeepThreads, Team::kDeepTeams>("rast::blend::resolve_long",
                                                          PeelTeam<kFam, kFeat, true>{peel, blocks, entries, 0}, true);
    } else {
      using Policy =
          Kokkos::RangePolicy<Exec, Kokkos::LaunchBounds<kBlendResolveLaunchBounds[0], kBlendResolveLaunchBounds[1]>>;
      // A CPU thread a few blocks: each in order where its triangles keep one
      // (peel_block.h), else its rows peeled.
      if (weighted) sortTileLists(f, FragFamily(kFam));
      if constexpr (kPeelRun > 1) {
        using Blocks = PeelBlocks<kFam, kFeat>;
        Kokkos::parallel_reduce("rast::blend::resolve", lightweight(Policy(0, Blocks::itemsFor(items))),
                                Blocks{peel, testHooks().peelRows, items}, result);
      } else {
        Kokkos::parallel_reduce("rast::blend::resolve", lightweight(Policy(0, items)), peel, result);
      }
    }
  }
};

}  // namespace

bool teamForm() { return kOnDevice || testHooks().teamResolve; }

void tileLists(FrameBuffers& f, const DView<uint64_t>& opaqueKeys, const FragFamily fam, const bool copyDepth) {
  BlendBuffers& bb = f.blend;
  const uint32_t blocksX = uint32_t(blendBlocks(f.vp.width));
  const uint32_t blocks = blocksX * uint32_t(blendBlocks(f.vp.height));
  const size_t n = size_t(f.vp.width) * size_t(f.vp.height) * size_t(f.vp.samples.count);
  ensureCapacity(bb.tileCount, "blend.tileCount", blocks);
  ensureCapacity(bb.tileEnd, "blend.tileEnd", blocks);
  ensureCapacity(bb.opaque, "blend.opaque", n);
  if (uniformBlocksOn(fam)) {  // the uniform blocks (uniform_blocks.h)
    ensureCapacity(bb.blockComposite, "blend.blockComposite", blocks);
    ensureCapacity(bb.blockFrags, "blend.blockFrags", blocks);
    ensureCapacity(bb.walkedBlocks, "blend.walkedBlocks", blocks);
  }
  if (!bb.tileTris.data()) {
    bb.tileCapacity = bb.tileCapacity ? bb.tileCapacity : blocks;  // one entry a block, then the frame's need
    bb.tileTris = allocUninit<uint32_t>("blend.tileTris", bb.tileCapacity);
  }
  Kokkos::deep_copy(Exec(), Kokkos::subview(bb.tileCount, std::make_pair(size_t(0), size_t(blocks))), 0u);
  const uint32_t threads = persistentThreads();
  bb.listStride = listStrideFor(f);
  TileItems c{f.tris, bb.blendStart, bb.totals, f.counters, bb.tileCount, bb.tileEnd, bb.tileTris, f.vp,
              f.triCapacity, threads, blocksX, blocks / blocksX, bb.tileCapacity, 0, 0};
  using Policy = Kokkos::RangePolicy<Exec, Kokkos::IndexType<uint32_t>>;
  if (bb.listStride) {
    c.fill = 1;
    c.stride = bb.listStride;
    Kokkos::parallel_for("rast::blend::tiles_fill", Policy(0, threads), c);
    // The glTF shading's team form classifies every block, reading its
    // count, and finds the longest list there (UniformBlocks; PeelLaunch
    // checks that each of its instances does).
    if (!uniformBlocksOn(fam)) longestList(bb.tileCount, bb.totals, blocks);
  } else {
    Kokkos::parallel_for("rast::blend::tiles_count", Policy(0, threads), c);
    Kokkos::parallel_scan("rast::blend::tiles_layout", Policy(0, blocks), TileScan{bb.tileCount, bb.tileEnd, bb.totals, blocks});
    c.fill = 1;
    Kokkos::parallel_for("rast::blend::tiles_fill", Policy(0, threads), c);
  }
  if (!copyDepth) return;  // the shade stage writes it (BlendPlan::shadeDepth)
  auto vis = opaqueKeys;
  auto opaque = bb.opaque;
  Kokkos::parallel_for("rast::blend::opaque_depth", Range(0, int64_t(n)),
                       KOKKOS_LAMBDA(const int64_t q) { opaque(q) = uint32_t(vis(q) >> 32); });
}

namespace {

void launchPeel(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights,
                const BlendPlan& b, const DView<uint64_t>& keys) {
  const Transparency method = b.method;
  const BlendBuffers& bb = f.blend;
  const int32_t blocksX = blendBlocks(f.vp.width);
  const int64_t blocks = int64_t(blocksX) * blendBlocks(f.vp.height);
  const int64_t items = kPeelRun == 1 ? blocks << (2 * kItemShift) : blocks;
  // The fragment count summed over threads into totals(kBlendFrags), not
  // one atomic a pixel; the depth's maximum (cleared with it by blendCollect)
  // rises a few times a frame.
  const Kokkos::Sum<uint64_t, Mem> result(Kokkos::View<uint64_t, Mem>(bb.totals.data() + kBlendFrags));
  const FragShade fs = makeFragShade(s, f, p, lights);
  withFragPath(fs, PeelLaunch{fs, f, result, items, blocksX, method == Transparency::Sorted ? 1 : 0,
                              method == Transparency::Weighted ? 1 : 0, b, s.srgbEncodePacked, keys});
}

}  // namespace

void peelResolve(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights,
                 const BlendPlan& b) {
  launchPeel(s, f, p, lights, b, DView<uint64_t>());
}

void uniformBlocksBeforeShading(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p,
                                const DView<LightGPU>& lights, const BlendPlan& b, const DView<uint64_t>& opaqueKeys) {
  launchPeel(s, f, p, lights, b, opaqueKeys);
}

}  // namespace blending

uint64_t blendLaunchKey(const FrameBuffers& f) {
  using namespace blending;
  const uint64_t l = f.blend.longestList;
  return (uint64_t(sortsLongLists(f)) << 63) ^ (uint64_t(PeelTeam<kFragLit, 0>::defersLong(l)) << 62) ^
         (uint64_t(PeelTeam<kFragPbr, 0>::defersLong(l)) << 61) ^ (uint64_t(listStrideFor(f)) << 48) ^
         (uint64_t(PeelTeam<kFragLit, 0>::entriesFor(l)) << 32 | PeelTeam<kFragPbr, 0>::entriesFor(l));
}

uint64_t stridedListRoom(const FrameBuffers& f) {
  const uint32_t stride = testHooks().listStride ? testHooks().listStride : kBlendListStride;
  if (!stride || f.blend.longestList > stride) return 0;
  constexpr int32_t kShift = blending::kItemShift;
  return uint64_t((f.vp.width + (1 << kShift) - 1) >> kShift) * uint64_t((f.vp.height + (1 << kShift) - 1) >> kShift) *
         stride;
}

uint32_t listStrideFor(const FrameBuffers& f) {
  const uint64_t room = stridedListRoom(f);
  if (!room || !f.blend.tileTris.data() || f.blend.tileCapacity < room) return 0;
  return testHooks().listStride ? testHooks().listStride : kBlendListStride;
}

}  // namespace rast
