// Built-in scenes that move: skinned, animated models with what the glTF
// spec asks a renderer to get right (joint hierarchies, scaled joints,
// weights that do not sum to 1 fixed as the spec says, cubic-spline
// tangents), so that `rast export builtin:skin-arm -o x.glb` makes the files
// the accuracy comparison with the Khronos Sample Renderer draws
// (scripts/measure/skinned_models.py, docs/animation.md).
#pragma once

#include "host/scene/scene.h"

#include <string>
#include <vector>

namespace rast {

struct MotionSceneInfo {
  const char* name;
  const char* description;
};
const std::vector<MotionSceneInfo>& motionScenes();
// Builds the named scene into out (posed at rest); false when the name is not one of them.
bool makeMotionScene(const std::string& name, Scene& out);

}  // namespace rast
