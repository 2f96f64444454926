// The listed methods' uniform blocks on GPUs (docs/transparency.md, "On a
// GPU: a team a block"). Under the glTF shading a block whose every listed
// triangle covers all its samples (or, with the other half of its quad, all
// but those across their shared edge), in front of its nearest opaque depth,
// with one colour (unlit, untextured layers: FragShade::constantColourOf)
// composites the same fragments in the same order at every sample: the
// team form's walk would repeat one "over" 64 times a sample. A few threads
// a block (one a list entry) decide that and compute the composite once,
// counting its fragments, and list the other blocks
// (rast::blend::uniform_blocks); the team then walks only the listed blocks
// (PeelTeam). At one sample this runs before shading, from the opaque keys,
// and the shade stage writes each uniform pixel's composite over the colour
// it shades (BlendPlan::shadeComposite, Shade::blendFilm: the film read and
// written once less); else, after shading, a thread a pixel writes it over
// the film's opaque colour (rast::blend::uniform_pixels). Kernels of their
// own and not steps of the team: classifying inside the team (a team
// reduction of the opaque depth and a barrier a block) made the H200's
// resolve slower, and the team kernel's occupancy (its scratch) is too low
// for a pass that only streams the film
// (docs/journal/transparency-2026-11.md). The CPU's block walk
// decides the same a sample at a time (peel_block.h, PeelBlocks::uniform).
#pragma once

#include "backends/team_scratch.h"
#include "pipeline/blend/peel.h"

namespace rast {
namespace blending {

// Longest list composited once (its keys and colours on the thread's stack).
constexpr uint32_t kUniformMax = 16;

// The resolves that read the uniform blocks: the glTF shading's instances
// that can have a constant colour.
template <int kFam, int kFeat>
constexpr bool uniformBlocksFor() {
  return kFam == kFragPbr && kFeat != shading::kPbrAny;
}

// A classifying team takes kClassBlocks neighbouring blocks, kClassLanes
// threads a block. The block's list entries (each a chain of dependent
// loads: the list, the triangle, its draw and material) and its opaque
// depths are shared out among its threads, which then rank the entries and
// test the quads' halves in parallel; one thread composites. A thread a
// block waited on those chains one entry after another (the blocks on the
// quads' diagonals, 16 triangles, the longest); more threads a block than
// four leave a multiprocessor (at this kernel's registers) too few blocks
// at once for the frame's 32,400.
constexpr int kClassLanes = 4;
constexpr int kClassBlocks = 16;

template <int kFam, int kFeat>
struct UniformBlocks {
  using P = Peel<kFam, kFeat>;
  P peel;  // writes its blockComposite (acc, T: weighted's after weightedFront),
           // blockFrags (the fragments a sample; kUniformWalk where the team walks
           // the list) and walkedBlocks (those, totals(kBlendWalked) of them)
  int64_t blocks;
  // Where set, each sample's opaque key, whose depth the classification
  // reads before shading (BlendPlan::shadeComposite); else the opaque depth
  // the shading wrote (peel.opaque).
  DView<uint64_t> keys;

  // An entry of a block's list, as its thread finds it.
  struct Entry {
    uint64_t key;    // its place in the walk's order
    float col[4];    // its one colour
    float lo, hi;    // exact and sorted: its depth range; weighted: its one depth (lo)
    uint32_t tri;    // its raster index
    uint32_t meta;   // kOpen: the one edge that leaves out some sample, + 1 (else 0); kOk; kPaired
  };
  static constexpr uint32_t kOpen = 3u, kOk = 4u, kPaired = 8u;
  static_assert(kUniformMax % kClassLanes == 0, "a block's threads take its entries in turn");  // kPaired: a quad's half with the next in the order
  // A team's scratch: per block its entries, its order, its threads' nearest
  // opaque depths, whether it is walked, its list's length, its fragments.
  struct Scratch {
    Entry* ent;
    uint8_t* ord;
    uint32_t *nearest, *count;
    int32_t* walk;
    uint64_t* frags;
  };
  static constexpr size_t kScratch =
      kClassBlocks * (kUniformMax * (sizeof(Entry) + 1) + kClassLanes * sizeof(uint32_t) + sizeof(uint32_t) +
                      sizeof(int32_t) + sizeof(uint64_t)) +
      64;

