// The BLEND class's work items (docs/transparency.md, "Work items"): where
// the setup's single-pass scan numbers them (a GPU's setup; here the same
// kernel on the CPU, TestHooks::gpuSetupOnHostTeam), the numbers, films and
// statistics equal those of the host's setup followed by the alpha classes'
// own scan.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstring>

#include "pipeline/data/test_hooks.h"
#include "pipeline/frame/renderer.h"
#include "pipeline/geometry/geometry.h"
#include "scenes/procedural.h"
#include "tests/support/test_support.h"

using namespace rast;
using namespace rast::test;

TEST_CASE("BLEND: the GPU's setup numbers the BLEND work items as the alpha classes' scan does", "[transparency][blend]") {
  // Where the setup runs its single-pass scan (GPUs; TestHooks::gpuSetupOnHostTeam
  // here) it numbers the BLEND triangles' work items itself (each raster
  // triangle's first, the total) and the alpha classes' scan is not run for
  // that class: the same numbers, films and statistics as the host's setup
  // followed by that scan, for one chunk and for three (300 layers: 601
  // triangles), with the eye among the layers (triangles clipped by the near
  // plane), one and four samples (the 300 layers at one), each after a frame
  // of the other view (whose totals the setup clears).
  if (kOnDevice) {  // the hook is a host backend's; a GPU's frames all take this path
    WARN("skipped: the GPU's setup on a host backend is compared here");
    return;
  }
  struct GpuSetup {
    explicit GpuSetup(int team) { testHooks().gpuSetupOnHostTeam = team; }
    ~GpuSetup() { testHooks().gpuSetupOnHostTeam = 0; }
  };
  // The frame's numbering: blendStart of its raster triangles, then the total.
  auto numbering = [](const Renderer& r, const FrameStats& st) {
    std::vector<uint64_t> v = download(r.frameBuffers().blend.blendStart);
    v.resize(st.rasterTris);
    v.push_back(download(r.frameBuffers().blend.totals)[kBlendItems]);
    return v;
  };
  auto sameBits = [](const std::vector<rast::float4>& a, const std::vector<rast::float4>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(rast::float4)) == 0;
  };
  const int most = std::min(4, int(Exec().concurrency()));
  for (const char* name : {"builtin:layers?n=8&mixed=1", "builtin:layers?n=12&mixed=1&cross=1&occluder=1",
                           "builtin:layers?n=300&mixed=1&cross=1"})
    for (bool inside : {false, true}) {
      const Scene s = builtinScene(name);
      REQUIRE(setupNumbersBlendItems(uint32_t(s.triangleCount())) == false);  // not on a CPU without the hook
      Camera among = defaultCamera(s);  // among the layers, looking across them
      among.eye = {0.0, 0.0, -0.45};
      among.target = {1.0, 0.1, -1.0};
      among.up = {0.0, 1.0, 0.0};
      const Camera cam = inside ? among : defaultCamera(s), other = inside ? defaultCamera(s) : among;
      for (int msaa : {1, 4})
        for (Transparency t : {Transparency::Exact, Transparency::Weighted}) {
          // The 300 layers (the look-back over three chunks) once a view: the
          // numbering does not depend on the samples or the method, and their
          // 1.5 M fragments a frame took most of the test's time.
          if (s.triangleCount() > 100 && (msaa != 1 || t != Transparency::Exact)) continue;
          INFO(name << (inside ? " inside" : "") << " msaa " << msaa << " method " << int(t));
          RenderSettings rs;
          rs.width = 93;
          rs.height = 53;
          rs.shading = ShadingMode::Pbr;
          rs.msaa = msaa;
          rs.transparency = t;
          Renderer host(s);
          const FrameStats hs = host.render(cam, rs);
          const std::vector<uint64_t> want = numbering(host, hs);
          CHECK(want.back() > 0);
          if (inside) CHECK(hs.rasterTris != uint64_t(s.triangleCount()));  // clipped (or culled) by the near plane
          for (int team : {1, most}) {
            INFO("teams of " << team);
            GpuSetup g(team);
            REQUIRE(setupNumbersBlendItems(uint32_t(s.triangleCount())));
            Renderer r(s);
            r.render(other, rs);  // first the other view: the status words and totals hold its numbers
            const FrameStats st = r.render(cam, rs);
            CHECK(st.rasterTris == hs.rasterTris);
            CHECK(numbering(r, st) == want);
            CHECK(r.frameBuffers().blend.longestList == host.frameBuffers().blend.longestList);
            CHECK(sameBits(host.filmBottomUp(), r.filmBottomUp()));
            CHECK(st.blendFragments == hs.blendFragments);
            CHECK(st.blendMaxDepth == hs.blendMaxDepth);
          }
        }
    }
}
