// glTF alpha modes (docs/transparency.md): MASK fragments below the cutoff
// lose the depth test in every raster method; BLEND layers composite in
// linear light, exactly for `exact`, with each approximate method's failure
// pinned to its bound; more layers than a resolve pass keeps are peeled bit
// for bit; the passes' specialised fragment shading gives the general one's
// bits; an opaque scene allocates nothing for them; tile lists over the
// memory budget fall back to kbuffer (weighted to its fixed-memory sums) and
// say so.
#include <catch2/catch.hpp>

#include <cmath>
#include <initializer_list>
#include <string>

#include "pipeline/blend/blend.h"
#include "pipeline/blend/peel_team.h"
#include "pipeline/blend/uniform_blocks.h"
#include "pipeline/frame/renderer.h"
#include "scenes/procedural.h"
#include "pipeline/data/test_hooks.h"
#include "tests/support/blend_support.h"
#include "tests/support/test_support.h"

using namespace rast;
using namespace rast::test;

namespace {

RenderSettings small(int w = 96, int h = 54) { return withIdsAndDepth(w, h); }

double maxDiff(const std::vector<rast::float4>& a, const std::vector<rast::float4>& b) {
  double m = 0.0;
  for (size_t i = 0; i < a.size(); ++i)
    m = std::max({m, std::fabs(double(a[i].x) - b[i].x), std::fabs(double(a[i].y) - b[i].y),
                  std::fabs(double(a[i].z) - b[i].z)});
  return m;
}

const Transparency kMethods[] = {Transparency::Exact, Transparency::Sorted, Transparency::KBuffer, Transparency::Weighted};

}  // namespace

TEST_CASE("MASK: fragments below the cutoff lose the depth test in every raster method", "[transparency][mask]") {
  const Scene s = builtinScene("builtin:cutout");  // backdrop: triangles 1-2; the mask quad: 3-4
  RenderSettings rs = small();
  for (int msaa : {1, 4}) {
    std::vector<uint32_t> first;  // ids are the first sample's: per sample count
    for (RasterMethod m : allRasterMethods()) {
      INFO(toString(m) << " msaa " << msaa);
      rs.raster = m;
      rs.msaa = msaa;
      const Frame f = renderFrame(s, defaultCamera(s), rs);
      // The quad spans x in [-2, 2] of [-3.68, 3.68]: pixels 22..73 of 96;
      // its alpha runs 0 -> 1 left to right, the cutoff 0.5 at the middle.
      const int y = rs.height / 2;
      CHECK(f.id(30, y) <= 2);  // alpha about 0.15: discarded, the backdrop shows
      CHECK(f.id(65, y) >= 3);  // alpha about 0.84: kept
      CHECK(f.id(5, y) <= 2);
      if (first.empty()) first = f.ids;
      else CHECK(f.ids == first);
    }
  }
  SECTION("the cutoff moves the edge") {
    const Frame none = renderFrame(builtinScene("builtin:cutout?cutoff=1.01"), defaultCamera(s), small());
    const Frame all = renderFrame(builtinScene("builtin:cutout?cutoff=0"), defaultCamera(s), small());
    for (int x = 25; x < 70; ++x) {
      CHECK(none.id(x, 27) <= 2);
      CHECK(all.id(x, 27) >= 3);
    }
  }
}

TEST_CASE("MASK under MSAA: alpha-to-coverage keeps a dithered share of each pixel's samples", "[transparency][mask]") {
  // The cutout quad faces the camera and its alpha runs along x alone, so a
  // per-sample test would cover the same samples in every row of a column;
  // alpha-to-coverage takes one alpha a pixel and covers the samples its
  // dither ranks first: along the edge, the first sample (the id) changes
  // from row to row while the share covered (the colour) does not. (With
  // the default cutoff 0.5 the edge falls on a pixel boundary: every pixel
  // is all in or all out either way; 0.45 moves it into a pixel.)
  const Scene s = builtinScene("builtin:cutout?cutoff=0.45");
  RenderSettings rs = small();
  rs.msaa = 4;
  std::vector<uint32_t> first;
  for (RasterMethod m : allRasterMethods()) {
    INFO(toString(m));
    rs.raster = m;
    const Frame f = renderFrame(s, defaultCamera(s), rs);
    if (first.empty()) first = f.ids;
    else CHECK(f.ids == first);  // the same samples under every method
  }
  const Frame f = renderFrame(s, defaultCamera(s), rs);
  int dithered = 0;
  for (int x = 30; x < 66; ++x) {
    bool differs = false;
    for (int y = 20; y < 34; ++y) {
      differs |= (f.id(x, y) >= 3) != (f.id(x, 20) >= 3);
      // colour rows are top first, ids bottom first: the same rows either way round
      const uint32_t a = f.color[size_t(f.height - 1 - y) * size_t(f.width) + size_t(x)];
      const uint32_t b = f.color[size_t(f.height - y) * size_t(f.width) + size_t(x)];  // the row below
      INFO("x " << x << " y " << y);
      for (int sh = 0; sh < 24; sh += 8) CHECK(std::abs(int(a >> sh & 0xffu) - int(b >> sh & 0xffu)) <= 3);
    }
    dithered += differs ? 1 : 0;
  }
  CHECK(dithered >= 1);
}

