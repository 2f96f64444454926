// The listed methods' resolve on GPUs, a team per 8x8 block
// (docs/transparency.md, "On a GPU: a team a block"); host backends run it
// under TestHooks::teamResolve. Its own file: it sets a block's list up in
// team scratch and orders it, where peel.h walks the list a pixel a thread.
#pragma once

#include "backends/team_scratch.h"
#include "pipeline/blend/peel.h"
#include "pipeline/blend/uniform_blocks.h"
#include "pipeline/data/test_hooks.h"

namespace rast {
namespace blending {

// The resolve's team form, for the specialised fragment shading on GPUs (and
// on host backends under TestHooks::teamResolve, so that tests compare it
// with the plain form): a team per 8x8 block. The block's list is copied into
// team scratch in raster-index order and each of its triangles set up there
// once for the block's 64 pixels: edges and depth terms, the shading lookups
// (AlphaTri, TriFrag, PbrTri), and the triangle's whole depth range. The
// plain resolve set a triangle up again for every fragment it shaded (one
// cached lookup a thread: a pixel's layers are different triangles).
// The triangles' order is then the same at every sample of the block when
//   sorted: always (a triangle's key is its draw's, whatever the sample);
//   exact:  the whole depth ranges do not overlap (separate layers: most
//           blocks; found once for a list and kept while the run's blocks
//           share it), else the ranges over the block do not,
// and each pixel walks the list once in that order, compositing what it
// covers as it finds it: no keys, no insertion, no second walk. Otherwise a
// pixel keeps the K nearest keys and peels as row() does, with keys that end
// in the triangle's place in the list instead of its raster index (the list
// is in raster-index order: the same order). Either way the same fragments
// are composited in the same order as by the plain form: the same bits.
// weighted needs no order: each pixel sums the entries in raster-index order,
// as the plain form sums its sorted list. A list longer than the scratch
// holds is ranked in the entries' room and walked once where its order
// holds at every sample (longOrder), else resolved the plain way.
// Where the last frame had lists longer than the larger scratch's entries,
// those lists are left to a kernel of their own (kLongLists, below), which can
// also merge overlapping ones in one walk: its code and registers stay out
// of the short lists' kernel, the 8 layers' hot path.
template <int kFam, int kFeat, bool kLongLists = false>
struct PeelTeam {
  struct Entry {
    AlphaTri a;
    TriFrag tf;
    FragPbrTri<kFam> pt;
    DepthTerms dz;   // no default: entries live in scratch, never constructed
    uint64_t order;  // its key in the block's order (sorted's key, kept; exact: the depth range's start)
    float lo, hi;    // exact: its depth range over the block
  };
  static constexpr int32_t kPixels = 1 << (2 * kItemShift);
  // Entries that fit n bytes of scratch; the scratch for n entries.
  static constexpr uint32_t entriesIn(size_t n) { return uint32_t((n - 64) / (sizeof(Entry) + 2 * sizeof(uint32_t))); }
  static constexpr size_t scratchFor(uint32_t n) { return n * (sizeof(Entry) + 2 * sizeof(uint32_t)) + 64; }
  static_assert(entriesIn(kBlendTeamScratchBytes) >= 16,
                "a block's list under 8 full-screen layers (16 triangles on its diagonal) fits");
  // The larger scratch, for frames with longer lists, and the launch bounds
  // that let its teams fit a multiprocessor: the glTF shading's entries are
  // the larger (backends/tuning.h).
  static constexpr size_t kDeepBytes = kFam == kFragPbr ? kBlendTeamScratchMaxPbrBytes : kBlendTeamScratchMaxBytes;
  static constexpr unsigned kDeepThreads =
      kFam == kFragPbr ? kBlendTeamDeepPbrLaunchBounds[0] : kBlendTeamDeepLaunchBounds[0];
  static constexpr unsigned kDeepTeams =
      kFam == kFragPbr ? kBlendTeamDeepPbrLaunchBounds[1] : kBlendTeamDeepLaunchBounds[1];
  static_assert(!kOnDevice || entriesIn(kDeepBytes) >= 64,
                "a block's list under 64 full-screen layers (off their diagonals) fits the larger scratch");
  // The larger scratch's entries (on a host backend TestHooks::teamDeepEntries
  // may lower them, so that small frames exercise the long lists' kernel).
  static uint32_t deepEntries() {
    const uint32_t hi = entriesIn(kDeepBytes), hook = testHooks().teamDeepEntries;
    return !kOnDevice && hook && hook < hi ? (hook > entriesIn(kBlendTeamScratchBytes) ? hook : hi) : hi;
  }
  // The entries of a frame whose last frame's longest list was `longest`.
  static uint32_t entriesFor(uint64_t longest) {
    const uint32_t lo = entriesIn(kBlendTeamScratchBytes), hi = deepEntries();
    return longest <= lo ? lo : (longest < hi ? uint32_t(longest) : hi);
  }
  // Whether such a frame leaves its lists longer than the entries to the
  // long lists' kernel (PeelTeam<kFam, kFeat, true>, launched after the team's).
  static bool defersLong(uint64_t longest) { return longest > deepEntries(); }

