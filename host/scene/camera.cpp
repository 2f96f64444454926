#include "host/scene/camera.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
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

// The pipeline runs in float: world positions, the camera's far plane and the
// clip coordinates (about |position| + distance, times the projection) must
// stay well inside float's range, or every vertex overflows and the image
// comes out blank. A margin of 2^10 below FLT_MAX covers the matrix products.
static void checkFramable(const glm::dvec3& lo, const glm::dvec3& hi, double d, double zfar) {
  constexpr double kLimit = double(std::numeric_limits<float>::max()) / 1024.0;
  double reach = 0.0;
  for (int k = 0; k < 3; ++k) reach = std::max({reach, std::fabs(lo[k]), std::fabs(hi[k])});
  char b[256];
  if (!std::isfinite(reach) || !std::isfinite(d) || !std::isfinite(zfar) || reach > kLimit || zfar + reach > kLimit) {
    std::snprintf(b, sizeof b,
                  "cannot frame the scene within float precision: its bounds reach %.3g and the camera would need a far "
                  "plane at %.3g (the limit is %.3g); scale the scene down or pass --eye/--target/--near/--far",
                  reach, zfar, kLimit);
    throw Error(b);
  }
}

Camera autoFrame(const Scene& scene, double fovyDeg) {
  glm::dvec3 lo, hi;
  scene.worldBounds(lo, hi);
  Camera c;
  c.fovyDeg = fovyDeg;
  c.target = (lo + hi) * 0.5;
  const bool empty = !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z);  // no vertex drawn
  if (empty) lo = hi = c.target = glm::dvec3(0.0);
  double r = glm::length(hi - lo) * 0.5;
  if (r == 0.0) r = 1.0;  // a single point or an empty box
  const double d = r / std::sin(glm::radians(fovyDeg) * 0.5);
  checkFramable(lo, hi, d, d * 100.0);
  c.eye = c.target + glm::normalize(glm::dvec3(0.0, 0.25, 1.0)) * d;
  c.up = glm::dvec3(0.0, 1.0, 0.0);
  c.znear = d / 100.0;
  c.zfar = d * 100.0;
  return c.roundTripped();
}

}  // namespace rast
