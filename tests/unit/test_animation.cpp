// Animation, skins and morph targets (host/scene/animation.h, the loader's
// host/gltf/animation_load.cpp): the sampler arithmetic against values worked
// by hand (STEP, LINEAR, slerp on the shorter arc, CUBICSPLINE with tangents
// scaled by the key interval, clamping outside the keys), tiny glTF files
// written here whose skinned and morphed vertices land where the spec puts
// them (the skinned node's own transform ignored, non-normalised weights
// scaled to 1), a renderer taking a new pose without a new upload, every
// kind of bad animation data refused in one line, and the planned, threaded
// evaluation giving the bits of the straightforward one (on one thread and
// two), and the helper threads that share its work (host_workers.h).
#include <catch2/catch.hpp>

#include "host/image/image_io.h"
#include "host/scene/animation.h"
#include "host/scene/host_workers.h"
#include "pipeline/frame/renderer.h"
#include "tests/support/animated_chain.h"
#include "tests/unit/loader_test_helpers.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <thread>
#ifdef _OPENMP
#include <omp.h>
#endif

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

namespace {

// A normal-mapped triangle (tangent-space normal +x, so the shaded normal
// follows the tangent) whose one morph target turns its tangents from +x
// towards +y: TANGENT deltas (0, 2, 0); the weight animated from 0 to 1 over
// [0, 1]; handedness -1.
Doc morphedTangents(const TempDir& d) {
  writePng(d.file("tilt.png"), 1, 1, {0xff8080ffu});  // (255, 128, 128): x = 1
  Doc doc;
  const int pos = doc.vec3(kTriangle);
  const int nrm = doc.vec3({0, 0, 1, 0, 0, 1, 0, 0, 1});
  const int uv = doc.floats({0, 0, 1, 0, 0, 1}, "VEC2", 2);
  const int tan = doc.floats({1, 0, 0, -1, 1, 0, 0, -1, 1, 0, 0, -1}, "VEC4", 4);
  const int dp = doc.vec3({0, 0, 0, 0, 0, 0, 0, 0, 0});
  const int dt = doc.vec3({0, 2, 0, 0, 2, 0, 0, 2, 0});
  doc.prim({{"attributes", {{"POSITION", pos}, {"NORMAL", nrm}, {"TEXCOORD_0", uv}, {"TANGENT", tan}}},
            {"material", 0},
            {"targets", json::array({{{"POSITION", dp}, {"TANGENT", dt}}})}});
  doc.j["meshes"][0]["weights"] = {0.25};
  doc.j["materials"] = json::array({{{"normalTexture", {{"index", 0}}}}});
  doc.j["textures"] = json::array({{{"source", 0}}});
  doc.j["images"] = json::array({{{"uri", "tilt.png"}}});
  const int in = doc.floats({0, 1}, "SCALAR", 1);
  const int out = doc.floats({0, 1}, "SCALAR", 1);
  doc.j["animations"] = json::array({{{"samplers", json::array({{{"input", in}, {"output", out}}})},
                                      {"channels", json::array({{{"sampler", 0}, {"target", {{"node", 0}, {"path", "weights"}}}}})}}});
  return doc;
}

}  // namespace