  Peel<kFam, kFeat> peel;
  int64_t blocks;
  uint32_t entries;     // entries the scratch holds (entriesFor)
  int32_t defer = 0;    // the short lists' kernel: lists longer than the entries are the long kernel's

  // The team's scratch: the entries, the raw and ordered lists, flags and
  // the team's fragment count.
  struct Scratch {
    Entry* ent;
    uint32_t *raw, *ord;
    int32_t *ordered, *same, *global, *few;
    uint64_t* frags;
  };

  // A team takes a run of neighbouring blocks (along a row: mostly the same
  // list, whose entries it then keeps), and counts its fragments into
  // totals(kBlendFrags) with one atomic (a team reduction per block cost
  // more than the resolve's own work on the H100). Where uniform blocks are
  // taken out first, the team walks only the blocks they list
  // (walkedBlocks): few, and gathered along the quads' diagonals, so a team
  // takes every league_size-th. One loop either way: a second loop calling
  // resolveBlock made the kernel's stack ten times larger on the H200.
  RAST_FLATTEN void operator()(const TeamMember& m) const {
    // inTeamScratch: read with shared loads on CUDA (backends/team_scratch.h).
    Scratch sc;
    sc.ent = inTeamScratch(static_cast<Entry*>(m.team_scratch(0).get_shmem_aligned(size_t(entries) * sizeof(Entry), 16)));
    sc.raw = inTeamScratch(static_cast<uint32_t*>(m.team_scratch(0).get_shmem(entries * sizeof(uint32_t))));
    sc.ord = inTeamScratch(static_cast<uint32_t*>(m.team_scratch(0).get_shmem(entries * sizeof(uint32_t))));
    sc.frags = inTeamScratch(static_cast<uint64_t*>(m.team_scratch(0).get_shmem_aligned(sizeof(uint64_t), 8)));
    sc.ordered = inTeamScratch(static_cast<int32_t*>(m.team_scratch(0).get_shmem(sizeof(int32_t))));
    sc.same = inTeamScratch(static_cast<int32_t*>(m.team_scratch(0).get_shmem(sizeof(int32_t))));
    sc.global = inTeamScratch(static_cast<int32_t*>(m.team_scratch(0).get_shmem(sizeof(int32_t))));
    sc.few = kLongLists ? inTeamScratch(static_cast<int32_t*>(m.team_scratch(0).get_shmem(sizeof(int32_t)))) : nullptr;
    constexpr bool kStrided = uniformBlocksFor<kFam, kFeat>();
    // The long lists' kernel strides through every block too: its lists
    // gather along the quads' diagonals, where a run of blocks would leave
    // most teams idle.
    constexpr bool kSpread = kStrided || kLongLists;
    const int64_t todo = kStrided ? int64_t(peel.totals(kBlendWalked)) : blocks;
    const int64_t per = (todo + m.league_size() - 1) / m.league_size();
    const int64_t b0 = kSpread ? m.league_rank() : per * m.league_rank();
    const int64_t b1 = kSpread ? todo : (b0 + per < todo ? b0 + per : todo);
    const int64_t step = kSpread ? m.league_size() : 1;
    uint64_t frags = 0;
    uint32_t held = ~0u;  // the length of the list whose entries the scratch holds (~0u: none)
    if (m.team_rank() == 0) *sc.frags = 0;
    m.team_barrier();  // before any thread adds to it (a run of long lists has no barrier of its own)
    for (int64_t k = b0; k < b1; k += step) resolveBlock(m, sc, kStrided ? int64_t(peel.walkedBlocks(k)) : k, held, frags);
    if (frags) Kokkos::atomic_add(sc.frags, frags);
    m.team_barrier();
    if (m.team_rank() == 0 && *sc.frags) Kokkos::atomic_add(&peel.totals(kBlendFrags), *sc.frags);
  }

