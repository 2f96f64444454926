// EXT_mesh_gpu_instancing (host/gltf/instancing.cpp): a node's instances
// become draws placed by node * T R S of each instance, the mesh stored once;
// an animated node moves all its instances; counts that disagree, a zero
// rotation or an extension without attributes are refused in one line.
#include <catch2/catch.hpp>

#include "host/scene/animation.h"
#include "tests/unit/loader_test_helpers.h"

using namespace rast;
using namespace rast::loader_test;
using Catch::Matchers::Contains;

namespace {

Doc instanced(bool animate) {
  Doc doc;
  doc.prim({{"attributes", {{"POSITION", doc.vec3(kTriangle)}}}});
  const int t = doc.vec3({0, 0, 0, 2, 0, 0, 4, 0, 0});
  const int r = doc.floats({0, 0, 0, 1, 0, 0, 0.70710678f, 0.70710678f, 0, 0, 0, 1}, "VEC4", 4);
  doc.j["nodes"][0]["translation"] = {0, 10, 0};
  doc.j["nodes"][0]["extensions"] = {{"EXT_mesh_gpu_instancing", {{"attributes", {{"TRANSLATION", t}, {"ROTATION", r}}}}}};
  doc.j["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
  doc.j["extensionsRequired"] = {"EXT_mesh_gpu_instancing"};
  if (animate) {
    const int in = doc.floats({0, 1}, "SCALAR", 1);
    const int out = doc.floats({0, 10, 0, 0, 20, 0}, "VEC3", 3);
    doc.j["animations"] = json::array({{{"samplers", json::array({{{"input", in}, {"output", out}}})},
                                        {"channels", json::array({{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}})}}});
  }
  return doc;
}

glm::dvec3 placed(const Scene& s, size_t draw, glm::dvec3 p) { return glm::dvec3(s.draws[draw].model * glm::dvec4(p, 1.0)); }

}  // namespace

TEST_CASE("instancing: each instance is a draw of the one stored mesh", "[instancing]") {
  TempDir d;
  Scene s = loadDoc(instanced(false), d, "inst");
  REQUIRE(s.draws.size() == 3);
  CHECK(s.prims.size() == 1);
  CHECK(s.positions.size() == 3);
  CHECK(placed(s, 0, {1, 0, 0}) == glm::dvec3(1, 10, 0));
  CHECK(placed(s, 2, {1, 0, 0}) == glm::dvec3(5, 10, 0));
  // Instance 1 is turned 90 degrees about z: (1, 0, 0) -> (0, 1, 0), then moved by (2, 0, 0) and the node.
  const glm::dvec3 p = placed(s, 1, {1, 0, 0});
  CHECK(p.x == Approx(2.0));
  CHECK(p.y == Approx(11.0));
}

TEST_CASE("instancing: an animated node carries its instances", "[instancing]") {
  TempDir d;
  Scene s = loadDoc(instanced(true), d, "inst_anim");
  poseScene(s, PoseRequest{0.5, kAllAnimations});
  CHECK(placed(s, 2, {1, 0, 0}).y == Approx(15.0));
  CHECK(placed(s, 2, {1, 0, 0}).x == Approx(5.0));
}

TEST_CASE("instancing: malformed instance data is refused in one line", "[instancing]") {
  TempDir d;
  Doc doc = instanced(false);
  doc.j["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["SCALE"] = doc.vec3({1, 1, 1, 1, 1, 1});
  CHECK_THAT(docError(doc, d, "count"), Contains("must have the same count"));
  doc = instanced(false);
  doc.j["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["ROTATION"] =
      doc.floats({0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 1}, "VEC4", 4);
  CHECK_THAT(docError(doc, d, "zero"), Contains("ROTATION 1 is zero"));
  doc = instanced(false);
  doc.j["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"] = json::object();
  CHECK_THAT(docError(doc, d, "empty"), Contains("needs an attributes object"));
}
