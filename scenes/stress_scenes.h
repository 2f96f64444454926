// The stability suite's procedural scenes (see stress_scenes.cpp).
#pragma once

#include "host/scene/scene.h"

#include <map>
#include <string>
#include <vector>

namespace rast {

struct StressSceneInfo {
  const char* name;
  const char* description;  // what it stresses and its parameters, in a few words
};
const std::vector<StressSceneInfo>& stressScenes();
std::vector<std::string> stressSceneNames();
// Builds "name[?k=v&...]" into out; false when the name is not a stress scene.
bool makeStressScene(const std::string& nameAndParams, Scene& out);

// A stress scene generated in part, so that a huge one never exists whole on
// one host (distributed runs, docs/distributed.md): a scene holding at least
// the drawn triangles [t0, t1) of the whole, numbered from global triangle
// `first`; `total` is the whole scene's triangle count (t0 = t1 = 0 asks for
// it cheaply). False for scenes that cannot be made in part (all but tiny).
bool makeStressScenePart(const std::string& nameAndParams, uint64_t t0, uint64_t t1, Scene& out, uint64_t& first,
                         uint64_t& total);

}  // namespace rast
