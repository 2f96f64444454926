// The stability suite's procedural scenes (see stress_scenes.cpp).
#pragma once

#include "../core/scene.h"

#include <map>
#include <string>
#include <vector>

namespace rast {

const std::vector<std::string>& stressSceneNames();
// Builds "name[?k=v&...]" into out; false when the name is not a stress scene.
bool makeStressScene(const std::string& nameAndParams, Scene& out);

}  // namespace rast
