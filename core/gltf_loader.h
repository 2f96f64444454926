#pragma once

#include "scene.h"

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
