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
  // > 0: an orthographic camera (a glTF file's), this the view volume's half
  // height (glTF ymag); its half width follows the image's aspect, as a
  // perspective camera's fovy does. 0: perspective (fovyDeg).
  double orthoHalfHeight = 0.0;

  // When set, replaces projection * view: for callers that bring their own
  // matrices (tests put vertices directly in clip space; a frame split into
  // tiles can pass an off-centre projection).
  std::optional<glm::dmat4> viewProjOverride;

  glm::dmat4 view() const;
  glm::dmat4 projection(int width, int height) const;
  glm::dmat4 viewProjection(int width, int height) const;
  // The command-line form of this camera (%.9g values), re-usable with rast
  // and glref: "--eye x,y,z --target ... --up ... --fovy ... --near ... --far ...",
  // and "--ortho H" for an orthographic camera (rast only: glref has none).
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

// A camera of a glTF file (Scene::cameras), chosen by its index N (in scene
// traversal order, from 0) or by its name: "2" or "Camera.001". The view
// looks down the node's -Z with its +Y up, through the file's yfov (or
// orthographic ymag), znear and zfar, with the image's aspect; an infinite
// zfar becomes 1.5 times the distance from the eye to the farthest corner of
// the scene's bounds. The target (which only the viewer's orbit and SSAO's
// default radius read) is the bounds' centre projected on the view axis.
// Throws Error naming the choices when the spec matches no camera.
Camera fileCamera(const Scene& scene, const std::string& spec);

}  // namespace rast
