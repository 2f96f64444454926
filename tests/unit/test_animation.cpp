// Animation, skins and morph targets (host/scene/animation.h, the loader's
// host/gltf/animation_load.cpp): the sampler arithmetic against values worked
// by hand (STEP, LINEAR, slerp on the shorter arc, CUBICSPLINE with tangents
// scaled by the key interval, clamping outside the keys), tiny glTF files
// written here whose skinned and morphed vertices land where the spec puts
// them (the skinned node's own transform ignored, non-normalised weights
// scaled to 1), a renderer taking a new pose without a new upload, and every
// kind of bad animation data refused in one line.
#include <catch2/catch.hpp>

#include "host/scene/animation.h"
#include "pipeline/frame/renderer.h"
#include "tests/unit/loader_test_helpers.h"

#include <chrono>
#include <cmath>

using namespace rast;
using namespace rast::loader_test;
using Catch::Matchers::Contains;

namespace {

AnimSampler sampler(Interpolation in, std::vector<float> times, std::vector<float> values, uint32_t comps) {
  AnimSampler s;
  s.interp = in;
  s.times = std::move(times);
  s.values = std::move(values);
  s.comps = comps;
  return s;
}

double at(const AnimSampler& s, double t, bool rotation = false, int j = 0) {
  double out[4] = {0, 0, 0, 0};
  sampleAt(s, t, rotation, out);
  return out[j];
}

}  // namespace

TEST_CASE("animation samplers: step, linear and clamping", "[animation]") {
  const AnimSampler lin = sampler(Interpolation::Linear, {1, 2, 4}, {10, 20, 0}, 1);
  CHECK(at(lin, 0.0) == 10.0);  // before the first key: the first value
  CHECK(at(lin, 1.5) == Approx(15.0));
  CHECK(at(lin, 3.0) == Approx(10.0));
  CHECK(at(lin, 9.0) == 0.0);  // after the last key: the last value
  const AnimSampler step = sampler(Interpolation::Step, {1, 2, 4}, {10, 20, 0}, 1);
  CHECK(at(step, 1.99) == 10.0);
  CHECK(at(step, 2.0) == 20.0);
  CHECK(at(step, 3.99) == 20.0);
}

TEST_CASE("animation samplers: rotations slerp on the shorter arc", "[animation]") {
  const double s45 = std::sin(M_PI / 4), c45 = std::cos(M_PI / 4);
  // Identity to 90 degrees about z; halfway is 45 degrees about z.
  AnimSampler r = sampler(Interpolation::Linear, {0, 1}, {0, 0, 0, 1, 0, 0, float(s45), float(c45)}, 4);
  CHECK(at(r, 0.5, true, 2) == Approx(std::sin(M_PI / 8)).margin(1e-6));
  CHECK(at(r, 0.5, true, 3) == Approx(std::cos(M_PI / 8)).margin(1e-6));
  // The same end rotation stored negated (q and -q are one rotation): same path.
  r.values = {0, 0, 0, 1, 0, 0, -float(s45), -float(c45)};
  CHECK(std::fabs(at(r, 0.5, true, 2)) == Approx(std::sin(M_PI / 8)).margin(1e-6));
  CHECK(std::fabs(at(r, 0.5, true, 3)) == Approx(std::cos(M_PI / 8)).margin(1e-6));
  // A quarter of the way: 22.5 degrees, not the normalised lerp's angle.
  r.values = {0, 0, 0, 1, 0, 0, float(s45), float(c45)};
  CHECK(at(r, 0.25, true, 2) == Approx(std::sin(M_PI / 16)).margin(1e-6));
}

