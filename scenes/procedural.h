// Procedural scenes built into rast, so that it renders without any file:
// `builtin:<name>[?key=value&...]`.
#pragma once

#include "host/gltf/gltf_loader.h"
#include "host/scene/scene.h"

#include <string>
#include <vector>

namespace rast {

// The embedded default scene: a checker-textured ground plane seen in
// perspective, a vertex-coloured cube, a textured sphere and a flat-shaded
// pyramid (no normals: the loader's flat-normal path).
Scene defaultScene();

// Resolves "builtin:<name>"; throws Error for an unknown name.
Scene builtinScene(const std::string& spec);
std::vector<std::string> builtinSceneNames();

struct BuiltinSceneInfo {
  std::string name, description;  // description: a few words for `rast info`
};
const std::vector<BuiltinSceneInfo>& builtinScenes();

// Loads a scene argument: empty -> the default scene, "builtin:..." -> a
// procedural scene, anything else -> a glTF file (read as `options` allow).
Scene loadSceneArg(const std::string& arg, const LoadOptions& options = {});

}  // namespace rast