// Which BLEND frames a GPU records and replays (blendLaunchesLightweight):
// those whose passes all launch lightweight, the listed methods with the lit
// or glTF fragment shading; kbuffer, weighted's fixed-memory sums and the
// general fragment maths copy their functors at each launch and run directly.
TEST_CASE("BLEND frames of the listed methods with a specialised shading launch lightweight", "[transparency][blend][graphs]") {
  ShadeParams p{};
  p.filter = TexFilter::Bilinear;
  BlendPlan b;
  b.blend = true;
  for (Transparency t : {Transparency::Exact, Transparency::Sorted, Transparency::Weighted}) {
    b.method = t;
    b.lists = true;
    for (ShadingMode m : {ShadingMode::Lambert, ShadingMode::BlinnPhong, ShadingMode::Pbr}) {
      p.mode = m;
      CHECK(blendLaunchesLightweight(b, p));
    }
    p.mode = ShadingMode::Normals;  // the general fragment maths
    CHECK_FALSE(blendLaunchesLightweight(b, p));
    p.mode = ShadingMode::Lambert;
    p.filter = TexFilter::Trilinear;  // the lit family filters bilinear or nearest
    CHECK_FALSE(blendLaunchesLightweight(b, p));
    p.filter = TexFilter::Bilinear;
  }
  p.mode = ShadingMode::Lambert;
  b.method = Transparency::Weighted;
  b.lists = false;  // its fixed-memory sums
  CHECK_FALSE(blendLaunchesLightweight(b, p));
  b.method = Transparency::KBuffer;
  CHECK_FALSE(blendLaunchesLightweight(b, p));
  b.blend = false;  // no BLEND layer: nothing of the method runs
  CHECK(blendLaunchesLightweight(b, p));
}

// The auto method's statistics (rasterStatistics) describe the opaque
// triangles the raster methods draw: MASK and BLEND triangles, whose boxes
// the setup empties, are no occluder candidates. Counted, eight full-screen
// layers over the backdrop made nine frames' worth of candidates and turned
// the visbuffer's occluder pass on (on a GPU) for the backdrop alone.
TEST_CASE("MASK and BLEND triangles are not counted as occluders by the auto method's statistics",
          "[transparency][blend][raster]") {
  for (const char* spec : {"builtin:layers?n=8&mixed=1", "builtin:cutout", "builtin:layers?n=0"}) {
    INFO(spec);
    const Scene s = builtinScene(spec);
    RenderSettings rs = small();
    rs.raster = RasterMethod::Auto;
    const Frame f = renderFrame(s, defaultCamera(s), rs);
    // The backdrop covers the viewport: its two triangles' area in it, once.
    const double frame = double(rs.width) * rs.height;
    CHECK(double(f.stats.occluderArea) >= 0.98 * frame);
    CHECK(double(f.stats.occluderArea) <= 1.02 * frame);
  }
}

TEST_CASE("BLEND: blue at alpha 0.5 over opaque red is (0.5, 0, 0.5) in linear light under every method",
          "[transparency][blend]") {
  const Scene s = builtinScene("builtin:layers?n=1&alpha=0.5&unlit=1");
  for (Transparency t : kMethods) {
    INFO(toString(t));
    RenderSettings rs = small();
    rs.shading = ShadingMode::Pbr;  // KHR_materials_unlit
    rs.transparency = t;
    const std::vector<rast::float4> f = film(s, rs);
    const rast::float4 c = f[size_t(rs.height / 2) * rs.width + rs.width / 2];
    const double tol = t == Transparency::Weighted ? 1e-6 : 0.0;
    CHECK(std::fabs(c.x - 0.5) <= tol);
    CHECK(c.y == 0.0f);
    CHECK(std::fabs(c.z - 0.5) <= tol);
  }
}