TEST_CASE("animation samplers: cubic spline tangents are scaled by the key interval", "[animation]") {
  // Keys at t=0 and t=2, values 0 and 0, out-tangent of key 0 = 1, in-tangent of key 1 = 0:
  // p(u) = (u^3 - 2u^2 + u) * dt * 1; at u = 0.5: 0.125 * 2 = 0.25.
  const AnimSampler c = sampler(Interpolation::CubicSpline, {0, 2}, {/*a0*/ 0, /*v0*/ 0, /*b0*/ 1, /*a1*/ 0, /*v1*/ 0, /*b1*/ 0}, 1);
  CHECK(at(c, 1.0) == Approx(0.25));
  CHECK(at(c, 0.0) == 0.0);
  CHECK(at(c, 5.0) == 0.0);
  // Values only (zero tangents): the smoothstep between them.
  const AnimSampler v = sampler(Interpolation::CubicSpline, {0, 1}, {0, 2, 0, 0, 6, 0}, 1);
  CHECK(at(v, 0.5) == Approx(4.0));
  CHECK(at(v, 0.25) == Approx(2.0 + 4.0 * (3 * 0.0625 - 2 * 0.015625)));
}

namespace {

// A triangle skinned to two joints (nodes 1 and 2, children of node 3); the
// mesh node 0 carries a translation that must be ignored. Joint 1 (node 2)
// is moved by animation 0 from x=0 to x=2 over [0, 1]; vertex 2 follows it
// with weights (2, 2): not normalised, scaled to (0.5, 0.5) on joints 1, 1.
Doc skinnedTriangle() {
  Doc doc;
  const int pos = doc.vec3(kTriangle);
  const std::vector<uint8_t> joints = {0, 0, 0, 0, 1, 0, 0, 0, 1, 1, 0, 0};
  const int ja = doc.accessor(doc.view(joints), kU8, 3, "VEC4");
  const int wa = doc.floats({1, 0, 0, 0, 1, 0, 0, 0, 2, 2, 0, 0}, "VEC4", 4);
  doc.prim({{"attributes", {{"POSITION", pos}, {"JOINTS_0", ja}, {"WEIGHTS_0", wa}}}});
  doc.j["nodes"] = json::array({{{"mesh", 0}, {"skin", 0}, {"translation", {100, 0, 0}}},
                                {{"name", "root-joint"}},
                                {{"name", "moving-joint"}},
                                {{"children", {1, 2}}, {"scale", {1, 1, 1}}}});
  doc.j["scenes"][0]["nodes"] = {0, 3};
  const int ibm = doc.floats({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1},
                             "MAT4", 16);
  doc.j["skins"] = json::array({{{"joints", {1, 2}}, {"inverseBindMatrices", ibm}}});
  const int in = doc.floats({0, 1}, "SCALAR", 1);
  const int out = doc.floats({0, 0, 0, 2, 0, 0}, "VEC3", 3);
  doc.j["animations"] = json::array({{{"name", "slide"},
                                      {"samplers", json::array({{{"input", in}, {"output", out}}})},
                                      {"channels", json::array({{{"sampler", 0}, {"target", {{"node", 2}, {"path", "translation"}}}}})}}});
  return doc;
}

}  // namespace

TEST_CASE("skins: joints move vertices, the skinned node's own transform is ignored", "[animation]") {
  TempDir d;
  Scene s = loadDoc(skinnedTriangle(), d, "skin");
  REQUIRE(s.rig);
  REQUIRE(s.rig->deformed.size() == 1);
  // Rest pose: the joints at the origin, the triangle as stored (not at x=100).
  CHECK(s.positions[0].x == 0.0f);
  CHECK(s.positions[1].x == 1.0f);
  CHECK(s.draws[0].model == glm::dmat4(1.0));
  poseScene(s, PoseRequest{0.5, kAllAnimations});  // joint 1 at x = 1
  CHECK(s.positions[0].x == 0.0f);                  // joint 0 only
  CHECK(s.positions[1].x == Approx(2.0f));          // 1 + joint 1's x
  CHECK(s.positions[2].x == Approx(1.0f));          // 0 + 0.5 * 1 + 0.5 * 1: weights (2, 2) scaled to 1
  CHECK(s.positions[2].y == Approx(1.0f));
  poseScene(s, PoseRequest{7.0, findAnimation(*s.rig, "slide")});  // past the end: the last key
  CHECK(s.positions[1].x == Approx(3.0f));
  poseScene(s, PoseRequest{0.5, kNoAnimation});
  CHECK(s.positions[1].x == 1.0f);
  CHECK_THROWS_WITH(findAnimation(*s.rig, "walk"), Contains("no animation named 'walk'") && Contains("0 'slide'"));
  CHECK_THROWS_WITH(findAnimation(*s.rig, "3"), Contains("animations 0..0"));
}

