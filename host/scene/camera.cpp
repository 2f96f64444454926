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
  const double aspect = double(width) / double(height);
  if (orthoHalfHeight > 0.0)
    return glm::ortho(-orthoHalfHeight * aspect, orthoHalfHeight * aspect, -orthoHalfHeight, orthoHalfHeight, znear, zfar);
  return glm::perspective(glm::radians(fovyDeg), aspect, znear, zfar);
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
  std::string f = "--eye " + fmt3(eye) + " --target " + fmt3(target) + " --up " + fmt3(up) + b;
  if (orthoHalfHeight > 0.0) {
    std::snprintf(b, sizeof b, " --ortho %.9g", orthoHalfHeight);
    f += b;
  }
  return f;
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
  c.orthoHalfHeight = round9(c.orthoHalfHeight);
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

Camera fileCamera(const Scene& scene, const std::string& spec) {
  const size_t n = scene.cameras.size();
  if (n == 0) throw Error("--camera " + spec + ": the scene has no cameras");
  size_t index = n;
  const bool number = !spec.empty() && spec.size() <= 9 && std::all_of(spec.begin(), spec.end(), [](char ch) {
    return ch >= '0' && ch <= '9';
  });
  if (number) {
    index = size_t(std::stoul(spec));
    if (index >= n)
      throw Error("--camera " + spec + ": the scene has " + std::to_string(n) + (n == 1 ? " camera (0)" : " cameras (0.." + std::to_string(n - 1) + ")"));
  } else {
    for (size_t i = 0; i < n && index == n; ++i)
      if (scene.cameras[i].name == spec) index = i;
    if (index == n) {
      std::string names;
      for (size_t i = 0; i < n && i < 8; ++i) names += (i ? ", " : "") + std::to_string(i) + " '" + scene.cameras[i].name + "'";
      if (n > 8) names += ", ...";
      throw Error("--camera: no camera named '" + spec + "' (the scene's: " + names + ")");
    }
  }
  const FileCamera& fc = scene.cameras[index];
  const glm::dmat4& w = fc.world;
  Camera c;
  c.eye = glm::dvec3(w[3]);
  const glm::dvec3 forward = glm::dmat3(w) * glm::dvec3(0.0, 0.0, -1.0), up = glm::dmat3(w) * glm::dvec3(0.0, 1.0, 0.0);
  if (!(glm::length(forward) > 0.0) || !(glm::length(up) > 0.0) || !(glm::length(glm::cross(forward, up)) > 0.0))
    throw Error("--camera " + spec + ": the camera's node transform is degenerate (no view direction)");
  const glm::dvec3 dir = glm::normalize(forward);
  c.up = glm::normalize(up);
  glm::dvec3 lo, hi;
  scene.worldBounds(lo, hi);
  const bool empty = !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z);
  const glm::dvec3 centre = empty ? c.eye + dir : (lo + hi) * 0.5;
  const double along = glm::dot(centre - c.eye, dir);
  c.target = c.eye + dir * (along > 0.0 ? along : 1.0);
  c.znear = fc.znear;
  c.zfar = fc.zfar;
  if (c.zfar == 0.0) {  // infinite: past the farthest corner of the bounds
    double farthest = 0.0;
    if (!empty)
      for (int k = 0; k < 8; ++k) {
        const glm::dvec3 corner(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
        farthest = std::max(farthest, glm::length(corner - c.eye));
      }
    c.zfar = std::max(1.5 * farthest, 2.0 * c.znear);
  }
  if (fc.orthographic) {
    c.orthoHalfHeight = fc.ymag;
  } else {
    c.fovyDeg = glm::degrees(fc.yfovRad);
  }
  return c.roundTripped();
}

}  // namespace rast