  // The block's pixels within the frame: [x0, x1] x [y0, y1].
  KOKKOS_INLINE_FUNCTION void extent(const int64_t block, int32_t& x0, int32_t& y0, int32_t& x1, int32_t& y1) const {
    const P& p = peel;
    x0 = int32_t(block % p.blocksX) << kItemShift;
    y0 = int32_t(block / p.blocksX) << kItemShift;
    x1 = x0 + (1 << kItemShift) <= p.width ? x0 + (1 << kItemShift) - 1 : p.width - 1;
    y1 = y0 + (1 << kItemShift) <= p.height ? y0 + (1 << kItemShift) - 1 : p.height - 1;
  }

  // The edges of e that leave out some sample of the pixels [x0, x1] x
  // [y0, y1], bit k for edge k (exact integers, Edges::inside's test): an
  // edge function is linear, so its least value over them is at the corner
  // its signs point away from (a sample adds the same offset at every pixel):
  // one corner an edge, not four (the classification's most instructions).
  KOKKOS_INLINE_FUNCTION static uint32_t openEdges(const Edges& e, const int32_t x0, const int32_t y0,
                                                   const int32_t x1, const int32_t y1, const SamplePattern& sp) {
    uint32_t open = 0;
    for (int k = 0; k < 3; ++k) {
      const int32_t X = e.A[k] > 0 ? x0 : x1, Y = e.B[k] > 0 ? y0 : y1;
      for (int s = 0; s < sp.count; ++s)
        if (!(e.sample(k, X, Y, sp.ox[s], sp.oy[s]) + e.bias[k] > 0)) open |= 1u << k;
    }
    return open;
  }

  // The length n of `block`'s list (0 past the frame), and where the block
  // may be uniform its begin (n at most kUniformMax); false where the team
  // walks it.
  KOKKOS_INLINE_FUNCTION bool listOf(const int64_t block, uint32_t& begin, uint32_t& n) const {
    const P& p = peel;
    n = 0;
    if (block >= blocks) return false;
    n = p.tileCount(block);  // (on overflow too: the longest list sizes the frame drawn again)
    if (p.totals(kBlendListed) > p.tileCapacity) return false;  // the frame is drawn again
    begin = p.listBegin(block, n);
    return n <= kUniformMax;
  }