  // The place of raster index i in the list in raster-index order (its
  // entries are unique).
  KOKKOS_INLINE_FUNCTION static uint32_t rankOf(const uint32_t* raw, const uint32_t n, const uint32_t i) {
    uint32_t r = 0;
    for (uint32_t k = 0; k < n; ++k) r += raw[k] < i ? 1u : 0u;
    return r;
  }

  // Ranks n keys, key(k), into ord; whether that order holds at every
  // sample: sorted's always, exact's where each range [lo(k), hi(k)] ends
  // before the next begins (NaN ranges order nothing). Every thread returns
  // the same. The entries' keys and ranges (orderEntries) or a long list's
  // (longOrder).
  template <class Key, class Lo, class Hi>
  RAST_GPU_INLINE bool rankKeys(const TeamMember& m, const Scratch& sc, const uint32_t n, uint32_t* ord, Key&& key,
                                Lo&& lo, Hi&& hi) const {
    const int nThreads = m.team_size(), me = m.team_rank();
    for (uint32_t r = uint32_t(me); r < n; r += uint32_t(nThreads)) {
      uint32_t d = 0;
      for (uint32_t k = 0; k < n; ++k) d += key(k) < key(r) ? 1u : 0u;
      ord[d] = r;
    }
    if (me == 0) *sc.ordered = 1;  // its last reader passed the barrier before this call
    m.team_barrier();
    if (!peel.sorted)
      for (uint32_t t = uint32_t(me); t + 1 < n; t += uint32_t(nThreads))
        if (!(hi(ord[t]) < lo(ord[t + 1]))) *sc.ordered = 0;  // ranges overlap (or NaN)
    m.team_barrier();
    return *sc.ordered != 0;
  }
  // The entries ranked by their keys (`order`) into sc.ord.
  RAST_GPU_INLINE bool orderEntries(const TeamMember& m, const Scratch& sc, const uint32_t n) const {
    const Entry* ent = sc.ent;
    return rankKeys(
        m, sc, n, sc.ord, [&](const uint32_t k) { return ent[k].order; }, [&](const uint32_t k) { return ent[k].lo; },
        [&](const uint32_t k) { return ent[k].hi; });
  }

