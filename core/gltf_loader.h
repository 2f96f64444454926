#pragma once

#include "scene.h"

#include <string>

namespace rast {

// Loads the default scene of a glTF 2.0 file (.gltf or .glb). Throws Error with a
// one-line message for unreadable or malformed input.
Scene loadGltf(const std::string& path);

}  // namespace rast