  // Thread j of block b: entries j, j + kClassLanes, ... of its list (each
  // triangle: one colour; every sample taken in but across at most one
  // edge; exact and sorted its whole depth range, depthBounds; weighted
  // parallel to the image, one depth and so one weight; its key in the
  // walk's order), and the nearest opaque depth of rows j, j + kClassLanes,
  // ... of the block.
  KOKKOS_INLINE_FUNCTION void entries(const Scratch& sc, const int b, const int64_t block, const int j) const {
    uint32_t begin, n;
    const bool may = listOf(block, begin, n);
    if (j == 0) {
      sc.walk[b] = may ? 0 : 1;
      sc.count[b] = n;
    }
    if (!may) return;
    const P& p = peel;
    const FragShade& fs = p.fs;
    int32_t x0, y0, x1, y1;
    extent(block, x0, y0, x1, y1);
    const int S = fs.sp.count;
    uint32_t nearest = ~0u;
    for (int32_t Y = y0 + j; Y <= y1; Y += kClassLanes)
      for (int s = 0; s < S; ++s) {
        const int64_t row = (int64_t(Y) * p.width + x0) * S + s;
#if defined(__CUDA_ARCH__) || defined(__HIP_DEVICE_COMPILE__)
#pragma unroll
#endif
        for (int32_t dx = 0; dx < (1 << kItemShift); ++dx) {
          const int64_t q = row + int64_t(dx) * S;
          const uint32_t o = x0 + dx > x1 ? ~0u : keys.data() ? uint32_t(keys(q) >> 32) : p.opaque(q);
          nearest = o < nearest ? o : nearest;
        }
      }
    sc.nearest[b * kClassLanes + j] = nearest;
    if (n == 0) return;
    Entry* ent = sc.ent + b * kUniformMax;
    // Every thread takes kUniformMax / kClassLanes entries, those past the
    // list the last one again (not written), so that the code has no branch
    // and the compiler overlaps their loads (latency, not arithmetic, is
    // this kernel's cost).
#if defined(__CUDA_ARCH__) || defined(__HIP_DEVICE_COMPILE__)
#pragma unroll
#endif
    for (uint32_t k = 0; k < kUniformMax / kClassLanes; ++k) {
      const uint32_t e = uint32_t(j) + k * kClassLanes, at = e < n ? e : n - 1;
      const uint32_t i = p.tileTris(begin + at);
      float4 c{0.0f, 0.0f, 0.0f, 0.0f};
      const bool one = fs.template constantColourOf<kFam, kFeat>(i, c);
      const RasterTri& t = fs.sc.tris(i);
      const uint32_t o = openEdges(Edges(t), x0, y0, x1, y1, fs.sp);
      bool ok = one && !(o & (o - 1));  // two edges or three open: a corner of it in the block
      Entry en;
      en.col[0] = c.x;
      en.col[1] = c.y;
      en.col[2] = c.z;
      en.col[3] = c.w;
      en.tri = i;
      if (p.weighted) {
        const DepthTerms dz(t);
        // DepthTerms::at with d1 = d2 = 0 is z0 + (+-0): z0 itself where z0 > 0.
        en.lo = clamp01(dz.z0);
        en.hi = 0.0f;
        ok = ok && dz.d1 == 0.0f && dz.d2 == 0.0f && dz.z0 > 0.0f;
        en.key = i;  // raster-index order, in which the sums add
      } else {
        const DepthBounds z = depthBounds(t);
        en.lo = z.lo;
        en.hi = z.hi;
        // The team's keys (PeelTeam::resolveBlock), the list's place r in
        // raster-index order replaced by the raster index: the same order.
        en.key = p.sorted ? (p.sortedKeyOf(i) & ~uint64_t(0xffffffffu)) | uint64_t(0xffffffffu - i)
                          : uint64_t(orderBits(z.lo)) << 32 | i;
      }
      en.meta = (o ? (o == 1u ? 1u : o == 2u ? 2u : 3u) : 0u) | (ok ? kOk : 0u);
      if (e < n) ent[e] = en;
    }
  }

  // Thread j of block b: its entries in front of the block's nearest opaque
  // depth (else the block is walked), and their places in the order.
  KOKKOS_INLINE_FUNCTION void rank(const Scratch& sc, const int b, const int j) const {
    if (sc.walk[b]) return;
    const P& p = peel;
    const uint32_t n = sc.count[b];
    const Entry* ent = sc.ent + b * kUniformMax;
    uint32_t nearest = ~0u;
    for (int k = 0; k < kClassLanes; ++k) {
      const uint32_t o = sc.nearest[b * kClassLanes + k];
      nearest = o < nearest ? o : nearest;
    }
    for (uint32_t e = uint32_t(j); e < n; e += kClassLanes) {
      const Entry& en = ent[e];
      if (!(en.meta & kOk) || !(p.weighted ? floatBits(en.lo) < nearest : blockInFront(en.lo, en.hi, nearest)))
        sc.walk[b] = 1;
      uint32_t r = 0;  // the keys are unique (they end in the raster index)
      for (uint32_t k = 0; k < n; ++k) r += ent[k].key < en.key ? 1u : 0u;
      sc.ord[b * kUniformMax + r] = uint8_t(e);
    }
  }