TEST_CASE("BLEND exact: the same bits under every raster method and sample count", "[transparency][blend]") {
  const Scene s = builtinScene("builtin:layers?n=12&mixed=1&cross=1");
  for (int msaa : {1, 4}) {
    std::vector<rast::float4> first;
    std::vector<uint32_t> firstIds;
    for (RasterMethod m : allRasterMethods()) {
      INFO(toString(m) << " msaa " << msaa);
      RenderSettings rs = small();
      rs.msaa = msaa;
      rs.raster = m;
      rs.transparency = Transparency::Exact;
      Renderer r(s);
      r.render(defaultCamera(s), rs);
      const std::vector<rast::float4> f = r.filmBottomUp();
      if (first.empty()) {
        first = f;
        firstIds = r.primIdsBottomUp();
      } else {
        CHECK(sameBits(f, first));
        CHECK(r.primIdsBottomUp() == firstIds);  // ids are the opaque surface's
      }
    }
  }
}

TEST_CASE("BLEND: each method's failure mode within its bound", "[transparency][blend]") {
  RenderSettings rs = small();
  auto with = [&](const char* scene, Transparency t, FrameStats* st = nullptr) {
    RenderSettings q = rs;
    q.transparency = t;
    q.blendK = 4;
    return film(builtinScene(scene), q, st);
  };
  SECTION("kbuffer equals exact bit for bit while layers <= k, and stays close beyond") {
    CHECK(sameBits(with("builtin:layers?n=4&mixed=1", Transparency::KBuffer),
                   with("builtin:layers?n=4&mixed=1", Transparency::Exact)));
    const double e = maxDiff(with("builtin:layers?n=16&mixed=1", Transparency::KBuffer),
                             with("builtin:layers?n=16&mixed=1", Transparency::Exact));
    CHECK(e > 0.0);   // more layers than k: the rest is merged
    CHECK(e < 0.05);  // behind four layers of alpha >= 0.2
  }
  SECTION("sorted equals exact for separate parallel layers, not for intersecting ones") {
    CHECK(maxDiff(with("builtin:layers?n=8&mixed=1", Transparency::Sorted),
                  with("builtin:layers?n=8&mixed=1", Transparency::Exact)) == 0.0);
    CHECK(maxDiff(with("builtin:layers?n=8&mixed=1&cross=1", Transparency::Sorted),
                  with("builtin:layers?n=8&mixed=1&cross=1", Transparency::Exact)) > 0.02);
  }
  SECTION("weighted: exact for layers of one colour, wrong with a strong layer in front") {
    CHECK(maxDiff(with("builtin:layers?n=8&alpha=0.3", Transparency::Weighted),
                  with("builtin:layers?n=8&alpha=0.3", Transparency::Exact)) < 1e-5);
    CHECK(maxDiff(with("builtin:layers?n=8&mixed=1", Transparency::Weighted),
                  with("builtin:layers?n=8&mixed=1", Transparency::Exact)) > 0.02);
  }
  SECTION("equal depths (coplanar layers) are ordered by primitive id: deterministic") {
    CHECK(sameBits(with("builtin:layers?n=6&mixed=1&equal=1", Transparency::Exact),
                   with("builtin:layers?n=6&mixed=1&equal=1&order=back", Transparency::Exact)));
  }
  SECTION("alpha outside [0, 1] is clamped") {
    CHECK(sameBits(with("builtin:layers?n=2&alpha=7", Transparency::Exact),
                   with("builtin:layers?n=2&alpha=1", Transparency::Exact)));
    // Alpha 0: every fragment dropped; the image is the opaque backdrop's
    // alone (drawn directly, without the film: the same bytes).
    auto colour = [&](const char* scene) {
      const Scene s = builtinScene(scene);
      Renderer r(s);
      r.render(defaultCamera(s), rs);
      return r.colorTopDown();
    };
    CHECK(colour("builtin:layers?n=2&alpha=-3") == colour("builtin:layers?n=0"));
  }
}

TEST_CASE("BLEND exact: more layers than the keys a pass keeps are peeled, bit for bit", "[transparency][blend]") {
  // 40 layers, mixed and intersecting: more than the K keys the resolve
  // keeps per sample and pass (16 on a CPU, 8 on a GPU), so every sample is
  // peeled in several passes over its block's list. The reference composites
  // every fragment at once: kbuffer with k >= layers keeps them all, sorted
  // by key, and merges nothing (the same "over" and fragment maths).
  const Scene s = builtinScene("builtin:layers?n=40&mixed=1&cross=1");
  for (int msaa : {1, 4}) {
    INFO("msaa " << msaa);
    RenderSettings rs = small();
    rs.msaa = msaa;
    rs.transparency = Transparency::Exact;
    FrameStats st;
    const std::vector<rast::float4> exact = film(s, rs, &st);
    CHECK(st.blendMaxDepth > 16);  // peeled
    RenderSettings k = rs;
    k.transparency = Transparency::KBuffer;
    k.blendK = 64;
    CHECK(sameBits(exact, film(s, k)));
  }
}

