// What the library's sources (api/) share behind the public header
// include/rast/rast.h: the scene it wraps, and the conversions from the public
// camera and settings to the pipeline's. Not installed.
#pragma once

#include "include/rast/rast.h"
#include "host/scene/camera.h"
#include "host/scene/scene.h"
#include "host/settings/render_settings.h"
#include "backends/exec_space.h"

#include <type_traits>

namespace rast {

static_assert(std::is_same<ExecutionSpace, Exec>::value,
              "include/rast/config.h names another execution space than the pipeline's (backends/exec_space.h)");

namespace lib {

struct Scene::Impl {
  ::rast::Scene scene;
};

// Checked as the CLI checks --fovy, --near/--far, --eye/--target/--up (same messages).
::rast::Camera toCamera(const Camera& c);
Camera fromCamera(const ::rast::Camera& c);
// Parsed as the CLI parses its flags (same messages); the scene's look applied
// as `rast render` applies it when settings.sceneLook.
RenderSettings toSettings(const Settings& s, const ::rast::Scene& scene);
// A scene with one mesh: its triangles in order, one draw per run of equal
// material so that primitive ids stay the triangle indices.
::rast::Scene meshScene(const std::vector<float3>& pos, const std::vector<float3>* nrm, const std::vector<float2>* uv,
                        const std::vector<float4>* col, const std::vector<uint32_t>& idx,
                        const std::vector<int32_t>* triMaterial, const std::vector<std::array<float, 4>>& materials);

}  // namespace lib
}  // namespace rast