TEST_CASE("skins: a renderer takes a new pose into the buffers it has", "[animation]") {
  TempDir d;
  Scene s = loadDoc(skinnedTriangle(), d, "skin");
  Renderer r(s);
  poseScene(s, PoseRequest{1.0, 0});
  r.updatePose(s);
  RenderSettings rs;
  rs.width = 64;
  rs.height = 64;
  rs.wantPrimId = true;
  Camera cam;
  cam.eye = {1.5, 0.5, 4};
  cam.target = {1.5, 0.5, 0};
  r.render(cam, rs);
  // The same pose uploaded afresh: the same pixels.
  Renderer fresh(s);
  fresh.render(cam, rs);
  CHECK(r.primIdsBottomUp() == fresh.primIdsBottomUp());
  // And not the rest pose's pixels.
  Scene rest = loadDoc(skinnedTriangle(), d, "skin2");
  Renderer still(rest);
  still.render(cam, rs);
  CHECK(r.primIdsBottomUp() != still.primIdsBottomUp());
}

namespace {

// A triangle with one morph target moving vertex 0 by (0, -2, 0); the mesh's
// default weight 0.25, and an animation of the weight from 0 to 1 over [0, 2].
Doc morphedTriangle(bool animate) {
  Doc doc;
  const int pos = doc.vec3(kTriangle);
  const int dp = doc.vec3({0, -2, 0, 0, 0, 0, 0, 0, 0});
  const int dn = doc.vec3({0, 0, 0, 0, 0, 0, 0, 0, 0});
  const int nrm = doc.vec3({0, 0, 1, 0, 0, 1, 0, 0, 1});
  doc.prim({{"attributes", {{"POSITION", pos}, {"NORMAL", nrm}}},
            {"targets", json::array({{{"POSITION", dp}, {"NORMAL", dn}}})}});
  doc.j["meshes"][0]["weights"] = {0.25};
  if (animate) {
    const int in = doc.floats({0, 2}, "SCALAR", 1);
    const int out = doc.floats({0, 1}, "SCALAR", 1);
    doc.j["animations"] = json::array({{{"samplers", json::array({{{"input", in}, {"output", out}}})},
                                        {"channels", json::array({{{"sampler", 0}, {"target", {{"node", 0}, {"path", "weights"}}}}})}}});
  }
  return doc;
}

}  // namespace

TEST_CASE("morph targets: weights from the mesh and from an animation", "[animation]") {
  TempDir d;
  Scene s = loadDoc(morphedTriangle(true), d, "morph");
  CHECK(s.positions[0].y == Approx(-0.5f));  // the mesh's weight 0.25 at rest
  poseScene(s, PoseRequest{1.0, kAllAnimations});
  CHECK(s.positions[0].y == Approx(-1.0f));  // weight 0.5
  poseScene(s, PoseRequest{2.0, kAllAnimations});
  CHECK(s.positions[0].y == Approx(-2.0f));
  CHECK(s.positions[1].x == 1.0f);
  CHECK(s.normals[0].z == Approx(1.0f));
  // A node's own weights win over its mesh's.
  Doc doc = morphedTriangle(false);
  doc.j["nodes"][0]["weights"] = {1.0};
  Scene n = loadDoc(doc, d, "morph_node");
  CHECK(n.positions[0].y == Approx(-2.0f));
}

TEST_CASE("animation: a scene that does not move carries no rig", "[animation]") {
  TempDir d;
  Doc doc;
  doc.prim({{"attributes", {{"POSITION", doc.vec3(kTriangle)}}}});
  CHECK_FALSE(loadDoc(doc, d, "static").rig);
}

