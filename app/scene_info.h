// `rast info SCENE`: what a scene file holds and declares, and what of it rast
// honours, so that a user can see before rendering why a file may look
// different here than in another glTF viewer (its cameras, lights, material
// features and extensions), and pick a camera for --camera.
#pragma once

#include "host/scene/scene.h"

#include <string>

namespace rast {

// Prints the scene's summary to stdout: geometry, cameras (index, name,
// projection, position), lights, materials by feature, extensions used and
// required, each marked honoured or not.
void printSceneInfo(const Scene& scene, const std::string& source);

// Whether rast implements a glTF extension (used or required by a file).
bool extensionHonoured(const std::string& name);

}  // namespace rast
