// The one way a scene file enters rast: glTF 2.0 (.gltf or .glb) loading
// through tinygltf, with every index and range checked so that a malformed or
// hostile file ends in one clear one-line Error, never in a crash, a hang, a
// read outside the scene's folder, a runaway allocation or a partial scene.
//
// Before tinygltf sees a file, loadGltf reads it whole and checks it itself
// (host/gltf/file_gate.cpp: a regular, non-empty file; the GLB container's
// header and chunk bounds) and checks the JSON (host/gltf/schema_check.cpp:
// nesting depth, the type of every core glTF property, extensionsRequired,
// image bufferView ranges, external buffers, the memory budget). tinygltf then
// parses the same bytes, reading external files only through the scene's
// UriResolver and decoding images through host/gltf/image_decode.cpp; the walk
// (host/gltf/model_walk.cpp, with host/gltf/accessors.cpp) checks every index,
// count and byte range again as it builds the Scene.
#pragma once

#include "host/scene/scene.h"

#include <cstdint>
#include <string>

namespace rast {

// What a load may touch and use (see docs/security.md).
struct LoadOptions {
  // External buffers and images are read only from inside the scene's folder
  // unless this is set (--allow-external-files).
  bool allowExternalFiles = false;
  // Bytes the load may hold (--max-memory); 0: defaultMemoryBudget().
  uint64_t maxMemory = 0;
};

// Loads the default scene of a glTF 2.0 file (.gltf or .glb). Throws Error with a
// one-line message for unreadable or malformed input, for an external file
// outside the scene's folder, and for a scene that would exceed the budget.
Scene loadGltf(const std::string& path, const LoadOptions& options = {});

}  // namespace rast
