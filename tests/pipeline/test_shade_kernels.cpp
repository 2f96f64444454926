// The per-pixel shade kernel's two forms give the same images: lit frames
// (Lambert or Blinn-Phong, nearest or bilinear texturing, 8-bit colour) take
// a kernel compiled without the other modes' code (core/shade_fragment.h,
// Shade::litOnly); TestHooks::generalShade makes them take the general one.
// On a GPU both are what every frame runs; on a host backend the per-pixel
// kernel is the one a shade run of 1 asks for. The glTF shading's own kernel
// (rast::shade::pbr, pipeline/shade/pbr_fragment.h: one instance per set of
// scene features) against the general kernel likewise, on every backend in
// its own layout.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>

#include "host/scene/camera.h"
#include "host/gltf/gltf_loader.h"
#include "pipeline/data/device_scene.h"
#include "backends/exec_space.h"
#include "pipeline/data/test_hooks.h"
#include "scenes/procedural.h"
#include "tests/support/test_support.h"

using namespace rast;
using namespace rast::test;

namespace {

struct GeneralShade {
  GeneralShade() { testHooks().generalShade = true; }
  ~GeneralShade() { testHooks().generalShade = false; }
};

// pixelRuns: runs of one pixel (the lit kernel's layout, which host backends
// take only when asked); the glTF kernel keeps each backend's own layout.
void compareForms(const std::string& name, const Scene& s, const Camera& cam, RenderSettings rs, bool pixelRuns = true) {
  rs.width = 203;  // not a multiple of the kernel's 32-pixel tiles
  rs.height = 61;
  testHooks().shadeRun = pixelRuns ? 1 : 0;  // the per-pixel kernel on host backends too (GPUs always take it)
  rs.wantNormals = rs.wantDepth = rs.wantPrimId = true;
  INFO(name);
  Renderer lit(s), general(s);
  lit.render(cam, rs);
  {
    GeneralShade g;
    general.render(cam, rs);
  }
  const std::vector<uint32_t> c = lit.colorTopDown(), cg = general.colorTopDown();
  REQUIRE(c.size() == size_t(rs.width) * rs.height);
  size_t litPixels = 0;
  for (uint32_t id : lit.primIdsBottomUp()) litPixels += id != 0;
  CHECK(litPixels > size_t(rs.width) * rs.height / 16);  // a frame with something to shade
  CHECK(lit.primIdsBottomUp() == general.primIdsBottomUp());
  CHECK(lit.depthBottomUp() == general.depthBottomUp());
  // The same arithmetic in both forms: the same bytes on host backends. A
  // GPU's shade stage may fuse multiplies and adds (CMakeLists.txt: the CUDA
  // build's shade_stage.cpp), and nvcc fuses the two kernels' expressions
  // differently: there normals agree within a few ulps and colours within
  // 1/255 (docs/determinism.md), as across backends.
  const float normalTol = kOnDevice ? 1e-6f : 0.0f;
  const int colourTol = kOnDevice ? 1 : 0;
  const std::vector<rast::float3> n = lit.normalsBottomUp(), ng = general.normalsBottomUp();
  size_t normalDiffs = 0;
  for (size_t i = 0; i < n.size(); ++i)
    normalDiffs += std::fabs(n[i].x - ng[i].x) > normalTol || std::fabs(n[i].y - ng[i].y) > normalTol ||
                   std::fabs(n[i].z - ng[i].z) > normalTol;
  CHECK(normalDiffs == 0);
  size_t colourDiffs = 0;
  for (size_t i = 0; i < c.size(); ++i)
    for (int sh = 0; sh < 32; sh += 8)
      colourDiffs += std::abs(int(c[i] >> sh & 0xffu) - int(cg[i] >> sh & 0xffu)) > colourTol;
  CHECK(colourDiffs == 0);
  testHooks().shadeRun = 0;
}

}  // namespace

