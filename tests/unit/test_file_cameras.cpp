// glTF cameras (#37): the loader keeps each node's camera with its world
// transform and checks its values; fileCamera() turns one, picked by index or
// name, into rast's Camera (perspective and orthographic), and a frame seen
// through it is the frame seen through the same view given as flags. The
// orthographic projection is checked by what only it gives: a triangle's
// area in pixels fixed by ymag, and window depth linear in distance.
#include <catch2/catch.hpp>

#include "host/scene/camera.h"
#include "pipeline/frame/renderer.h"
#include "tests/support/test_support.h"
#include "tests/unit/loader_test_helpers.h"

#include <glm/gtc/constants.hpp>

using namespace rast;
using namespace rast::loader_test;
using Catch::Matchers::Contains;

namespace {

// A triangle (mesh 0 on node 0) and two cameras: node 1 places a perspective
// camera at z = 5 looking down -z; node 2 an orthographic one named "top",
// translated to z = 5 as well.
Doc camerasDoc() {
  Doc doc;
  doc.prim({{"attributes", {{"POSITION", doc.vec3(kTriangle)}}}});
  doc.j["cameras"] = json::array(
      {{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}},
       {{"type", "orthographic"}, {"name", "top"},
        {"orthographic", {{"xmag", 2.0}, {"ymag", 1.5}, {"znear", 0.0}, {"zfar", 10.0}}}}});
  doc.j["nodes"].push_back({{"camera", 0}, {"name", "front"}, {"translation", {0.0, 0.0, 5.0}}});
  doc.j["nodes"].push_back({{"camera", 1}, {"translation", {0.0, 0.0, 5.0}}});
  doc.j["scenes"][0]["nodes"] = {0, 1, 2};
  return doc;
}

}  // namespace

TEST_CASE("glTF cameras load with their nodes' transforms", "[cameras]") {
  TempDir d;
  const Scene s = loadDoc(camerasDoc(), d, "cams");
  REQUIRE(s.cameras.size() == 2);
  CHECK(s.cameras[0].name == "front");  // no camera name: the node's
  CHECK_FALSE(s.cameras[0].orthographic);
  CHECK(s.cameras[0].yfovRad == 0.5);
  CHECK(s.cameras[0].zfar == 0.0);  // infinite
  CHECK(s.cameras[0].world[3][2] == 5.0);
  CHECK(s.cameras[1].name == "top");
  CHECK(s.cameras[1].orthographic);
  CHECK(s.cameras[1].xmag == 2.0);
  CHECK(s.cameras[1].ymag == 1.5);
  CHECK(s.cameras[1].zfar == 10.0);
}

TEST_CASE("a camera that cannot make a view is refused at load", "[cameras]") {
  TempDir d;
  auto fails = [&](const json& camera, const char* message) {
    Doc doc = camerasDoc();
    doc.j["cameras"][0] = camera;
    INFO(camera.dump());
    CHECK_THAT(docError(doc, d, "bad"), Contains(message));
  };
  fails({{"type", "perspective"}, {"perspective", {{"yfov", 0.0}, {"znear", 0.1}}}}, "yfov must be in (0, pi)");
  fails({{"type", "perspective"}, {"perspective", {{"yfov", 4.0}, {"znear", 0.1}}}}, "yfov must be in (0, pi)");
  fails({{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.0}}}}, "znear must be positive");
  fails({{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 2.0}, {"zfar", 1.0}}}},
        "zfar must be greater than znear");
  fails({{"type", "orthographic"}, {"orthographic", {{"xmag", 0.0}, {"ymag", 1.0}, {"znear", 0.0}, {"zfar", 1.0}}}},
        "xmag and ymag must be finite and not zero");
  fails({{"type", "orthographic"}, {"orthographic", {{"xmag", 1.0}, {"ymag", 1.0}, {"znear", 1.0}, {"zfar", 1.0}}}},
        "zfar must be greater than znear");
  Doc doc = camerasDoc();
  doc.j["nodes"][1]["camera"] = 7;
  CHECK_THAT(docError(doc, d, "index"), Contains("camera index 7 out of range"));
}

TEST_CASE("a file's camera is picked by index or name (--camera)", "[cameras]") {
  TempDir d;
  const Scene s = loadDoc(camerasDoc(), d, "cams");
  const Camera p = fileCamera(s, "0");
  CHECK(p.eye == glm::dvec3(0.0, 0.0, 5.0));
  CHECK(p.target.x == 0.0);
  CHECK(p.target.y == 0.0);
  CHECK(p.target.z < 5.0);  // looks down -z
  CHECK(p.up == glm::dvec3(0.0, 1.0, 0.0));
  CHECK(p.fovyDeg == Approx(glm::degrees(0.5)).epsilon(1e-8));
  CHECK(p.orthoHalfHeight == 0.0);
  // Infinite far: 1.5 x the farthest corner of the bounds (0..1, 0..1, 0) from (0, 0, 5).
  CHECK(p.zfar == Approx(1.5 * std::sqrt(1.0 + 1.0 + 25.0)).epsilon(1e-8));
  const Camera o = fileCamera(s, "top");
  CHECK(o.orthoHalfHeight == 1.5);
  CHECK(o.znear == 0.0);
  CHECK(o.zfar == 10.0);
  CHECK(fileCamera(s, "1").orthoHalfHeight == 1.5);
  CHECK_THROWS_WITH(fileCamera(s, "2"), Contains("the scene has 2 cameras (0..1)"));
  CHECK_THROWS_WITH(fileCamera(s, "side"), Contains("no camera named 'side'") && Contains("1 'top'"));
  CHECK_THROWS_WITH(fileCamera(test::trianglesScene({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 2}), "0"),
                    Contains("the scene has no cameras"));
}

TEST_CASE("a frame through a file's camera is the frame through the same view", "[cameras]") {
  TempDir d;
  const Scene s = loadDoc(camerasDoc(), d, "cams");
  RenderSettings rs;
  rs.width = 120;
  rs.height = 90;
  const Camera file = fileCamera(s, "front");
  Camera flags;
  flags.eye = {0, 0, 5};
  flags.target = file.target;
  flags.fovyDeg = file.fovyDeg;
  flags.znear = file.znear;
  flags.zfar = file.zfar;
  const test::Frame a = test::renderFrame(s, file, rs), b = test::renderFrame(s, flags, rs);
  CHECK(a.ids == b.ids);
  CHECK(a.depth == b.depth);
  size_t covered = 0;
  for (uint32_t id : a.ids) covered += id != 0;
  CHECK(covered > 0);
}

TEST_CASE("an orthographic camera keeps sizes and makes depth linear", "[cameras]") {
  TempDir d;
  const Scene s = loadDoc(camerasDoc(), d, "cams");
  RenderSettings rs;
  rs.width = 300;
  rs.height = 300;
  // ymag 1.5 over 300 rows (and the same across, square image): 100 pixels a unit,
  // so the unit right triangle covers 100 x 100 / 2 pixels, 4,950 to 5,050 by
  // which pixels on its long edge the top-left rule keeps.
  const test::Frame f = test::renderFrame(s, fileCamera(s, "top"), rs);
  size_t covered = 0;
  float depth = -1.0f;
  for (size_t i = 0; i < f.ids.size(); ++i)
    if (f.ids[i]) {
      ++covered;
      depth = f.depth[i];
    }
  CHECK(covered >= 4900);
  CHECK(covered <= 5100);
  // The triangle lies 5 units in front of the eye, halfway from near 0 to far 10:
  // window depth 0.5 under an orthographic projection (a perspective one would not be linear).
  CHECK(depth == Approx(0.5).margin(1e-6));
}
