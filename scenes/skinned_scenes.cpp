// The built-in skinned models (skinned_scenes.h). Both are a tube of radius
// 0.2 along x in [0, 3] (8 sides, a ring every 0.25) skinned to a chain of
// three joints: the root (translation (-1.5, -0.5, 0), uniform scale 1.25), a
// joint at x = 1 and one at x = 2, with inverse bind matrices relative to the
// root, so the rest pose is the root's transform of the tube. The mesh's own
// node has a translation the spec says to ignore (glTF 2.0, 3.7.3.3). Weights
// come from a falloff around each joint summing to 2, scaled to 1 as the spec
// asks (the loader's arithmetic), and written so. The same model, in Python,
// is scripts/measure/skinned_models.py's description, from which
// tests/cli/cli_skinned_models.py skins it by hand.
#include "scenes/skinned_scenes.h"

#include "host/scene/animation.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <memory>

namespace rast {
namespace {

constexpr double kRadius = 0.2;
constexpr int kSides = 8, kRings = 13;

// A vertex's weights on the three joints at x: the falloff, summing to 2.
void rawWeights(float x, float w[3]) {
  w[0] = w[1] = w[2] = 0.0f;
  if (x <= 0.5f) w[0] = 1.0f;
  else if (x < 1.5f) w[0] = 1.5f - x, w[1] = x - 0.5f;
  else if (x < 2.5f) w[1] = 2.5f - x, w[2] = x - 1.5f;
  else w[2] = 1.0f;
  for (int k = 0; k < 3; ++k) w[k] *= 2.0f;
}

std::vector<float> quatZ(double deg) {  // x, y, z, w (glTF order)
  const double h = deg * (3.14159265358979323846 / 180.0) / 2.0;  // as Python's math.radians(deg) / 2
  return {0.0f, 0.0f, float(std::sin(h)), float(std::cos(h))};
}

AnimSampler samplerOf(Interpolation in, std::vector<float> times, std::vector<float> values, uint32_t comps) {
  AnimSampler s;
  s.interp = in;
  s.times = std::move(times);
  s.values = std::move(values);
  s.comps = comps;
  return s;
}

std::vector<float> cat(std::initializer_list<std::vector<float>> parts) {
  std::vector<float> v;
  for (const std::vector<float>& p : parts) v.insert(v.end(), p.begin(), p.end());
  return v;
}

Animation armAnimation() {
  // The middle joint rotates about z (0, 90, 30, -45 degrees at t = 0..3); the
  // tip joint scales non-uniformly ((1.4, 0.7, 1) at t = 2, 1 at 0, 1 and 3).
  Animation a;
  a.name = "arm";
  a.samplers.push_back(samplerOf(Interpolation::Linear, {0, 1, 2, 3}, cat({quatZ(0), quatZ(90), quatZ(30), quatZ(-45)}), 4));
  a.samplers.push_back(samplerOf(Interpolation::Linear, {0, 1, 2, 3}, {1, 1, 1, 1, 1, 1, 1.4f, 0.7f, 1, 1, 1, 1}, 3));
  a.channels = {{2, AnimPath::Rotation, 0}, {3, AnimPath::Scale, 1}};
  a.end = 3.0;
  return a;
}

Animation tailAnimation() {
  // CUBICSPLINE rotation of the middle joint and translation of the tip, with
  // non-zero tangents, keys at t = 0, 0.8 and 2 (intervals of different
  // lengths, so that tangents scaled by the wrong interval show).
  Animation a;
  a.name = "tail";
  a.samplers.push_back(samplerOf(Interpolation::CubicSpline, {0, 0.8f, 2},
                                 cat({{0, 0, 0.6f, 0}, quatZ(0), {0, 0, 0.6f, 0}, {0, 0, -0.4f, 0}, quatZ(70), {0, 0, -0.4f, 0},
                                      {0, 0, 0.3f, 0}, quatZ(-20), {0, 0, 0.3f, 0}}),
                                 4));
  a.samplers.push_back(samplerOf(Interpolation::CubicSpline, {0, 0.8f, 2},
                                 {0, 1.5f, 0, 1, 0, 0, 0, 1.5f, 0, -1, 0, 0, 1.2f, 0.3f, 0, -1, 0, 0, 0.5f, -2, 0, 1, 0, 0, 0.5f, -2, 0}, 3));
  a.channels = {{2, AnimPath::Rotation, 0}, {3, AnimPath::Translation, 1}};
  a.end = 2.0;
  return a;
}

void skinnedTube(Scene& s, Animation anim) {
  auto rig = std::make_shared<SceneRig>();
  // Nodes: 0 the tube (its translation ignored), 1 root, 2 middle, 3 tip.
  rig->nodes.resize(4);
  rig->nodes[0].translation = {5.0, 0.0, 0.0};
  rig->nodes[1].translation = {-1.5, -0.5, 0.0};
  rig->nodes[1].scale = glm::dvec3(1.25);
  rig->nodes[2].parent = 1;
  rig->nodes[2].translation = {1.0, 0.0, 0.0};
  rig->nodes[3].parent = 2;
  rig->nodes[3].translation = {1.0, 0.0, 0.0};
  rig->order = {0, 1, 2, 3};
  Skin sk;
  sk.joints = {1, 2, 3};
  for (int k = 0; k < 3; ++k) sk.inverseBind.push_back(glm::translate(glm::dmat4(1.0), glm::dvec3(-double(k), 0.0, 0.0)));
  rig->skins.push_back(sk);
  rig->animations.push_back(std::move(anim));

  Material mat;
  mat.baseColorFactor = {0.8f, 0.8f, 0.8f, 1.0f};
  mat.metallic = 0.0f;
  s.materials.push_back(mat);
  MeshPrim p;
  p.material = 0;
  DeformedDraw dd;
  dd.skin = 0;
  dd.sets = 1;
  for (int r = 0; r < kRings; ++r)
    for (int k = 0; k < kSides; ++k) {
      const float x = 0.25f * float(r);
      const double a = 2.0 * 3.14159265358979323846 * k / kSides;
      s.positions.push_back({x, float(kRadius * std::cos(a)), float(kRadius * std::sin(a))});
      s.normals.push_back({0.0f, float(std::cos(a)), float(std::sin(a))});
      float w[3];
      rawWeights(x, w);
      double sum = 0.0;  // scaled to sum 1 as the loader scales a file's (glTF 2.0, 3.7.3.3)
      for (float wk : w) sum += wk;
      dd.joints.insert(dd.joints.end(), {0, 1, 2, 0});
      dd.weights.insert(dd.weights.end(), {float(w[0] / sum), float(w[1] / sum), float(w[2] / sum), 0.0f});
    }
  for (int r = 0; r + 1 < kRings; ++r)
    for (int k = 0; k < kSides; ++k) {
      const uint32_t a = uint32_t(r * kSides + k), b = uint32_t(r * kSides + (k + 1) % kSides), c = a + kSides, d = b + kSides;
      s.indices.insert(s.indices.end(), {a, b, d, a, d, c});
    }
  p.vertexCount = uint32_t(s.positions.size());
  p.triCount = uint32_t(s.indices.size() / 3);
  s.prims.push_back(p);
  s.draws.push_back(Draw{0, glm::dmat4(1.0)});
  rig->drawNode = {0};
  dd.draw = 0;
  dd.basePositions = s.positions;
  dd.baseNormals = s.normals;
  rig->deformed.push_back(std::move(dd));
  planAnimations(*rig);
  s.rig = rig;
  poseScene(s, PoseRequest{0.0, kNoAnimation});
}

}  // namespace

const std::vector<MotionSceneInfo>& motionScenes() {
  static const std::vector<MotionSceneInfo> all = {
      {"skin-arm", "a tube skinned to a chain of 3 joints under a scaled root; rotation and non-uniform scale, LINEAR"},
      {"skin-tail", "the same tube and joints; rotation and translation CUBICSPLINE with tangents, unequal key intervals"},
  };
  return all;
}

bool makeMotionScene(const std::string& name, Scene& out) {
  Scene s;
  if (name == "skin-arm") skinnedTube(s, armAnimation());
  else if (name == "skin-tail") skinnedTube(s, tailAnimation());
  else return false;
  s.name = "builtin:" + name;
  s.validate();
  out = std::move(s);
  return true;
}

}  // namespace rast