TEST_CASE("BLEND: the specialised fragment shading gives the general fragment maths' bits", "[transparency][blend]") {
  // Each pass shades its fragments with code compiled for the frame's
  // shading (lit, glTF; frag_shade.h); TestHooks::generalShade makes them
  // take the shade stage's general fragment maths instead. Lit and glTF
  // layers (lit, not unlit), intersecting; COLOR_0 with an alpha ramp
  // (the cut-out quad drawn BLEND); one and four samples; the methods whose
  // films do not depend on the thread schedule (kbuffer with room for every
  // layer merges nothing).
  struct General {
    General() { testHooks().generalShade = true; }
    ~General() { testHooks().generalShade = false; }
  };
  for (const char* name : {"builtin:layers?n=12&mixed=1&cross=1&unlit=0", "builtin:cutout?blend=1"}) {
    const Scene s = builtinScene(name);
    for (ShadingMode mode : {ShadingMode::Lambert, ShadingMode::BlinnPhong, ShadingMode::Pbr})
      for (int msaa : {1, 4})
        for (Transparency t : {Transparency::Exact, Transparency::Sorted, Transparency::KBuffer}) {
          INFO(name << " " << toString(mode) << " msaa " << msaa << " method " << int(t));
          RenderSettings rs = small();
          rs.shading = mode;
          rs.msaa = msaa;
          rs.transparency = t;
          rs.blendK = 16;
          const std::vector<rast::float4> special = film(s, rs);
          std::vector<rast::float4> general;
          {
            General g;
            general = film(s, rs);
          }
          CHECK(sameBits(special, general));
        }
  }
}

// The listed methods' films and statistics as the renderer draws them and
// under the test hook that Guard sets (constructor) and restores
// (destructor): the same bits, for each scene, under Lambert, Blinn-Phong
// and the glTF shading, one and four samples, exact, sorted and weighted.
template <class Guard>
void sameUnderHook(std::initializer_list<const char*> names, const RenderSettings& size) {
  for (const char* name : names) {
    const Scene s = builtinScene(name);
    for (ShadingMode mode : {ShadingMode::Lambert, ShadingMode::BlinnPhong, ShadingMode::Pbr})
      for (int msaa : {1, 4})
        for (Transparency t : {Transparency::Exact, Transparency::Sorted, Transparency::Weighted}) {
          INFO(name << " " << toString(mode) << " msaa " << msaa << " method " << int(t));
          RenderSettings rs = size;
          rs.shading = mode;
          rs.msaa = msaa;
          rs.transparency = t;
          FrameStats plainStats, hookStats;
          const std::vector<rast::float4> plain = film(s, rs, &plainStats);
          std::vector<rast::float4> hooked;
          {
            Guard g;
            hooked = film(s, rs, &hookStats);
          }
          CHECK(sameBits(plain, hooked));
          CHECK(plainStats.blendFragments == hookStats.blendFragments);
          CHECK(plainStats.blendMaxDepth == hookStats.blendMaxDepth);
        }
  }
}

