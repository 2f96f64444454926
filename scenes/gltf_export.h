// The way out of rast for a scene: a Scene (typically a built-in stress or
// procedural scene, which exists in no file) written as a binary glTF 2.0
// file, so that other renderers (glref, Blender, ...) can draw exactly what
// rast draws and their images can be compared with rast's.
#pragma once

#include "host/scene/scene.h"

#include <string>

namespace rast {

// Writes the scene as a self-contained .glb (textures embedded as PNG). Node
// order follows Scene::draws, so primitive ids are preserved. Non-finite
// positions are written as they are (and rast's own loader refuses them).
void exportGlb(const Scene& scene, const std::string& path);

}  // namespace rast
