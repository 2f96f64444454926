// Golden images: the default scene and a few Debian / shared models rendered at
// their auto-framed camera, compared with images stored in tests/golden/.
//
// Tolerance (explicit): at most 0.1% of the pixels may differ by more than
// 2/255 in any channel, and the mean absolute difference over all channels must
// stay under 0.25/255. That admits the 1/255 colour spread allowed between
// backends (sqrt/pow rounding on GPUs) and nothing visible.
// Set RAST_UPDATE_GOLDEN=1 to rewrite the stored images after a reviewed change.
#include <catch2/catch.hpp>

#include "host/gltf/gltf_loader.h"
#include "host/image/image_io.h"
#include "scenes/procedural.h"
#include "tests/support/test_support.h"

#include <cstdlib>

using namespace rast;
using namespace rast::test;

namespace {

void checkGolden(const std::string& name, const Scene& scene, int W, int H, ShadingMode mode = ShadingMode::Lambert) {
  RenderSettings rs;
  rs.width = W;
  rs.height = H;
  rs.shading = mode;
  const Frame f = renderFrame(scene, autoFrame(scene), rs);
  const std::string path = std::string(RAST_SOURCE_DIR) + "/tests/golden/" + name + ".png";
  if (std::getenv("RAST_UPDATE_GOLDEN")) {
    writePng(path, W, H, f.color);
    WARN("rewrote " << path);
    return;
  }
  INFO("golden " << path << " (RAST_UPDATE_GOLDEN=1 rewrites it)");
  REQUIRE(fileExists(path));
  int gw = 0, gh = 0;
  const std::vector<uint32_t> g = readPng(path, gw, gh);
  REQUIRE(gw == W);
  REQUIRE(gh == H);
  size_t off = 0;
  double sum = 0.0;
  for (size_t i = 0; i < g.size(); ++i) {
    int worst = 0;
    for (int c = 0; c < 3; ++c) {
      const int d = std::abs(int((g[i] >> (8 * c)) & 0xff) - int((f.color[i] >> (8 * c)) & 0xff));
      worst = std::max(worst, d);
      sum += d;
    }
    off += worst > 2;
  }
  const double offFraction = double(off) / g.size(), mean = sum / (3.0 * g.size());
  INFO("pixels off by > 2/255: " << off << " (" << offFraction * 100 << "%), mean abs diff " << mean);
  CHECK(offFraction <= 0.001);
  CHECK(mean < 0.25);
}

}  // namespace

TEST_CASE("golden: embedded default scene", "[golden]") {
  checkGolden("default_320x180", defaultScene(), 320, 180);
  checkGolden("default_normals_320x180", defaultScene(), 320, 180, ShadingMode::Normals);
}

TEST_CASE("golden: Debian test models", "[golden]") {
  const std::string d = assimpDir();
  if (d.empty()) {
    skipTest("assimp-testmodels not installed");
    return;
  }
  checkGolden("boxtextured_320x240", loadGltf(d + "/BoxTextured-glTF-Binary/BoxTextured.glb"), 320, 240);
  checkGolden("engine_320x240", loadGltf(d + "/2CylinderEngine-glTF-Binary/2CylinderEngine.glb"), 320, 240);
}

TEST_CASE("golden: shared models", "[golden][shared]") {
  const std::string d = sharedDir();
  if (d.empty()) {
    skipTest("../shared is absent (a user's clone has none)");
    return;
  }
  checkGolden("duck_320x240", loadGltf(d + "/models/duck.glb"), 320, 240);
  checkGolden("cow_320x240", loadGltf(d + "/models/cow.glb"), 320, 240);
  checkGolden("checkerboard_320x240", loadGltf(d + "/models/checkerboard.glb"), 320, 240);
}
