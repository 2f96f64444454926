// Pinhole camera with OpenGL conventions, built in double precision exactly as
// ../shared/tools/glref does, so both renderers see the same matrices.
#pragma once

#include "host/scene/scene.h"

#include <glm/glm.hpp>
#include <optional>
#include <string>

namespace rast {

struct Camera {
  glm::dvec3 eye{0, 0, 3}, target{0, 0, 0}, up{0, 1, 0};
  double fovyDeg = 45.0, znear = 0.1, zfar = 1000.0;

  // When set, replaces projection * view: for callers that bring their own
  // matrices (tests put vertices directly in clip space; a frame split into
  // tiles can pass an off-centre projection).
  std::optional<glm::dmat4> viewProjOverride;

  glm::dmat4 view() const;
  glm::dmat4 projection(int width, int height) const;
  glm::dmat4 viewProjection(int width, int height) const;
  // The command-line form of this camera (%.9g values), re-usable with rast
  // and glref: "--eye x,y,z --target ... --up ... --fovy ... --near ... --far ...".
  std::string flags() const;
  // Rounds every value through its printed form, as glref does, so that a camera
  // passed on as text reproduces the same frame.
  Camera roundTripped() const;
};

// Frames the scene's world bounds: target = box centre, r = half the diagonal,
// d = r / sin(fovy/2), eye = target + normalize(0, 0.25, 1) * d, up = +Y,
// near = d/100, far = d*100.
Camera autoFrame(const Scene& scene, double fovyDeg = 45.0);

// The scene's own camera when it has one, else autoFrame().
Camera defaultCamera(const Scene& scene, double fovyDeg = 45.0);

}  // namespace rast