  RAST_GPU_INLINE void resolveBlock(const TeamMember& m, const Scratch& sc, const int64_t block, uint32_t& held,
                                    uint64_t& frags) const {
    const Peel<kFam, kFeat>& P = peel;
    const int32_t bx = int32_t(block % P.blocksX), by = int32_t(block / P.blocksX);
    const int32_t x0 = bx << kItemShift, y0 = by << kItemShift;
    const bool listed = P.totals(kBlendListed) <= P.tileCapacity;  // else the frame is drawn again
    const uint32_t n = listed ? P.tileCount(block) : 0u, begin = listed ? P.listBegin(block, n) : 0u, end = begin + n;
    const int nThreads = m.team_size(), me = m.team_rank();
    if (n > entries) {  // longer than the scratch's entries
      if (!kLongLists && defer) return;  // the long lists' kernel's
      typename Peel<kFam, kFeat>::PeelCache cache;
      // exact and sorted rank it in the entries' room; weighted sums the
      // list as it is (raster-index order), leaving the entries alone. The
      // long lists' kernel ranks exact's by their ranges over the block
      // (tighter than the whole ones) and merges them where they overlap
      // but few at a time (fewOpen).
      const bool ranked = !P.weighted && n <= longEntries();
      if (ranked) held = ~0u;  // longOrder overwrites the entries
      const bool inOrder = ranked && longOrder<kLongLists>(m, sc, begin, n, x0, y0);
      bool merged = false;
      if constexpr (kLongLists) merged = ranked && !inOrder && fewOpen(m, sc, n);
      for (int p = me; p < kPixels; p += nThreads) {
        const int32_t X = x0 + (p & ((1 << kItemShift) - 1)), Y = y0 + (p >> kItemShift);
        if (X >= P.width || Y >= P.height) continue;
        if (inOrder)
          pixelLongInOrder(sc, n, X, Y, cache, frags);
        else if (kLongLists && merged)
          pixelLongMerged(sc, n, X, Y, cache, frags);
        else
          P.row(X, Y, 1, begin, end, cache, frags);  // the plain resolve's walk of the global list
      }
      if (kLongLists && merged && me == 0) Kokkos::atomic_add(&P.totals(kBlendMerged), uint64_t(1));
      m.team_barrier();  // the scratch is the next block's
      return;
    }
    if constexpr (kLongLists) return;  // the short lists' kernel's
    Entry* ent = sc.ent;
    uint32_t *raw = sc.raw, *ord = sc.ord;
    for (uint32_t j = uint32_t(me); j < n; j += uint32_t(nThreads)) raw[j] = P.tileTris(begin + j);
    if (me == 0) *sc.same = n == held ? 1 : 0;
    m.team_barrier();
    // Entry r of the list in raster-index order: its rank among the (unique)
    // raster indices. The last block's entries serve when they are the same.
    for (uint32_t j = uint32_t(me); j < n; j += uint32_t(nThreads))
      if (ent[rankOf(raw, n, raw[j])].a.index != raw[j]) *sc.same = 0;
    m.team_barrier();
    if (!*sc.same) {
      for (uint32_t j = uint32_t(me); j < n; j += uint32_t(nThreads)) {
        const uint32_t i = raw[j], r = rankOf(raw, n, i);
        Entry& en = ent[r];
        en.a.index = ~0u;
        P.fs.sc.prepare(i, en.a);
        en.tf.index = ~0u;
        P.fs.template use<kFam>(i, en.tf, en.pt);
        en.dz = DepthTerms(P.fs.sc.tris(i));
        // exact: the triangle's whole depth range (depthBounds: widened past
        // the depth's rounding), the list's order for every block it serves
        // when no two ranges overlap.
        if (!P.weighted) {
          const DepthBounds z = depthBounds(P.fs.sc.tris(i));
          en.lo = z.lo;
          en.hi = z.hi;
          en.order = P.sorted ? (P.sortedKeyOf(i) & ~uint64_t(0xffffffffu)) | uint64_t(0xffffffffu - r)
                              : uint64_t(orderBits(en.lo)) << 32 | r;
        }
      }
      m.team_barrier();  // an entry's range below is another thread's set-up
    }
    held = n;
    if (P.weighted) {
      for (int p = me; p < kPixels; p += nThreads) {
        const int32_t X = x0 + (p & ((1 << kItemShift) - 1)), Y = y0 + (p >> kItemShift);
        if (X < P.width && Y < P.height) pixelWeighted(ent, n, X, Y, frags);
      }
      m.team_barrier();  // the scratch is the next block's
      return;
    }
    // The list's order: sorted's keys, or exact's whole ranges where they do
    // not overlap, serve every block the list does (kept with its entries:
    // *sc.global); else each entry's depth range over this block, its key
    // the range's start, ties by raster index.
    bool inOrder = *sc.same && *sc.global;
    if (!*sc.same) {
      inOrder = orderEntries(m, sc, n);
      if (me == 0) *sc.global = inOrder ? 1 : 0;
    }
    if (!inOrder) {
      for (uint32_t r = uint32_t(me); r < n; r += uint32_t(nThreads)) {
        Entry& en = ent[r];
        blockDepthRange(en.tf.e, en.dz, x0, y0, en.lo, en.hi);
        en.order = uint64_t(orderBits(en.lo)) << 32 | r;
      }
      m.team_barrier();
      inOrder = orderEntries(m, sc, n);
    }
    for (int p = me; p < kPixels; p += nThreads) {
      const int32_t X = x0 + (p & ((1 << kItemShift) - 1)), Y = y0 + (p >> kItemShift);
      if (X < P.width && Y < P.height) {
        if (inOrder)
          pixelInOrder(ent, ord, n, X, Y, frags);
        else
          pixel(ent, n, X, Y, frags);
      }
    }
    m.team_barrier();  // the scratch is the next block's
  }