TEST_CASE("BLEND: the resolve's team form gives the plain form's bits", "[transparency][blend]") {
  // GPUs resolve exact and sorted a team per 8x8 block, its list set up once
  // in team scratch (peel_team.h, PeelTeam); TestHooks::teamResolve runs
  // that form here. Separate lit layers, submitted back to front and front to
  // back (exact: the blocks whose triangles' depth ranges do not overlap are
  // walked once in that order; unlit ones too, which the glTF shading
  // composites with their one colour), 40 separate lit layers (lists longer
  // than the entries a frame's first scratch holds: ordered by their ranges
  // in its room and walked once from global memory), intersecting ones (12:
  // peeled keys from the list in scratch; 40: the lists outgrow it, their
  // ranges overlap, and they take the plain walk), coplanar ones (ordered by raster index), a
  // vertex-coloured BLEND quad; one and four samples; exact, sorted and
  // weighted (its sums in raster-index order: the list sorted, or the
  // entries in scratch); the statistics too.
  sameUnderHook<TeamForm>({"builtin:layers?n=8&mixed=1&unlit=0", "builtin:layers?n=8&mixed=1&unlit=0&order=front",
                       "builtin:layers?n=8&mixed=1", "builtin:layers?n=8&mixed=1&order=front",
                       "builtin:layers?n=8&mixed=1&occluder=1", "builtin:layers?n=8&mixed=1&cross=1",
                       "builtin:layers?n=8&mixed=1&tex=1",
                       "builtin:layers?n=40&mixed=1&unlit=0", "builtin:layers?n=12&mixed=1&cross=1&unlit=0",
                       "builtin:layers?n=40&mixed=1&cross=1",
                       "builtin:layers?n=6&mixed=1&equal=1", "builtin:cutout?blend=1"},
                      small());
  // Under the glTF shading the unlit layers' blocks are composited once
  // before the team's walk (uniform_blocks.h), those on the quads' diagonals
  // too (a quad's two halves, which share an edge, as one layer); those that
  // the occluder's edges cross or hide layers in are walked: both kinds are
  // in the films compared above. The walk is taken for
  // every block of lit layers, for weighted's tilted ones (no one weight), and
  // for exact's tilted ones, whose whole depth ranges overlap, and for
  // unlit layers with a texture (FragShade::constantColourOf).
  {
    TeamForm g;
    const auto uniformBlocks = [](const char* name, Transparency t) {  // under the glTF shading
      const Scene s = builtinScene(name);
      RenderSettings rs = small();
      rs.shading = ShadingMode::Pbr;
      rs.transparency = t;
      Renderer r(s);
      r.render(defaultCamera(s), rs);
      const auto frags = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), r.frameBuffers().blend.blockFrags);
      const size_t blocks = size_t((rs.width + 7) / 8) * size_t((rs.height + 7) / 8);
      size_t once = 0;
      for (size_t b = 0; b < blocks && b < frags.extent(0); ++b) once += frags(b) != rast::kUniformWalk ? 1 : 0;
      return std::make_pair(once, blocks);
    };
    for (Transparency t : {Transparency::Exact, Transparency::Sorted, Transparency::Weighted}) {
      INFO("method " << int(t));
      const auto plain = uniformBlocks("builtin:layers?n=8&mixed=1", t);
      CHECK(plain.first == plain.second);  // the quads' diagonals too: their halves taken as one
      const auto hidden = uniformBlocks("builtin:layers?n=8&mixed=1&occluder=1", t);
      CHECK(hidden.first > 0);
      CHECK(hidden.first + 4 < plain.first);  // the blocks over the occluder (9 of 84) walked
      CHECK(uniformBlocks("builtin:layers?n=8&mixed=1&unlit=0", t).first == 0);
      CHECK(uniformBlocks("builtin:layers?n=8&mixed=1&tex=1", t).first == 0);  // unlit, textured
      const auto tilted = uniformBlocks("builtin:layers?n=8&mixed=1&cross=1", t);
      if (t == Transparency::Sorted)
        CHECK(tilted.first > 0);
      else
        CHECK(tilted.first == 0);
    }
  }
  // A second frame sizes the scratch for the first frame's longest list
  // (40 intersecting layers: up to 80 triangles a block, past the smaller
  // scratch): the same bits as the first frame, which walked those lists
  // from global memory.
  TeamForm g;
  const Scene s = builtinScene("builtin:layers?n=40&mixed=1&cross=1");
  RenderSettings rs = small();
  rs.transparency = Transparency::Exact;
  Renderer r(s);
  r.render(defaultCamera(s), rs);
  const std::vector<rast::float4> first = r.filmBottomUp();
  r.render(defaultCamera(s), rs);
  CHECK(r.frameBuffers().blend.longestList >= 60);
  CHECK(sameBits(first, r.filmBottomUp()));
}