  // Thread j of block b: whether the entries at places j, j + kClassLanes,
  // ... open across one edge are a quad's half with the next in the order:
  // open across the same edge reversed (sharedEdge), of the same colour
  // (weighted: depth). Each sample then lies inside the pair's four outer
  // edges and the shared one gives it to exactly one half: one fragment of
  // the pair's colour at every sample, in the pair's place. (Halves apart
  // in the order: another triangle's fragment would fall between them at
  // some samples.)
  KOKKOS_INLINE_FUNCTION void pair(const Scratch& sc, const int b, const int j) const {
    if (sc.walk[b]) return;
    const P& p = peel;
    const uint32_t n = sc.count[b];
    Entry* ent = sc.ent + b * kUniformMax;
    const uint8_t* ord = sc.ord + b * kUniformMax;
    for (uint32_t r = uint32_t(j); r + 1 < n; r += kClassLanes) {
      Entry& a = ent[ord[r]];
      const Entry& c = ent[ord[r + 1]];
      const uint32_t oa = a.meta & kOpen, oc = c.meta & kOpen;
      if (!oa || !oc) continue;
      const int32_t e = sharedEdge(p.fs.sc.tris(a.tri), p.fs.sc.tris(c.tri));
      if (e < 0 || uint32_t(e / 3) + 1 != oa || uint32_t(e % 3) + 1 != oc) continue;
      bool same = true;
      for (int k = 0; k < 4; ++k) same = same && floatBits(a.col[k]) == floatBits(c.col[k]);
      if (same && (!p.weighted || floatBits(a.lo) == floatBits(c.lo))) a.meta |= kPaired;
    }
  }

  // The composite of block b in `out` (the team's pixelInOrder and
  // pixelWeighted at one sample, once), a unit at a time: a triangle, or a
  // quad's two halves; and its fragments a sample (kUniformWalk: walked).
  // exact: one order at every sample only where each unit's range (a
  // pair's: their union) ends before the next begins (the team's orderEntries).
  KOKKOS_INLINE_FUNCTION uint32_t composite(const Scratch& sc, const int b, float4& out) const {
    if (sc.walk[b]) return kUniformWalk;
    const P& p = peel;
    const uint32_t n = sc.count[b];
    const Entry* ent = sc.ent + b * kUniformMax;
    const uint8_t* ord = sc.ord + b * kUniformMax;
    float3 acc{0.0f, 0.0f, 0.0f};
    float T = 1.0f;
    float4 w{0.0f, 0.0f, 0.0f, 0.0f};
    float reveal = 1.0f, before = 0.0f;
    uint32_t units = 0;
    for (uint32_t t = 0; t < n; ++units) {
      const Entry& a = ent[ord[t]];
      float l = a.lo, h = a.hi;
      if (a.meta & kOpen) {
        if (!(a.meta & kPaired)) return kUniformWalk;
        const Entry& c = ent[ord[t + 1]];  // (no NaN: blockInFront)
        l = c.lo < l ? c.lo : l;
        h = c.hi > h ? c.hi : h;
        t += 2;
      } else {
        t += 1;
      }
      const float4 col{a.col[0], a.col[1], a.col[2], a.col[3]};
      if (p.weighted) {
        if (col.w > 0.0f) weightedTerms(w, reveal, col, p.fs.weight(l));
        continue;
      }
      if (!p.sorted && units > 0 && !(before < l)) return kUniformWalk;  // ranges overlap (or NaN)
      before = h;
      if (T > 0.0f && col.w > 0.0f) over(acc, T, col);
    }
    if (p.weighted) weightedFront(w, reveal, acc, T);
    out = float4{acc.x, acc.y, acc.z, T};
    return units;
  }

  // Block b's result: its composite and count, or its place among the
  // walked blocks (their order depends on the thread schedule; each is
  // resolved alone, so the film does not). Its fragments: the statistics.
  KOKKOS_INLINE_FUNCTION uint64_t finish(const Scratch& sc, const int b, const int64_t block) const {
    if (block >= blocks) return 0;
    const P& p = peel;
    float4 out;
    const uint32_t units = composite(sc, b, out);
    p.blockFrags(block) = units;
    if (units == kUniformWalk) {
      p.walkedBlocks(Kokkos::atomic_fetch_add(&p.totals(kBlendWalked), uint64_t(1))) = uint32_t(block);
      return 0;
    }
    p.blockComposite(block) = out;
    int32_t x0, y0, x1, y1;
    extent(block, x0, y0, x1, y1);
    uint64_t frags = 0;
    p.count(uint64_t(x1 - x0 + 1) * uint64_t(y1 - y0 + 1) * uint64_t(p.fs.sp.count) * units, units, frags);
    return frags;
  }

