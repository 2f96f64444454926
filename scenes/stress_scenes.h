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

}  // namespace rast