TEST_CASE("BLEND: the long lists' kernel gives the plain form's bits", "[transparency][blend]") {
  // Where the last frame's longest list outgrew the team's larger scratch
  // (here lowered to 24 entries, TestHooks::teamDeepEntries), the lists
  // longer than its entries are resolved by a kernel of their own
  // (PeelTeam<…, true>): exact's ranked by their depth ranges over the
  // block, walked once where those keep one order, merged in one walk where
  // they overlap but few at a time (a quad's two halves, whose ranges
  // coincide: the blocks on the quads' diagonals), else peeled from the
  // list (intersecting layers where more ranges are open at once). sorted's
  // and weighted's stay in the team's kernel. The second frame's film and
  // statistics against the plain form's: separate lit layers back to front
  // and front to back (40: lists of 40, and of 80 on the diagonals), 64
  // unlit ones, 40 intersecting ones; Lambert and the glTF shading; one and
  // four samples. A walk that let a later fragment pass a nearer one held,
  // or lost one, changes the bits.
  struct Deep {
    Deep() { testHooks().teamDeepEntries = 24; }
    ~Deep() { testHooks().teamDeepEntries = 0; }
  };
  for (const char* name : {"builtin:layers?n=40&mixed=1&unlit=0", "builtin:layers?n=40&mixed=1&unlit=0&order=front",
                           "builtin:layers?n=64&alpha=0.1", "builtin:layers?n=40&mixed=1&cross=1"}) {
    const Scene s = builtinScene(name);
    for (ShadingMode mode : {ShadingMode::Lambert, ShadingMode::Pbr})
      for (int msaa : {1, 4})
        for (Transparency t : {Transparency::Exact, Transparency::Sorted, Transparency::Weighted}) {
          INFO(name << " " << toString(mode) << " msaa " << msaa << " method " << int(t));
          RenderSettings rs = small();
          rs.shading = mode;
          rs.msaa = msaa;
          rs.transparency = t;
          FrameStats plainStats, longStats;
          const std::vector<rast::float4> plain = film(s, rs, &plainStats);
          TeamForm g;
          Deep d;
          Renderer r(s);
          r.render(defaultCamera(s), rs);
          longStats = r.render(defaultCamera(s), rs);
          // Whether the frame left its long lists to the long lists' kernel
          // (exact's only; on a GPU, which ignores the hook, where the lists
          // outgrew the real larger scratch).
          const uint64_t longest = r.frameBuffers().blend.longestList;
          const bool ran = mode == ShadingMode::Pbr ? blending::PeelTeam<blending::kFragPbr, 0>::defersLong(longest)
                                                    : blending::PeelTeam<blending::kFragLit, 0>::defersLong(longest);
          if (!kOnDevice) REQUIRE(ran);
          CHECK(sameBits(plain, r.filmBottomUp()));
          CHECK(plainStats.blendFragments == longStats.blendFragments);
          CHECK(plainStats.blendMaxDepth == longStats.blendMaxDepth);
          const auto totals = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), r.frameBuffers().blend.totals);
          const std::string n(name);
          const bool separate = n.find("unlit=0") != std::string::npos || n.find("n=64") != std::string::npos;
          if (t != Transparency::Exact || !ran)
            CHECK(totals(kBlendMerged) == 0);  // the team's kernel
          else if (separate)
            CHECK(totals(kBlendMerged) > 0);  // the diagonals' blocks
        }
  }
}

TEST_CASE("BLEND: the glTF shading's kernel writes the opaque depth that the resolve reads", "[transparency][blend]") {
  // The glTF shading's kernel at one sample writes each sample's opaque
  // depth as it reads and clears its key (BlendPlan::shadeDepth), and the
  // tile lists' stage copies none; the general kernel (a CPU's at a pixel a
  // work item, TestHooks::shadeRun = 1) and MSAA keep the copy. The same
  // bits and statistics: layers with an occluder (the resolve compares each
  // fragment with that depth), intersecting ones, a cut-out quad, exact,
  // sorted and weighted, with and without the team form.
  struct PerPixel {
    PerPixel() { testHooks().shadeRun = 1; }
    ~PerPixel() { testHooks().shadeRun = 0; }
  };
  for (const char* name : {"builtin:layers?n=8&mixed=1&occluder=1", "builtin:layers?n=12&mixed=1&cross=1&unlit=0",
                           "builtin:cutout?blend=1"}) {
    const Scene s = builtinScene(name);
    for (bool team : {false, true})
      for (Transparency t : {Transparency::Exact, Transparency::Sorted, Transparency::Weighted}) {
        INFO(name << " team " << team << " method " << int(t));
        TeamForm h(team);
        RenderSettings rs = small(93, 53);
        rs.shading = ShadingMode::Pbr;
        rs.transparency = t;
        FrameStats copied, written;
        Renderer a(s);
        written = a.render(defaultCamera(s), rs);
        CHECK(a.lastPlan().blend.shadeDepth);
        // The team form's uniform blocks classified before shading and
        // composited by the kernel (Shade::blendFilm), against the pass
        // after shading that the general kernel keeps: the same bits.
        CHECK(a.lastPlan().blend.shadeComposite == (team || kOnDevice));
        PerPixel g;
        Renderer b(s);
        copied = b.render(defaultCamera(s), rs);
        CHECK(b.lastPlan().blend.shadeDepth == kOnDevice);  // (a GPU's run is one pixel anyway)
        CHECK(b.lastPlan().blend.shadeComposite == kOnDevice);
        CHECK(sameBits(a.filmBottomUp(), b.filmBottomUp()));
        CHECK(copied.blendFragments == written.blendFragments);
        CHECK(copied.blendMaxDepth == written.blendMaxDepth);
        rs.msaa = 4;  // the kernel of several samples copies
        a.render(defaultCamera(s), rs);
        CHECK(!a.lastPlan().blend.shadeDepth);
        CHECK(!a.lastPlan().blend.shadeComposite);
      }
  }
}