  // A list longer than the entries, in its order where that holds at every
  // sample (exact: the depth ranges do not overlap, the whole ones in the
  // team's kernel, those over the block in the long lists'; sorted: always):
  // the entries' room holds each triangle's raster index, key and range
  // (kLong bytes), and each pixel walks the list once in that order,
  // setting its triangles up from global memory as the plain walk does,
  // instead of peeling kPeelK fragments a pass over the whole list (a cost
  // that grows with the square of the depth). The same fragments in the
  // same order: the plain form's bits.
  static constexpr size_t kLong = sizeof(uint64_t) + 2 * sizeof(float) + 2 * sizeof(uint32_t);
  KOKKOS_INLINE_FUNCTION uint32_t longEntries() const { return uint32_t(size_t(entries) * sizeof(Entry) / kLong); }
  struct Long {
    uint64_t* key;
    float *lo, *hi;
    uint32_t *idx, *ord;
  };
  KOKKOS_INLINE_FUNCTION Long longOf(const Scratch& sc) const {
    const uint32_t cap = longEntries();
    char* base = reinterpret_cast<char*>(sc.ent);  // 16-byte aligned; the arrays in falling alignment
    Long l;
    l.key = reinterpret_cast<uint64_t*>(base);
    l.lo = reinterpret_cast<float*>(l.key + cap);
    l.hi = l.lo + cap;
    l.idx = reinterpret_cast<uint32_t*>(l.hi + cap);
    l.ord = l.idx + cap;
    return l;
  }
  // kOverBlock: exact's ranges over the block at (x0, y0) (blockDepthRange),
  // else the triangles' whole ranges.
  template <bool kOverBlock>
  RAST_GPU_INLINE bool longOrder(const TeamMember& m, const Scratch& sc, const uint32_t begin, const uint32_t n,
                                 const int32_t x0, const int32_t y0) const {
    const Peel<kFam, kFeat>& P = peel;
    const Long l = longOf(sc);
    const int nThreads = m.team_size(), me = m.team_rank();
    if (kLongLists && me == 0) *sc.few = 1;  // (fewOpen's; its last reader passed the last block's barrier)
    for (uint32_t j = uint32_t(me); j < n; j += uint32_t(nThreads)) {
      const uint32_t i = P.tileTris(begin + j);
      const RasterTri& t = P.fs.sc.tris(i);
      float lo, hi;
      if (kOverBlock && !P.sorted) {
        blockDepthRange(Edges(t), DepthTerms(t), x0, y0, lo, hi);
      } else {
        const DepthBounds z = depthBounds(t);
        lo = z.lo;
        hi = z.hi;
      }
      l.idx[j] = i;
      l.lo[j] = lo;
      l.hi[j] = hi;
      l.key[j] = P.sorted ? P.sortedKeyOf(i) : uint64_t(orderBits(lo)) << 32 | j;  // unique either way
    }
    m.team_barrier();
    return rankKeys(
        m, sc, n, l.ord, [&](const uint32_t k) { return l.key[k]; }, [&](const uint32_t k) { return l.lo[k]; },
        [&](const uint32_t k) { return l.hi[k]; });
  }
  RAST_GPU_INLINE void pixelLongInOrder(const Scratch& sc, const uint32_t n, const int32_t X, const int32_t Y,
                                        typename Peel<kFam, kFeat>::PeelCache& cache, uint64_t& frags) const {
    const Peel<kFam, kFeat>& P = peel;
    const Long l = longOf(sc);
    eachSample(X, Y, [&](const int s, const uint32_t opq, float3& acc, float& T) {
      const int32_t ox = P.fs.sp.ox[s], oy = P.fs.sp.oy[s];
      uint32_t cnt = 0;
      for (uint32_t t = 0; t < n; ++t) {
        const uint32_t i = l.idx[l.ord[t]];
        const RasterTri& tri = P.fs.sc.tris(i);
        const Edges e(tri);
        const int64_t s0 = e.sample(0, X, Y, ox, oy), s1 = e.sample(1, X, Y, ox, oy), s2 = e.sample(2, X, Y, ox, oy);
        if (!e.inside(s0, s1, s2)) continue;
        if (!(floatBits(DepthTerms(tri).at(s0, s2)) < opq)) continue;  // LESS against the opaque depth
        ++cnt;
        if (!(T > 0.0f)) continue;  // opaque already: counted, not shaded
        const float4 c = cache.template at<kFeat>(P.fs, i, X, Y, s);
        if (c.w > 0.0f) over(acc, T, c);  // alpha 0 (or NaN): no fragment
      }
      count(cnt, frags);
    });
  }