  // The team's steps, a barrier apart; its blocks' fragments added to
  // totals(kBlendFrags) with one atomic, and their longest list raised into
  // totals(kBlendLongest): the classification reads every block's count, so
  // the strided layout's frames need no pass of their own for it
  // (tileLists: tiles_longest).
  KOKKOS_INLINE_FUNCTION void operator()(const TeamMember& m) const {
    Scratch sc;
    sc.ent = inTeamScratch(static_cast<Entry*>(
        m.team_scratch(0).get_shmem_aligned(kClassBlocks * kUniformMax * sizeof(Entry), alignof(Entry))));
    sc.frags = inTeamScratch(static_cast<uint64_t*>(m.team_scratch(0).get_shmem_aligned(kClassBlocks * sizeof(uint64_t), 8)));
    sc.nearest = inTeamScratch(static_cast<uint32_t*>(m.team_scratch(0).get_shmem(kClassBlocks * kClassLanes * sizeof(uint32_t))));
    sc.count = inTeamScratch(static_cast<uint32_t*>(m.team_scratch(0).get_shmem(kClassBlocks * sizeof(uint32_t))));
    sc.walk = inTeamScratch(static_cast<int32_t*>(m.team_scratch(0).get_shmem(kClassBlocks * sizeof(int32_t))));
    sc.ord = inTeamScratch(static_cast<uint8_t*>(m.team_scratch(0).get_shmem(kClassBlocks * kUniformMax)));
    const int64_t first = int64_t(m.league_rank()) * kClassBlocks;
    const auto each = [&](auto&& step) {  // every (block, thread) of the team
      for (int t = m.team_rank(); t < kClassBlocks * kClassLanes; t += m.team_size())
        step(t / kClassLanes, first + t / kClassLanes, t % kClassLanes);
    };
    each([&](const int b, const int64_t block, const int j) { entries(sc, b, block, j); });
    m.team_barrier();
    each([&](const int b, const int64_t, const int j) { rank(sc, b, j); });
    m.team_barrier();
    each([&](const int b, const int64_t, const int j) { pair(sc, b, j); });
    m.team_barrier();
    each([&](const int b, const int64_t block, const int j) {
      if (j == 0) sc.frags[b] = finish(sc, b, block);
    });
    m.team_barrier();
    if (m.team_rank() == 0) {
      uint64_t sum = 0;
      uint32_t longest = 0;
      for (int b = 0; b < kClassBlocks; ++b) {
        sum += sc.frags[b];
        longest = sc.count[b] > longest ? sc.count[b] : longest;
      }
      if (sum) Kokkos::atomic_add(&peel.totals(kBlendFrags), sum);
      raiseTotal(peel.totals(kBlendLongest), longest);
    }
  }
};

// A uniform block's pixel: the block's composite over the opaque colour at
// every sample (the team's arithmetic: Peel::filmSample).
template <int kFam, int kFeat>
struct UniformPixels {
  Peel<kFam, kFeat> peel;
  KOKKOS_INLINE_FUNCTION void operator()(const int64_t px) const {
    const Peel<kFam, kFeat>& p = peel;
    const int32_t X = int32_t(px % p.width), Y = int32_t(px / p.width);
    const int64_t block = blendBlockOf(X, Y, p.blocksX);
    if (p.blockFrags(block) == kUniformWalk) return;
    const float4 o = p.blockComposite(block);
    const int S = p.fs.sp.count;
    float4 sum{0.0f, 0.0f, 0.0f, 0.0f};
    for (int s = 0; s < S; ++s) p.filmSample(px, s, S, float3{o.x, o.y, o.z}, o.w, sum);
  }
};

}  // namespace blending
}  // namespace rast
