// The tile lists of the listed BLEND methods (docs/transparency.md, "exact and
// sorted: tile lists, peeled in registers"): the strided layout that a GPU
// takes where the last frame's lists were short gives the counted layout's
// bits, and weighted's lists that the team form walks in place are in
// raster-index order when it walks them.
#include <catch2/catch.hpp>

#include "pipeline/blend/peel_team.h"
#include "pipeline/data/test_hooks.h"
#include "pipeline/frame/renderer.h"
#include "scenes/procedural.h"
#include "tests/support/blend_support.h"
#include "tests/support/test_support.h"

using namespace rast;
using namespace rast::test;

namespace {

// The strided layout's room (TestHooks::listStride) for a scope.
struct Stride {
  explicit Stride(uint32_t s) { testHooks().listStride = s; }
  ~Stride() { testHooks().listStride = 0; }
};

// Whether every tile list of the last frame longer than `longer` entries is in
// raster-index order (ascending: the entries are unique).
bool longListsInOrder(const Renderer& r, const uint32_t longer) {
  const BlendBuffers& bb = r.frameBuffers().blend;
  const auto count = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), bb.tileCount);
  const auto end = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), bb.tileEnd);
  const auto tris = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), bb.tileTris);
  const FrameBuffers& f = r.frameBuffers();
  const int64_t blocks = int64_t(blendBlocks(f.vp.width)) * blendBlocks(f.vp.height);
  for (int64_t b = 0; b < blocks; ++b) {
    const uint32_t n = count(b);
    if (n <= longer) continue;
    const uint64_t begin = bb.listStride ? uint64_t(b) * bb.listStride : end(b) - n;
    for (uint32_t k = 1; k < n; ++k)
      if (!(tris(begin + k - 1) < tris(begin + k))) return false;
  }
  return true;
}

}  // namespace

TEST_CASE("BLEND: weighted's lists that the team walks in place are sorted before it", "[transparency][blend]") {
  // weighted adds a sample's terms in raster-index order. The team form
  // ranks a list that fits every team's scratch itself (kTeamEntriesAlways)
  // and walks a longer one in place: the resolve sorts those first
  // (tiles_sort), after every layout has found the frame's longest list
  // (the counted lists' scan, tiles_longest, or the glTF shading's
  // classification of the uniform blocks), and sorts nothing where it fits.
  // A GPU's fill leaves a list in its schedule's order, a CPU's where its
  // threads share a block's items. The lists as the resolve left them (a
  // second frame), for crossing layers whose diagonals' lists outgrow the
  // scratch: counted (40 layers, 80 entries) and strided (14 layers, 28
  // entries, the room 32), Lambert and the glTF shading, one and four
  // samples.
  TeamForm g;
  for (const char* name : {"builtin:layers?n=40&mixed=1&cross=1", "builtin:layers?n=14&mixed=1&cross=1"}) {
    const Scene s = builtinScene(name);
    for (ShadingMode mode : {ShadingMode::Lambert, ShadingMode::Pbr})
      for (int msaa : {1, 4}) {
        INFO(name << " " << toString(mode) << " msaa " << msaa);
        RenderSettings rs = withIdsAndDepth(93, 53);
        rs.shading = mode;
        rs.msaa = msaa;
        rs.transparency = Transparency::Weighted;
        Stride h(32);
        Renderer r(s);
        // The first frame's lists are counted; where they would fit the
        // strided layout's room, the renderer then allocates it for the
        // next frames (lastFrameFit), and the lists are gone.
        r.render(defaultCamera(s), rs);
        const std::vector<rast::float4> want = r.filmBottomUp();
        const uint64_t longest = r.frameBuffers().blend.longestList;
        REQUIRE(longest > blending::kTeamEntriesAlways);  // lists that the team walks in place
        r.render(defaultCamera(s), rs);  // strided where they fit its room, else counted again
        CHECK(r.frameBuffers().blend.listStride == (longest <= 32 ? 32u : 0u));
        CHECK(longListsInOrder(r, blending::kTeamEntriesAlways));
        CHECK(sameBits(want, r.filmBottomUp()));
      }
  }
}