TEST_CASE("BLEND: a CPU's walk of a block's triangles in order gives its peeled rows' bits", "[transparency][blend]") {
  // A CPU thread resolves an 8x8 block: where the block's triangles keep one
  // order at every sample (sorted always; exact where their depth ranges
  // over the block do not overlap; weighted in raster-index order) it walks
  // each over the block's pixels in that order (peel_block.h), else it peels
  // the block's rows (peel.h), which TestHooks::peelRows forces everywhere.
  // Separate layers back to front and front to back (a quad's two halves,
  // whose ranges overlap along its diagonal, walked as one), intersecting
  // ones (the blocks along the intersections peeled; 40 of them: 80
  // triangles, more than a thread's lookups hold, blocks walked and peeled
  // by one thread), coplanar ones (equal ranges: peeled), 64 layers (the
  // diagonals' lists of 128 longer than a block walks in order), opaque
  // layers (a pixel stops at the first), a vertex-coloured quad; Lambert (lit
  // together by the span shader's vector loop), Blinn-Phong, the glTF shading
  // (the layers unlit: one colour a triangle, composited without shading;
  // where every listed layer covers a block, once for its 64 pixels);
  // one and four samples; the frame's size not a multiple of 8. GPUs ignore
  // the hook: there both films are the team form's.
  struct Rows {
    Rows() { testHooks().peelRows = true; }
    ~Rows() { testHooks().peelRows = false; }
  };
  sameUnderHook<Rows>({"builtin:layers?n=8&mixed=1&unlit=0", "builtin:layers?n=8&mixed=1&unlit=0&order=front",
                       "builtin:layers?n=8&mixed=1", "builtin:layers?n=8&mixed=1&order=front",
                       "builtin:layers?n=8&mixed=1&occluder=1",
                       "builtin:layers?n=40&mixed=1&unlit=0", "builtin:layers?n=12&mixed=1&cross=1&unlit=0",
                       "builtin:layers?n=40&mixed=1&cross=1",
                       "builtin:layers?n=6&mixed=1&equal=1", "builtin:layers?n=64&alpha=0.1",
                       "builtin:layers?n=4&alpha=1&unlit=0", "builtin:cutout?blend=1"},
                      small(93, 53));
}

TEST_CASE("BLEND: the tile lists' resolve encodes the colour to the post chain's bytes", "[transparency][blend]") {
  // Where nothing reads the float film after the tile lists' resolve (no
  // post pass, no float output, no supersampling), the resolve writes the
  // colour's bytes too (BlendPlan::encode, encodeFilm) and the post chain
  // does not run (on CPUs always, on GPUs under the glTF shading); TestHooks::chainEncode
  // makes the chain encode instead.
  // Light and raw data (the normals mode), an opaque, a transparent and a
  // half-transparent background (straight alpha), one and four samples, the
  // three listed methods; the frame's size not a multiple of 8. The team
  // form under the glTF shading at one sample too, whose shade stage encodes
  // the uniform blocks' pixels (BlendPlan::shadeComposite).
  struct Chain {
    Chain() { testHooks().chainEncode = true; }
    ~Chain() { testHooks().chainEncode = false; }
  };
  for (const char* name : {"builtin:layers?n=8&mixed=1&unlit=0", "builtin:layers?n=12&mixed=1&cross=1&unlit=0",
                           "builtin:layers?n=64&alpha=0.1", "builtin:cutout?blend=1"}) {
    const Scene s = builtinScene(name);
    for (ShadingMode mode : {ShadingMode::Lambert, ShadingMode::Pbr, ShadingMode::Normals})
      for (int msaa : {1, 4})
        for (Transparency t : {Transparency::Exact, Transparency::Sorted, Transparency::Weighted})
          for (const rast::float4 bg : {rast::float4{0.1f, 0.2f, 0.3f, 1.0f}, rast::float4{0.0f, 0.0f, 0.0f, 0.0f},
                                        rast::float4{0.2f, 0.3f, 0.4f, 0.5f}})
            for (bool team : {false, true}) {
              // (64 layers' lists are longer than a uniform block's: walked.)
              if (team && (mode != ShadingMode::Pbr || msaa != 1 || std::string(name).find("n=64") != std::string::npos))
                continue;
              INFO(name << " " << toString(mode) << " msaa " << msaa << " method " << int(t) << " alpha " << bg.w
                        << " team " << team);
              TeamForm h(team);
              RenderSettings rs = small(93, 53);
              rs.shading = mode;
              rs.msaa = msaa;
              rs.transparency = t;
              rs.background = bg;
              Renderer folded(s);
              folded.render(defaultCamera(s), rs);
              // CPUs: every fragment family; GPUs: the glTF shading's, whose
              // uniform blocks' pixels the shade stage writes (familyEncodes).
              CHECK(folded.lastPlan().blend.encode == (kBlendResolveEncodes || mode == ShadingMode::Pbr));
              if (team) CHECK(folded.lastPlan().blend.shadeComposite);
              Chain g;
              Renderer chained(s);
              chained.render(defaultCamera(s), rs);
              CHECK(!chained.lastPlan().blend.encode);
              CHECK(folded.colorTopDown() == chained.colorTopDown());
            }
  }
  // A post pass reads the film after the resolve: the chain encodes.
  const Scene s = builtinScene("builtin:layers?n=8&mixed=1");
  RenderSettings rs = small();
  rs.post.exposure = 0.5f;
  Renderer r(s);
  r.render(defaultCamera(s), rs);
  CHECK(r.lastPlan().blend.blend);
  CHECK(!r.lastPlan().blend.encode);
}