  // exact, a long list ranked by its ranges' starts (longOrder) that overlap:
  // whether at each range's start at most kPeelK - 1 earlier ranges are still
  // open (end at or past it), none of them NaN. Then a sample's merged walk
  // (pixelLongMerged) never holds more than kPeelK keys.
  RAST_GPU_INLINE bool fewOpen(const TeamMember& m, const Scratch& sc, const uint32_t n) const {
    const Long l = longOf(sc);
    const int nThreads = m.team_size(), me = m.team_rank();
    for (uint32_t t = uint32_t(me); t < n; t += uint32_t(nThreads)) {
      const float lo = l.lo[l.ord[t]], hi = l.hi[l.ord[t]];
      uint32_t open = lo == lo && hi == hi ? 1u : uint32_t(kPeelK) + 1u;
      for (uint32_t u = 0; u < t && open <= uint32_t(kPeelK); ++u) open += l.hi[l.ord[u]] < lo ? 0u : 1u;
      if (open > uint32_t(kPeelK)) *sc.few = 0;
    }
    m.team_barrier();
    return *sc.few != 0;
  }
  // Pixel (X, Y) of such a list: one walk in the ranges' order, each
  // fragment in front of the opaque depth held (its key, in order, as
  // Peel::insert keeps them) until the next range starts past its depth;
  // no later fragment can then come before it, so it is composited. The
  // keys leave in row()'s order: the same fragments in the same order, the
  // plain form's bits, for one walk instead of a pass per kPeelK fragments.
  RAST_GPU_INLINE void pixelLongMerged(const Scratch& sc, const uint32_t n, const int32_t X, const int32_t Y,
                                       typename Peel<kFam, kFeat>::PeelCache& cache, uint64_t& frags) const {
    const Peel<kFam, kFeat>& P = peel;
    const Long l = longOf(sc);
    eachSample(X, Y, [&](const int s, const uint32_t opq, float3& acc, float& T) {
      const int32_t ox = P.fs.sp.ox[s], oy = P.fs.sp.oy[s];
      uint64_t best[kPeelK];
      for (int k = 0; k < kPeelK; ++k) best[k] = kNoKey;
      uint32_t cnt = 0, held = 0;
      // t == n: past the last range, every key left held leaves.
      for (uint32_t t = 0; t <= n; ++t) {
        const uint32_t j = t < n ? l.ord[t] : 0u;
        const uint32_t start = t < n ? floatBits(l.lo[j]) : ~0u;  // lo in [0, 1]: ordered as its bits
        // The nearest key held leaves: composited while light passes (row()
        // stops there too), the rest shifted down (compile-time indices).
        while (held > 0 && uint32_t(best[0] >> 32) < start) {
          if (T > 0.0f) {
            const float4 c = cache.template at<kFeat>(P.fs, keyIndex(best[0], false), X, Y, s);
            if (c.w > 0.0f) over(acc, T, c);  // alpha 0 (or NaN): no fragment
          }
          for (int q = 0; q + 1 < kPeelK; ++q) best[q] = best[q + 1];
          best[kPeelK - 1] = kNoKey;
          --held;
        }
        if (t == n) break;
        const uint32_t i = l.idx[j];
        const RasterTri& tri = P.fs.sc.tris(i);
        const Edges e(tri);
        const int64_t s0 = e.sample(0, X, Y, ox, oy), s1 = e.sample(1, X, Y, ox, oy), s2 = e.sample(2, X, Y, ox, oy);
        if (!e.inside(s0, s1, s2)) continue;
        const float z = DepthTerms(tri).at(s0, s2);
        if (!(floatBits(z) < opq)) continue;  // LESS against the opaque depth
        ++cnt;
        if (!(T > 0.0f)) continue;  // opaque already: counted, not shaded
        Peel<kFam, kFeat>::insert(best, visKey(z, i), held);  // held < kPeelK (fewOpen)
        ++held;
      }
      count(cnt, frags);
    });
  }

