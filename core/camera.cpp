#include "camera.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace rast {

glm::dmat4 Camera::view() const { return glm::lookAt(eye, target, up); }

glm::dmat4 Camera::projection(int width, int height) const {
  return glm::perspective(glm::radians(fovyDeg), double(width) / double(height), znear, zfar);
}

glm::dmat4 Camera::viewProjection(int width, int height) const {
  return viewProjOverride ? *viewProjOverride : projection(width, height) * view();
}

static std::string fmt3(const glm::dvec3& v) {
  char b[128];
  std::snprintf(b, sizeof b, "%.9g,%.9g,%.9g", v.x, v.y, v.z);
  return b;
}

std::string Camera::flags() const {
  char b[128];
  std::snprintf(b, sizeof b, " --fovy %.9g --near %.9g --far %.9g", fovyDeg, znear, zfar);
  return "--eye " + fmt3(eye) + " --target " + fmt3(target) + " --up " + fmt3(up) + b;
}

static double round9(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.9g", v);
  return std::strtod(b, nullptr);
}

Camera Camera::roundTripped() const {
  Camera c = *this;
  for (glm::dvec3* v : {&c.eye, &c.target, &c.up})
    for (int k = 0; k < 3; ++k) (*v)[k] = round9((*v)[k]);
  c.fovyDeg = round9(c.fovyDeg);
  c.znear = round9(c.znear);
  c.zfar = round9(c.zfar);
  return c;
}

Camera defaultCamera(const Scene& scene, double fovyDeg) {
  if (!scene.camera) return autoFrame(scene, fovyDeg);
  Camera c;
  c.eye = scene.camera->eye;
  c.target = scene.camera->target;
  c.up = scene.camera->up;
  c.fovyDeg = scene.camera->fovyDeg;
  c.znear = scene.camera->znear;
  c.zfar = scene.camera->zfar;
  return c;
}

Camera autoFrame(const Scene& scene, double fovyDeg) {
  glm::dvec3 lo, hi;
  scene.worldBounds(lo, hi);
  Camera c;
  c.fovyDeg = fovyDeg;
  c.target = (lo + hi) * 0.5;
  double r = glm::length(hi - lo) * 0.5;
  if (!(r > 0.0) || !std::isfinite(r)) r = 1.0;  // a single point or an empty box
  const double d = r / std::sin(glm::radians(fovyDeg) * 0.5);
  c.eye = c.target + glm::normalize(glm::dvec3(0.0, 0.25, 1.0)) * d;
  c.up = glm::dvec3(0.0, 1.0, 0.0);
  c.znear = d / 100.0;
  c.zfar = d * 100.0;
  return c.roundTripped();
}

}  // namespace rast