TEST_CASE("morph targets: TANGENT deltas move a normal-mapped primitive's tangents, w kept", "[animation]") {
  TempDir d;
  Scene s = loadDoc(morphedTangents(d), d, "morph_tangent");
  REQUIRE(s.tangents.size() == s.positions.size());
  CHECK(s.tangents[0].x == 1.0f);
  CHECK(s.tangents[0].y == Approx(0.5f));  // the mesh's weight 0.25 at rest
  CHECK(s.tangents[0].w == -1.0f);
  poseScene(s, PoseRequest{1.0, kAllAnimations});
  CHECK(s.tangents[2].y == Approx(2.0f));
  CHECK(s.tangents[2].w == -1.0f);
  // A renderer takes the morphed tangents with the new pose: the normal map
  // (its +x is the tangent) shades as a fresh upload of that pose does, and
  // unlike the rest pose.
  Scene rest = loadDoc(morphedTangents(d), d, "morph_tangent_rest");
  poseScene(rest, PoseRequest{0.0, kAllAnimations});
  Renderer r(rest);
  RenderSettings rs;
  rs.width = 48;
  rs.height = 48;
  rs.shading = ShadingMode::Pbr;
  rs.environment = "none";
  Camera cam;
  cam.eye = {0.3, 0.3, 2};
  cam.target = {0.3, 0.3, 0};
  r.render(cam, rs);
  const std::vector<uint32_t> atRest = r.colorTopDown();
  r.updatePose(s);
  r.render(cam, rs);
  Renderer fresh(s);
  fresh.render(cam, rs);
  CHECK(r.colorTopDown() == fresh.colorTopDown());
  CHECK(r.colorTopDown() != atRest);
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

namespace {

bool sameBits(const std::vector<glm::dmat4>& a, const std::vector<glm::dmat4>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(glm::dmat4)) == 0;
}

// Six nodes: 0 -> 1 -> 2 (a matrix node), 3 -> 4, and 5 alone. Two animations
// drive node 1's translation (the second wins when both play); the first also
// node 0's rotation (STEP), node 3's scale (CUBICSPLINE) and its weights;
// nodes 2 and 4 move with their parents, 5 stays at rest.
SceneRig smallRig() {
  SceneRig rig;
  rig.nodes.resize(6);
  rig.nodes[1].parent = 0;
  rig.nodes[2].parent = 1;
  rig.nodes[2].hasMatrix = true;
  rig.nodes[2].matrix = glm::translate(glm::dmat4(1.0), glm::dvec3(0.5, -1.0, 2.0));
  rig.nodes[4].parent = 3;
  rig.nodes[4].translation = {0.0, 3.0, 0.0};
  rig.nodes[5].rotation = glm::normalize(glm::dquat(0.9, 0.1, 0.3, 0.0));
  rig.nodes[3].weights = {0.25, 0.5};
  rig.order = {0, 3, 5, 1, 4, 2};
  Animation a, b;
  a.samplers.push_back(sampler(Interpolation::Linear, {0, 1, 3}, {0, 0, 0, 1, 2, 3, -1, 0, 4}, 3));
  a.samplers.push_back(sampler(Interpolation::Step, {0, 0.5f, 2}, {0, 0, 0, 1, 0, 0.6f, 0, 0.8f, 0.6f, 0, 0, 0.8f}, 4));
  a.samplers.push_back(sampler(Interpolation::CubicSpline, {0, 2}, {0, 0, 0, 1, 1, 1, 1, 0, 0, 0, 0, 0, 2, 2, 2, 0, 0, 0}, 3));
  a.samplers.push_back(sampler(Interpolation::Linear, {0, 2}, {0, 1, 1, 0}, 2));
  a.channels = {{1, AnimPath::Translation, 0}, {0, AnimPath::Rotation, 1}, {3, AnimPath::Scale, 2}, {3, AnimPath::Weights, 3}};
  b.samplers.push_back(sampler(Interpolation::Linear, {0.5f, 1.5f}, {5, 0, 0, 6, 1, 0}, 3));
  b.channels = {{1, AnimPath::Translation, 0}};
  rig.animations = {a, b};
  return rig;
}

}  // namespace

TEST_CASE("animation: evaluation gives the bits of playing every channel in order", "[animation]") {
  SceneRig rig = smallRig();
  planAnimations(rig);
  for (int anim : {kAllAnimations, 0, 1, kNoAnimation})
    for (double t : {-1.0, 0.0, 0.25, 0.5, 0.75, 1.0, 1.2, 2.0, 2.5, 9.0}) {
      INFO("animation " << anim << " at " << t);
      std::vector<std::vector<double>> w, wRef;
      const std::vector<glm::dmat4> world = evaluateNodes(rig, PoseRequest{t, anim}, &w);
      CHECK(sameBits(world, test_support::referenceEvaluate(rig, PoseRequest{t, anim}, &wRef)));
      CHECK(w == wRef);
    }
  // Both animations drive node 1's translation: the later one wins when all play.
  const std::vector<glm::dmat4> all = evaluateNodes(rig, PoseRequest{1.0, kAllAnimations}, nullptr);
  CHECK((glm::inverse(all[0]) * all[1])[3][0] == Approx(5.5));
  const std::vector<glm::dmat4> first = evaluateNodes(rig, PoseRequest{1.0, 0}, nullptr);
  CHECK((glm::inverse(first[0]) * first[1])[3][0] == Approx(1.0));
  // A rig without a plan (or a copy, whose plan views another rig's keys) is planned on the fly.
  const SceneRig copy = rig;
  CHECK(sameBits(evaluateNodes(copy, PoseRequest{0.75, kAllAnimations}, nullptr), evaluateNodes(rig, PoseRequest{0.75, kAllAnimations}, nullptr)));
}