  // Each sample of pixel (X, Y): op(s, sample's opaque depth bits, acc, T)
  // composites the fragments in front of it from acc = 0, T = 1; the result
  // over the opaque colour into the film, the samples averaged (Peel::filmSample).
  template <class Op>
  RAST_GPU_INLINE void eachSample(const int32_t X, const int32_t Y, Op&& op) const {
    const Peel<kFam, kFeat>& P = peel;
    const int S = P.fs.sp.count;
    const int64_t px = int64_t(Y) * P.width + X;
    float4 sum{0.0f, 0.0f, 0.0f, 0.0f};
    for (int s = 0; s < S; ++s) {
      float3 acc{0.0f, 0.0f, 0.0f};
      float T = 1.0f;
      op(s, P.opaque(px * S + s), acc, T);
      P.filmSample(px, s, S, acc, T, sum);
    }
  }
  // The statistics: every fragment in front of the opaque depth.
  RAST_GPU_INLINE void count(const uint32_t cnt, uint64_t& frags) const { peel.count(cnt, frags); }
  // An entry's edge values at sample s of pixel (X, Y) (exact integers; on
  // a GPU from the 32-bit factors, Edges::sample).
  RAST_GPU_INLINE void edgesAt(const Entry& en, const int32_t X, const int32_t Y, const int s, int64_t (&v)[3]) const {
    const Edges& e = en.tf.e;
    const int32_t ox = peel.fs.sp.ox[s], oy = peel.fs.sp.oy[s];
    for (int k = 0; k < 3; ++k) v[k] = e.sample(k, X, Y, ox, oy);
  }

  // Pixel (X, Y) of a block whose triangles keep one order at all its
  // samples: one walk in that order, each fragment composited as found.
  RAST_GPU_INLINE void pixelInOrder(const Entry* ent, const uint32_t* ord, const uint32_t n, const int32_t X,
                                    const int32_t Y, uint64_t& frags) const {
    eachSample(X, Y, [&](const int s, const uint32_t opq, float3& acc, float& T) {
      uint32_t cnt = 0;
      for (uint32_t t = 0; t < n; ++t) {
        const Entry& en = ent[ord[t]];
        int64_t v[3];
        edgesAt(en, X, Y, s, v);
        if (!en.tf.e.inside(v[0], v[1], v[2])) continue;
        if (!(floatBits(en.dz.at(v[0], v[2])) < opq)) continue;  // LESS against the opaque depth
        ++cnt;
        if (!(T > 0.0f)) continue;  // opaque already: counted, not shaded
        const float4 c = peel.fs.template shadeAt<kFam, kFeat>(X, Y, s, v[0], v[1], v[2], en.a, en.tf, en.pt);
        if (c.w > 0.0f) over(acc, T, c);  // alpha 0 (or NaN): no fragment
      }
      count(cnt, frags);
    });
  }