TEST_CASE("BLEND: tile lists over the memory budget fall back to kbuffer (weighted: its fixed sums) and say so",
          "[transparency][blend]") {
  {  // the statistics the tile lists' resolve reduces
    const Scene s = builtinScene("builtin:layers?n=64&alpha=0.2");
    RenderSettings rs = small(320, 180);
    rs.transparency = Transparency::Exact;
    FrameStats big;
    film(s, rs, &big);
    CHECK(big.transparency == Transparency::Exact);
    CHECK(!big.blendFallback);
    CHECK(big.blendFragments == uint64_t(320) * 180 * 64);  // every layer covers the frame
    CHECK(big.blendMaxDepth == 64);
  }
  // 1024 layers over 128x64 pixels: 4 bytes a (layer, 8x8 block) make lists
  // of about 600 KB, more than a k-buffer of one key (28 bytes a pixel,
  // 230 KB). A budget halfway between exact's bytes and kbuffer's: the
  // lists do not fit, the k-buffer does. (Opaque layers: exact stops after
  // the first.) Not a byte short of exact's final bytes: on the H100 that
  // still let the lists grow, as their check counts the bytes held at that
  // point of the frame (Renderer::render), not the frame's final ones.
  const Scene s = builtinScene("builtin:layers?n=1024&alpha=1");
  RenderSettings rs = small(128, 64);
  rs.transparency = Transparency::Exact;
  rs.blendK = 1;
  FrameStats ex, kb, tight;
  film(s, rs, &ex);
  REQUIRE(!ex.blendFallback);
  RenderSettings k = rs;
  k.transparency = Transparency::KBuffer;
  const std::vector<rast::float4> kbuf = film(s, k, &kb);
  INFO("exact " << ex.deviceBytes << " bytes, kbuffer " << kb.deviceBytes);
  REQUIRE(ex.deviceBytes > kb.deviceBytes + 100000);
  const uint64_t budget = (ex.deviceBytes + kb.deviceBytes) / 2;
  const std::vector<rast::float4> f = film(s, rs, &tight, budget);
  INFO("budget " << budget << " bytes, the fallen-back frame " << tight.deviceBytes);
  CHECK(tight.deviceBytes <= budget);
  CHECK(tight.blendFallback);
  CHECK(tight.transparency == Transparency::KBuffer);
  CHECK(maxDiff(f, kbuf) < 1e-5);  // the merged rest is summed with float atomics: any order
  // weighted walks the same lists (counting the same fragments), and over
  // the budget keeps its method with McGuire and Bavoil's fixed per-sample
  // sums: the same terms, added with atomics in any order.
  {
    RenderSettings w = rs;
    w.transparency = Transparency::Weighted;
    FrameStats listed, fixed;
    const std::vector<rast::float4> a = film(s, w, &listed);
    CHECK(!listed.blendFallback);
    CHECK(listed.transparency == Transparency::Weighted);
    CHECK(listed.blendFragments == ex.blendFragments);
    CHECK(listed.blendMaxDepth == ex.blendMaxDepth);
    const std::vector<rast::float4> b = film(s, w, &fixed, budget);
    CHECK(fixed.deviceBytes <= budget);
    CHECK(fixed.blendFallback);
    CHECK(fixed.transparency == Transparency::Weighted);
    CHECK(maxDiff(a, b) < 1e-5);
  }
  // A budget that holds neither: one clear error, no silent cap.
  CHECK_THROWS_AS(film(s, rs, nullptr, kb.deviceBytes - 100000), Error);
}

TEST_CASE("an opaque scene allocates nothing for transparency", "[transparency]") {
  const Scene s = builtinScene("builtin:default");
  Renderer r(s);
  RenderSettings rs = small();
  r.render(defaultCamera(s), rs);
  CHECK(r.frameBuffers().blend.bytes() == 0);
  CHECK(!r.scene().alphaDraws.data());
}