TEST_CASE("the lit shade kernel gives the general kernel's images", "[shade]") {
  const Scene d = builtinScene("builtin:default");  // textured, with vertex colours on some draws
  const Camera cam = defaultCamera(d);
  RenderSettings rs;
  compareForms("default (headlight, bilinear)", d, cam, rs);
  RenderSettings nearest = rs;
  nearest.filter = TexFilter::Nearest;
  compareForms("default, nearest", d, cam, nearest);
  RenderSettings phong = rs;
  phong.shading = ShadingMode::BlinnPhong;
  phong.lights = {DirectionalLight{{0.3f, 0.5f, 1.0f}, 0.7f}, DirectionalLight{{-1.0f, 0.2f, 0.3f}, 0.4f}};
  phong.background = {0.2f, 0.3f, 0.4f, 1.0f};
  compareForms("default, Blinn-Phong, two lights, background", d, cam, phong);
  RenderSettings wire = rs;
  wire.wireframe = Wireframe::On;  // line fragments among the triangles'
  compareForms("default, wireframe", d, cam, wire);
  for (const char* spec : {"builtin:bigtri", "builtin:overdraw?layers=8", "builtin:lines"}) {
    const Scene s = builtinScene(spec);
    compareForms(spec, s, defaultCamera(s), rs);
  }
  // The float film: tone mapped, and under BLEND layers (the resolve
  // composites over the film the lit kernel wrote).
  RenderSettings film = phong;
  film.post.tonemap = ToneMap::Neutral;
  compareForms("default, Blinn-Phong, tone mapped (the float film)", d, cam, film);
  const Scene layers = builtinScene("builtin:layers?n=8&mixed=1&unlit=0");
  compareForms("BLEND layers over the float film", layers, defaultCamera(layers), rs);
  const std::string dir = sharedDir();
  if (dir.empty()) {
    skipTest("../shared is absent: the textured milk truck (seen from its cab) was not compared");
    return;
  }
  const Scene truck = loadGltf(dir + "/models/milktruck.glb");
  compareForms("milktruck from its cab", truck, milktruckCabCamera(), rs);
  compareForms("milktruck", truck, defaultCamera(truck), rs);
}

TEST_CASE("the glTF shading's kernel gives the general kernel's images", "[shade][pbr]") {
  const Scene d = builtinScene("builtin:default");  // textured, with vertex colours on some draws
  const Camera cam = defaultCamera(d);
  RenderSettings rs;
  rs.shading = ShadingMode::Pbr;
  rs.filter = TexFilter::Auto;  // the samplers' own filters, anisotropic where they blend levels
  rs.environment = "none";
  compareForms("default, glTF, headlight", d, cam, rs, false);
  RenderSettings env = rs;
  env.environment = "";  // the built-in environment
  compareForms("default, glTF, built-in environment", d, cam, env, false);
  RenderSettings lights = rs;
  lights.lights = {DirectionalLight{{0.3f, 0.5f, 1.0f}, 0.7f}, DirectionalLight{{-1.0f, 0.2f, 0.3f}, 0.4f}};
  compareForms("default, glTF, two lights", d, cam, lights, false);
  RenderSettings wire = rs;
  wire.wireframe = Wireframe::On;  // line fragments among the triangles'
  compareForms("default, glTF, wireframe", d, cam, wire, false);
  RenderSettings film = env;
  film.post.tonemap = ToneMap::Neutral;  // the float film
  compareForms("default, glTF, environment, tone mapped", d, cam, film, false);
  // builtin:default samples base colour textures only: the frames above
  // took the instances that sample that texture alone (kPbrBaseTexture).
  // With an occlusion texture too they take the loop over the material's
  // slots (Shade::materialTexels), compared the same way.
  CHECK(DeviceScene::upload(d).baseTexturesOnly);
  Scene occluded = d;
  size_t withTexture = 0;
  for (Material& m : occluded.materials)
    if (m.texture >= 0) {
      m.occlusionTexture = m.texture;
      m.occlusionStrength = 0.5f;
      ++withTexture;
    }
  REQUIRE(withTexture > 0);
  CHECK_FALSE(DeviceScene::upload(occluded).baseTexturesOnly);
  compareForms("default with occlusion textures, glTF, headlight", occluded, cam, rs, false);
  compareForms("default with occlusion textures, glTF, built-in environment", occluded, cam, env, false);
  const std::string a = assimpDir();
  if (a.empty()) {
    skipTest("assimp-testmodels is absent: ClearCoatTest (emissive and normal maps) was not compared");
  } else {
    for (const char* f : {"/ClearCoat-glTF/ClearCoatTest.gltf", "/textureTransform/TextureTransformTest.gltf"}) {
      const Scene s = loadGltf(a + f);
      compareForms(f, s, defaultCamera(s), rs, false);
      compareForms(std::string(f) + ", environment", s, defaultCamera(s), env, false);
    }
  }
  const std::string dir = sharedDir();
  if (dir.empty()) {
    skipTest("../shared is absent: the textured milk truck was not compared");
    return;
  }
  const Scene truck = loadGltf(dir + "/models/milktruck.glb");
  compareForms("milktruck, glTF", truck, defaultCamera(truck), rs, false);
  compareForms("milktruck, glTF, environment", truck, defaultCamera(truck), env, false);
}