  // weighted, pixel (X, Y): rowWeighted's sums over the entries, in
  // raster-index order. The walk's first lines are pixel()'s and
  // pixelInOrder()'s, written out: one helper for the three measured 2 to 4%
  // slower on the H100 (docs/journal/transparency-2026-11.md).
  RAST_GPU_INLINE void pixelWeighted(const Entry* ent, const uint32_t n, const int32_t X, const int32_t Y,
                                     uint64_t& frags) const {
    eachSample(X, Y, [&](const int s, const uint32_t opq, float3& acc, float& T) {
      float4 w{0.0f, 0.0f, 0.0f, 0.0f};
      float reveal = 1.0f;
      uint32_t cnt = 0;
      for (uint32_t r = 0; r < n; ++r) {
        const Entry& en = ent[r];
        int64_t v[3];
        edgesAt(en, X, Y, s, v);
        if (!en.tf.e.inside(v[0], v[1], v[2])) continue;
        const float z = en.dz.at(v[0], v[2]);
        if (!(floatBits(z) < opq)) continue;  // LESS against the opaque depth
        ++cnt;
        const float4 c = peel.fs.template shadeAt<kFam, kFeat>(X, Y, s, v[0], v[1], v[2], en.a, en.tf, en.pt);
        if (c.w > 0.0f) weightedTerms(w, reveal, c, peel.fs.weight(z));  // alpha 0 (or NaN): no fragment
      }
      count(cnt, frags);
      weightedFront(w, reveal, acc, T);
    });
  }

  // Pixel (X, Y): row()'s passes over the scratch entries, key for key.
  RAST_GPU_INLINE void pixel(const Entry* ent, const uint32_t n, const int32_t X, const int32_t Y,
                             uint64_t& frags) const {
    const bool sorted = peel.sorted != 0;
    eachSample(X, Y, [&](const int s, const uint32_t opq, float3& acc, float& T) {
      uint64_t after = 0;  // every key is above 0
      for (bool more = n > 0, first = true; more; first = false) {
        uint64_t best[kPeelK];
        for (int k = 0; k < kPeelK; ++k) best[k] = kNoKey;
        uint32_t cnt = 0;
        for (uint32_t j = n; j-- > 0;) {  // last entry first, as row()
          const Entry& en = ent[j];
          int64_t v[3];
          edgesAt(en, X, Y, s, v);
          if (!en.tf.e.inside(v[0], v[1], v[2])) continue;
          const float z = en.dz.at(v[0], v[2]);
          if (!(floatBits(z) < opq)) continue;  // LESS against the opaque depth
          const uint64_t key = sorted ? en.order : visKey(z, j);  // sorted's: its draw's, then its place j
          if (key <= after) continue;  // composited by an earlier pass
          if (key < best[kPeelK - 1]) Peel<kFam, kFeat>::insert(best, key, cnt);
          ++cnt;
        }
        if (first) count(cnt, frags);
        const uint64_t lastKey = best[kPeelK - 1];
        const int kept = cnt < uint32_t(kPeelK) ? int(cnt) : kPeelK;
        for (int k = 0; k < kept && T > 0.0f; ++k) {
          const uint64_t key = best[kOnDevice ? 0 : k];
          if (kOnDevice)
            for (int q = 0; q + 1 < kPeelK; ++q) best[q] = best[q + 1];
          const Entry& en = ent[keyIndex(key, sorted)];
          int64_t v[3];
          edgesAt(en, X, Y, s, v);
          const float4 c = peel.fs.template shadeAt<kFam, kFeat>(X, Y, s, v[0], v[1], v[2], en.a, en.tf, en.pt);
          if (c.w > 0.0f) over(acc, T, c);  // alpha 0 (or NaN): no fragment
        }
        more = cnt > uint32_t(kPeelK) && T > 0.0f;
        after = lastKey;
      }
    });
  }
};

// The entries that every team's scratch holds, whatever the fragment family
// (the smaller scratch, the larger entries): a list no longer is always
// resolved from scratch, whose entries are in raster-index order.
constexpr uint32_t kTeamEntriesAlways =
    PeelTeam<kFragLit, 0>::entriesIn(kBlendTeamScratchBytes) < PeelTeam<kFragPbr, 0>::entriesIn(kBlendTeamScratchBytes)
        ? PeelTeam<kFragLit, 0>::entriesIn(kBlendTeamScratchBytes)
        : PeelTeam<kFragPbr, 0>::entriesIn(kBlendTeamScratchBytes);

}  // namespace blending
}  // namespace rast
