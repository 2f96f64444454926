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

// A triangle's barycentrics at the centre of pixel (x, y) of a width x height
// image, from its corners' NDC positions (px, py) and 1/w (iw): the
// screen-space weights b (for interpolating z/w) and the perspective-correct
// ones p (for attributes). A degenerate triangle gets (1/3, 1/3, 1/3).
// Shared by rasterize() and the renderer's barycentrics output.
struct PixelBarycentrics {
  double b[3], p[3];
};
KOKKOS_INLINE_FUNCTION PixelBarycentrics pixelBarycentrics(int64_t x, int64_t y, int64_t width, int64_t height,
                                                           const double (&px)[3], const double (&py)[3],
                                                           const double (&iw)[3]) {
  const double sx = (2.0 * double(x) + 1.0) / double(width) - 1.0;
  const double sy = (2.0 * double(y) + 1.0) / double(height) - 1.0;
  const double ax = px[1] - px[0], ay = py[1] - py[0], bx = px[2] - px[0], by = py[2] - py[0];
  const double qx = sx - px[0], qy = sy - py[0];
  const double d = ax * by - ay * bx;
  // One reciprocal for both weights (and for the three below): a double
  // division is a long instruction sequence on GPUs, and the rasterize
  // output pass is bound by its instructions (Nsight Compute on the H100).
  double b1 = 1.0 / 3.0, b2 = 1.0 / 3.0;
  if (d != 0.0) {
    const double inv = 1.0 / d;
    b1 = (qx * by - qy * bx) * inv;
    b2 = (ax * qy - ay * qx) * inv;
  }
  const double b0 = 1.0 - b1 - b2;
  const double q0 = b0 * iw[0], q1 = b1 * iw[1], q2 = b2 * iw[2], sum = q0 + q1 + q2;
  PixelBarycentrics r{{b0, b1, b2}, {b0, b1, b2}};
  if (sum != 0.0) {
    const double inv = 1.0 / sum;
    r.p[0] = q0 * inv;
    r.p[1] = q1 * inv;
    r.p[2] = q2 * inv;
  }
  return r;
}

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