TEST_CASE("animation: bad animation data is refused in one line", "[animation]") {
  TempDir d;
  auto broken = [&](auto edit) {
    Doc doc = skinnedTriangle();
    edit(doc);
    return docError(doc, d, "bad");
  };
  CHECK_THAT(broken([](Doc& doc) { doc.j["animations"][0]["samplers"][0]["input"] = doc.floats({1, 1}, "SCALAR", 1); }),
             Contains("keyframe times must increase"));
  CHECK_THAT(broken([](Doc& doc) { doc.j["animations"][0]["samplers"][0]["input"] = doc.floats({0, 1, 2}, "SCALAR", 1); }),
             Contains("output has 2 elements, 3 keyframes need 3"));
  CHECK_THAT(broken([](Doc& doc) { doc.j["animations"][0]["samplers"][0]["output"] = doc.floats({0, 0, 0, NAN, 0, 0}, "VEC3", 3); }),
             Contains("NaN"));
  CHECK_THAT(broken([](Doc& doc) { doc.j["animations"][0]["channels"][0]["target"]["node"] = 9; }),
             Contains("target node 9 out of range"));
  CHECK_THAT(broken([](Doc& doc) { doc.j["animations"][0]["samplers"][0]["interpolation"] = "BOUNCY"; }),
             Contains("unknown interpolation"));
  CHECK_THAT(broken([](Doc& doc) { doc.j["skins"][0]["joints"] = {1}; }), Contains("joint 1 out of range"));
  CHECK_THAT(broken([](Doc& doc) { doc.j["skins"][0]["joints"] = {1, 12}; }), Contains("joint node index 12 out of range"));
  // Joints 1 and 2 made each other's child: a cycle outside the scene's roots.
  CHECK_THAT(broken([](Doc& doc) {
               doc.j["nodes"][3]["children"] = json::array();
               doc.j["nodes"][1]["children"] = {2};
               doc.j["nodes"][2]["children"] = {1};
             }),
             Contains("cycle"));
  CHECK_THAT(broken([](Doc& doc) { doc.j["skins"][0]["inverseBindMatrices"] = doc.floats(std::vector<float>(16, 0.0f), "MAT4", 16); }),
             Contains("1 inverse bind matrices for 2 joints"));
}

TEST_CASE("animation: 10,000 animated nodes evaluate in milliseconds", "[animation]") {
  // A chain of 10,000 nodes, each rotated and translated by its own LINEAR
  // channels of 100 keys (the budget: under 1 ms on the CPU).
  SceneRig rig;
  const int n = 10000;
  rig.nodes.resize(n);
  Animation a;
  for (int i = 0; i < n; ++i) {
    rig.nodes[size_t(i)].parent = i - 1;
    rig.order.push_back(i);
    AnimSampler r = sampler(Interpolation::Linear, {}, {}, 4), t = sampler(Interpolation::Linear, {}, {}, 3);
    for (int k = 0; k < 100; ++k) {
      r.times.push_back(float(k) * 0.1f);
      t.times.push_back(float(k) * 0.1f);
      const float h = 0.01f * float(k % 7);
      r.values.insert(r.values.end(), {0.0f, std::sin(h), 0.0f, std::cos(h)});
      t.values.insert(t.values.end(), {0.001f * float(k), 0.0f, 0.0f});
    }
    a.samplers.push_back(std::move(r));
    a.samplers.push_back(std::move(t));
    a.channels.push_back({i, AnimPath::Rotation, 2 * i});
    a.channels.push_back({i, AnimPath::Translation, 2 * i + 1});
  }
  rig.animations.push_back(std::move(a));
  evaluateNodes(rig, PoseRequest{3.05, 0}, nullptr);  // warm
  const auto t0 = std::chrono::steady_clock::now();
  constexpr int kRuns = 20;
  std::vector<glm::dmat4> w;
  for (int r = 0; r < kRuns; ++r) w = evaluateNodes(rig, PoseRequest{3.05 + 0.01 * r, 0}, nullptr);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / kRuns;
  WARN("evaluating 10,000 animated nodes: " << ms << " ms");
  CHECK(std::isfinite(w.back()[3][0]));
  CHECK(ms < 20.0);  // loose: a shared 2-core machine; the figure is in docs/animation.md
}
