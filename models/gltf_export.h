#pragma once

#include "../core/scene.h"

#include <string>

namespace rast {

// Writes the scene as a self-contained .glb (textures embedded as PNG). Node
// order follows Scene::draws, so primitive ids are preserved. Non-finite
// positions are written as they are (and rast's own loader refuses them).
void exportGlb(const Scene& scene, const std::string& path);

}  // namespace rast