TEST_CASE("animation: 10,000 animated nodes, the same bits on any number of threads", "[animation]") {
  const SceneRig rig = test_support::animatedChain(10000);
  std::vector<glm::dmat4> one, many;
#ifdef _OPENMP
  const int threads = omp_get_max_threads();
  for (double t : {-1.0, 0.05, 0.63, 3.05, 9.9, 20.0}) {  // 0.6 to 0.7: a key interval slerped through acos
    INFO("t = " << t);
    omp_set_num_threads(1);
    evaluateNodes(rig, PoseRequest{t, 0}, one, nullptr);
    omp_set_num_threads(std::max(2, threads));
    evaluateNodes(rig, PoseRequest{t, 0}, many, nullptr);
    CHECK(sameBits(one, many));
    CHECK(sameBits(one, test_support::referenceEvaluate(rig, PoseRequest{t, 0}, nullptr)));
  }
  omp_set_num_threads(1);
  evaluateNodes(rig, PoseRequest{3.05, 0}, one, nullptr);
  omp_set_num_threads(threads);
#else
  evaluateNodes(rig, PoseRequest{3.05, 0}, one, nullptr);
#endif
  CHECK(sameBits(one, test_support::referenceEvaluate(rig, PoseRequest{3.05, 0}, nullptr)));
  evaluateNodes(rig, PoseRequest{3.07, 0}, many, nullptr);
  CHECK_FALSE(sameBits(one, many));  // a different time moves the chain
}

TEST_CASE("animation: 10,000 animated nodes evaluate in milliseconds", "[animation]") {
  // A chain of 10,000 nodes, each rotated and translated by its own LINEAR
  // channels of 100 keys (the budget: under 1 ms on the CPU; the
  // figures, from rast-anim-bench, in docs/animation.md).
  const SceneRig rig = test_support::animatedChain(10000);
  std::vector<glm::dmat4> w;
#ifdef _OPENMP
  // One thread: on a shared machine a second one may wait a scheduler tick
  // (4 ms) for its core, which would decide the figure.
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
#endif
  evaluateNodes(rig, PoseRequest{3.05, 0}, w, nullptr);  // warm
  constexpr int kRuns = 41;
  std::vector<double> ms;
  for (int r = 0; r < kRuns; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    evaluateNodes(rig, PoseRequest{3.05 + 0.01 * r, 0}, w, nullptr);
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
#ifdef _OPENMP
  omp_set_num_threads(threads);
#endif
  std::sort(ms.begin(), ms.end());
  WARN("evaluating 10,000 animated nodes on one thread: median " << ms[kRuns / 2] << " ms");
  CHECK(std::isfinite(w.back()[3][0]));
  CHECK(ms[kRuns / 2] < 20.0);  // loose: a shared 2-core machine; the figures are in docs/animation.md
}

TEST_CASE("animation: shared chunks run once each, on helpers when they come", "[animation]") {
  // host_workers.h: every chunk exactly once whatever the thread count; with
  // two threads a helper takes chunks (the caller's first chunk waits until
  // another thread has run one), and the caller never needs one.
  struct Ctx {
    std::vector<std::atomic<int>> runs = std::vector<std::atomic<int>>(64);
    std::atomic<int> others{0};
    std::thread::id caller = std::this_thread::get_id();
    bool waitForHelper = false;
    bool helperCame = false;
  };
  auto run = [](void* p, uint32_t c) {
    Ctx& x = *static_cast<Ctx*>(p);
    x.runs[c].fetch_add(1);
    if (std::this_thread::get_id() != x.caller) x.others.fetch_add(1);
    if (c == 0 && x.waitForHelper) {
      const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(20);
      while (x.others.load() == 0 && std::chrono::steady_clock::now() < until) std::this_thread::yield();
      x.helperCame = x.others.load() > 0;
    }
  };
  for (int threads : {1, 2, 3}) {
    Ctx x;
    shareChunks(64, threads, run, &x);
    for (auto& r : x.runs) CHECK(r.load() == 1);
    if (threads == 1) CHECK(x.others.load() == 0);
  }
  Ctx x;
  x.waitForHelper = true;
  shareChunks(64, 2, run, &x);
  CHECK(x.helperCame);
  for (auto& r : x.runs) CHECK(r.load() == 1);
}
