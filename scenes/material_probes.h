// Feature probes of the glTF material and light model (issue #37): small
// built-in scenes, each isolating a few properties of glTF 2.0 (metallic x
// roughness, normal maps, emission, alpha masks and sides, sampler wrap modes
// and filters, punctual light types and ranges), exported with `rast export`
// for the Khronos Sample Renderer, whose images are the goldens of
// tests/cli/cli_probe_goldens.py (docs/gltf-support.md, "Feature probes").
#pragma once

#include "host/scene/scene.h"

#include <string>
#include <vector>

namespace rast {

struct ProbeSceneInfo {
  const char* name;         // "probe-spheres", ... (`builtin:<name>`)
  const char* description;  // a few words for `rast info`
};
const std::vector<ProbeSceneInfo>& probeScenes();
// Builds the probe `name` into out; false when it is not one.
bool makeProbeScene(const std::string& name, Scene& out);

}  // namespace rast