TEST_CASE("BLEND: the strided tile lists give the counted lists' bits", "[transparency][blend]") {
  // Where the last frame's lists were short, a GPU lays a block's list out
  // at block x stride and fills it in one pass (blend_tiles.cpp,
  // listStrideFor); TestHooks::listStride takes that layout here. The
  // first frame is counted (it finds the lists' lengths), the second
  // strided: the same bits and statistics as a counted frame, in the
  // plain and the team form, for separate, hidden, intersecting and 40
  // intersecting layers (their diagonals' 80 entries outgrow the room:
  // counted again), exact, sorted and weighted, Lambert and the glTF
  // shading, one and four samples, a frame not a multiple of 8.
  for (const char* name : {"builtin:layers?n=8&mixed=1", "builtin:layers?n=8&mixed=1&occluder=1",
                           "builtin:layers?n=12&mixed=1&cross=1&unlit=0", "builtin:layers?n=40&mixed=1&cross=1"}) {
    const Scene s = builtinScene(name);
    for (bool team : {false, true})
      for (ShadingMode mode : {ShadingMode::Lambert, ShadingMode::Pbr})
        for (int msaa : {1, 4})
          for (Transparency t : {Transparency::Exact, Transparency::Sorted, Transparency::Weighted}) {
            INFO(name << " team " << team << " " << toString(mode) << " msaa " << msaa << " method " << int(t));
            TeamForm g(team);
            RenderSettings rs = withIdsAndDepth(93, 53);
            rs.shading = mode;
            rs.msaa = msaa;
            rs.transparency = t;
            FrameStats counted;
            const std::vector<rast::float4> want = film(s, rs, &counted);
            Stride h(32);
            Renderer r(s);
            r.render(defaultCamera(s), rs);
            CHECK(r.frameBuffers().blend.listStride == 0);  // the first frame counts
            const uint64_t longest = r.frameBuffers().blend.longestList;
            const FrameStats got = r.render(defaultCamera(s), rs);
            CHECK(r.frameBuffers().blend.listStride == (longest <= 32 ? 32u : 0u));
            // The strided frame's longest list (found by tiles_longest, or
            // by the glTF shading's team form as it classifies the blocks)
            // is the counted frame's.
            CHECK(r.frameBuffers().blend.longestList == longest);
            CHECK(sameBits(want, r.filmBottomUp()));
            CHECK(got.blendFragments == counted.blendFragments);
            CHECK(got.blendMaxDepth == counted.blendMaxDepth);
          }
  }
  // Lists that outgrow the room of a frame whose last frame's were short
  // (looking away: none): the frame is drawn again, counted; in the plain
  // form and the glTF shading's team form (whose classification finds the
  // longest list).
  const Scene s = builtinScene("builtin:layers?n=8&mixed=1");
  for (ShadingMode mode : {ShadingMode::Lambert, ShadingMode::Pbr})
    for (bool team : {false, true}) {
      INFO(toString(mode) << " team " << team);
      TeamForm g(team);
      RenderSettings rs = withIdsAndDepth(93, 53);
      rs.transparency = Transparency::Exact;
      rs.shading = mode;
      const std::vector<rast::float4> want = film(s, rs);
      Stride h(4);
      Renderer r(s);
      Camera away = defaultCamera(s);
      away.target = away.eye + (away.eye - away.target);
      r.render(away, rs);
      r.render(away, rs);
      CHECK(r.frameBuffers().blend.listStride == 4);
      const FrameStats st = r.render(defaultCamera(s), rs);
      CHECK(st.attempts >= 2);  // (then the counted lists may need more room: a third)
      CHECK(r.frameBuffers().blend.listStride == 0);
      CHECK(sameBits(want, r.filmBottomUp()));
    }
}
