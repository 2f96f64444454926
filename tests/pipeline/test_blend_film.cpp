// The BLEND frame's film where its bytes are the output (docs/transparency.md,
// "The film"): the pixels that the glTF shading composites as it shades them
// write their colour's bytes and no film value (BlendPlan::filmless), which
// nothing reads after them. The other tests keep the film (TestHooks::keepFilm,
// set for every test case by tests/support/test_main.cpp) to compare it; here
// the frames without it are checked against those with it.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "pipeline/data/test_hooks.h"
#include "pipeline/frame/renderer.h"
#include "scenes/procedural.h"
#include "tests/support/test_support.h"

using namespace rast;
using namespace rast::test;

namespace {

// Pixels of the last frame's film that hold NaN in every channel (left as
// filled: no pass of the frame wrote them).
size_t unwritten(const Renderer& r) {
  size_t n = 0;
  for (const rast::float4& c : r.filmBottomUp())
    n += std::isnan(c.x) && std::isnan(c.y) && std::isnan(c.z) && std::isnan(c.w) ? 1u : 0u;
  return n;
}

// A second frame of r over a film filled with NaN.
void renderOverNan(Renderer& r, const Scene& s, const RenderSettings& rs) {
  r.render(defaultCamera(s), rs);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  Kokkos::deep_copy(r.frameBuffers().post.hdr, rast::float4{nan, nan, nan, nan});
  r.render(defaultCamera(s), rs);
}

}  // namespace

TEST_CASE("BLEND: the pixels the glTF shading composites write their bytes without the film, the same bytes",
          "[transparency][blend]") {
  // The glTF shading's team form (GPUs; TestHooks::teamResolve here) at one
  // sample composites the uniform blocks as it shades them; where the frame
  // writes its colour's bytes (a PNG's frame, no post pass) those pixels
  // skip the film. Each frame is drawn over a film filled with NaN: with the
  // film kept every pixel is written, without it those of the composited
  // blocks are not, and the colour's bytes are the same, for separate and
  // hidden layers and a blended cut-out (blocks composited by the shading),
  // lit intersecting and 40 intersecting layers (every block walked by the
  // resolve, which reads the film: all of it written), exact, sorted and
  // weighted, an opaque and a transparent background (straight alpha).
  const struct {
    const char* name;
    bool composited;
  } scenes[] = {{"builtin:layers?n=8&mixed=1", true},
                {"builtin:layers?n=8&mixed=1&occluder=1", true},
                {"builtin:layers?n=12&mixed=1&cross=1&unlit=0", false},
                {"builtin:layers?n=40&mixed=1&cross=1", false},
                {"builtin:cutout?blend=1", true}};
  for (const auto& sc : scenes) {
    const char* name = sc.name;
    const Scene s = builtinScene(name);
    for (Transparency t : {Transparency::Exact, Transparency::Sorted, Transparency::Weighted})
      for (float alpha : {1.0f, 0.0f}) {
        INFO(name << " method " << int(t) << " background alpha " << alpha);
        testHooks().teamResolve = true;
        RenderSettings rs;
        rs.width = 93;
        rs.height = 53;
        rs.shading = ShadingMode::Pbr;
        rs.transparency = t;
        rs.background.w = alpha;
        testHooks().keepFilm = true;
        Renderer kept(s);
        renderOverNan(kept, s, rs);
        REQUIRE(kept.lastPlan().blend.shadeComposite);
        CHECK_FALSE(kept.lastPlan().blend.filmless);
        CHECK(unwritten(kept) == 0);
        testHooks().keepFilm = false;
        Renderer r(s);
        renderOverNan(r, s, rs);
        CHECK(r.lastPlan().blend.filmless);
        CHECK((unwritten(r) > 0) == sc.composited);
        CHECK(r.colorTopDown() == kept.colorTopDown());
      }
  }
  // Where the film is an output (PFM, EXR: post.floatOutput) or several
  // samples are resolved, every pixel's film is written.
  const Scene s = builtinScene("builtin:layers?n=8&mixed=1");
  testHooks().teamResolve = true;
  testHooks().keepFilm = false;
  for (int msaa : {1, 4}) {
    INFO("msaa " << msaa);
    RenderSettings rs;
    rs.width = 93;
    rs.height = 53;
    rs.shading = ShadingMode::Pbr;
    rs.transparency = Transparency::Exact;
    rs.msaa = msaa;
    rs.post.floatOutput = msaa == 1;
    Renderer r(s);
    renderOverNan(r, s, rs);
    CHECK_FALSE(r.lastPlan().blend.filmless);
    CHECK(unwritten(r) == 0);
  }
}
