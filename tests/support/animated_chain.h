// The animation benchmark's rig, shared by the unit test that bounds its cost
// (tests/unit/test_animation.cpp) and the timing tool rast-anim-bench
// (tests/tools/anim_bench_main.cpp), so both measure the same thing: a chain
// of n nodes, each rotated and translated by its own LINEAR channels of 100
// keys 0.1 s apart (the "animations of 10,000 nodes"). And the
// straightforward evaluation (every channel in file order, then every node
// down the hierarchy) that evaluateNodes must match bit for bit, the baseline
// of its timings.
#pragma once

#include "host/scene/animation.h"

#include <glm/gtc/quaternion.hpp>

#include <cmath>
#include <vector>

namespace rast::test_support {

inline SceneRig animatedChain(int n) {
  SceneRig rig;
  rig.nodes.resize(size_t(n));
  Animation a;
  for (int i = 0; i < n; ++i) {
    rig.nodes[size_t(i)].parent = i - 1;
    rig.order.push_back(i);
    AnimSampler r, t;
    r.comps = 4;
    t.comps = 3;
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
  a.start = 0.0;
  a.end = 9.9;
  rig.animations.push_back(std::move(a));
  planAnimations(rig);
  return rig;
}

inline std::vector<glm::dmat4> referenceEvaluate(const SceneRig& rig, const PoseRequest& r, std::vector<std::vector<double>>* weights) {
  const size_t n = rig.nodes.size();
  std::vector<glm::dvec3> tr(n), sc(n);
  std::vector<glm::dquat> rot(n);
  std::vector<std::vector<double>> w(n);
  for (size_t i = 0; i < n; ++i) {
    tr[i] = rig.nodes[i].translation;
    rot[i] = rig.nodes[i].rotation;
    sc[i] = rig.nodes[i].scale;
    w[i] = rig.nodes[i].weights;
  }
  for (size_t a = 0; a < rig.animations.size(); ++a) {
    if (r.animation != kAllAnimations && size_t(r.animation) != a) continue;
    const Animation& anim = rig.animations[a];
    for (const AnimChannel& ch : anim.channels) {
      const AnimSampler& s = anim.samplers[size_t(ch.sampler)];
      double v[4] = {0, 0, 0, 0};
      const size_t i = size_t(ch.node);
      switch (ch.path) {
        case AnimPath::Translation: sampleAt(s, r.time, false, v); tr[i] = {v[0], v[1], v[2]}; break;
        case AnimPath::Scale: sampleAt(s, r.time, false, v); sc[i] = {v[0], v[1], v[2]}; break;
        case AnimPath::Rotation: sampleAt(s, r.time, true, v); rot[i] = glm::dquat(v[3], v[0], v[1], v[2]); break;
        case AnimPath::Weights: w[i].assign(s.comps, 0.0); sampleAt(s, r.time, false, w[i].data()); break;
      }
    }
  }
  std::vector<glm::dmat4> world(n, glm::dmat4(1.0));
  for (int32_t i : rig.order) {
    const RigNode& nd = rig.nodes[size_t(i)];
    glm::dmat4 local = nd.matrix;
    if (!nd.hasMatrix) {
      const glm::dmat3 m = glm::mat3_cast(glm::normalize(rot[i]));
      local = glm::dmat4(glm::dvec4(m[0] * sc[i].x, 0.0), glm::dvec4(m[1] * sc[i].y, 0.0), glm::dvec4(m[2] * sc[i].z, 0.0),
                         glm::dvec4(tr[i], 1.0));
    }
    world[i] = nd.parent >= 0 ? world[size_t(nd.parent)] * local : local;
  }
  if (weights) *weights = std::move(w);
  return world;
}

}  // namespace rast::test_support
