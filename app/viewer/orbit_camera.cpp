#include "app/viewer/orbit_camera.h"

#include <algorithm>
#include <cmath>

namespace rast {

namespace {

constexpr double kPi = 3.14159265358979323846;
double rad(double deg) { return deg * (kPi / 180.0); }
double deg(double rad) { return rad * (180.0 / kPi); }

}  // namespace

void OrbitCamera::reset(const Camera& c) {
  fovyDeg_ = c.fovyDeg;
  znear_ = c.znear;
  zfar_ = c.zfar;
  target_ = c.target;
  up_ = glm::length(c.up) > 0.0 ? glm::normalize(c.up) : glm::dvec3(0, 1, 0);
  glm::dvec3 off = c.eye - c.target;
  distance_ = glm::length(off);
  if (!(distance_ > 0.0) || !std::isfinite(distance_)) {
    distance_ = 1.0;
    off = glm::dvec3(0, 0, 1);
  }
  const glm::dvec3 dir = off / glm::length(off);
  const double s = std::clamp(glm::dot(dir, up_), -1.0, 1.0);
  // Yaw 0 is the initial direction, projected off the up axis; when looking
  // along up, any direction perpendicular to it will do.
  glm::dvec3 flat = dir - s * up_;
  if (glm::length(flat) < 1e-9) {
    flat = std::abs(up_.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0);
    flat -= glm::dot(flat, up_) * up_;
  }
  axisZ_ = glm::normalize(flat);
  axisX_ = glm::cross(up_, axisZ_);
  yaw_ = 0.0;
  pitch_ = std::clamp(deg(std::asin(s)), -kMaxPitchDeg, kMaxPitchDeg);
  clampDistance();
}

glm::dvec3 OrbitCamera::eyeOffsetDir() const {
  const double y = rad(yaw_), p = rad(pitch_);
  return std::cos(p) * (std::sin(y) * axisX_ + std::cos(y) * axisZ_) + std::sin(p) * up_;
}

void OrbitCamera::clampDistance() {
  // Stay in front of the near plane and well inside the far plane.
  distance_ = std::clamp(distance_, znear_ * 2.0, zfar_ * 0.5);
}

void OrbitCamera::orbit(double dx, double dy) {
  yaw_ = std::remainder(yaw_ - dx * kDegPerPixel, 360.0);
  pitch_ = std::clamp(pitch_ + dy * kDegPerPixel, -kMaxPitchDeg, kMaxPitchDeg);
}

void OrbitCamera::pan(double dx, double dy, int viewportHeight) {
  const double h = viewportHeight > 0 ? double(viewportHeight) : 1.0;
  const double worldPerPixel = 2.0 * distance_ * std::tan(rad(fovyDeg_) * 0.5) / h;
  const glm::dvec3 forward = -eyeOffsetDir();
  const glm::dvec3 right = glm::normalize(glm::cross(forward, up_));
  const glm::dvec3 camUp = glm::cross(right, forward);
  // The scene follows the cursor: the camera moves the other way.
  target_ += (-dx * right + dy * camUp) * worldPerPixel;
}

void OrbitCamera::zoomSteps(double steps) {
  distance_ *= std::pow(kZoomPerWheelStep, steps);
  clampDistance();
}

void OrbitCamera::zoomDrag(double dy) {
  distance_ *= std::pow(kZoomPerPixel, dy);
  clampDistance();
}

void OrbitCamera::frame(const glm::dvec3& lo, const glm::dvec3& hi) {
  // The same numbers as autoFrame (core/camera.cpp).
  target_ = (lo + hi) * 0.5;
  double r = glm::length(hi - lo) * 0.5;
  if (!(r > 0.0) || !std::isfinite(r)) r = 1.0;
  distance_ = r / std::sin(rad(fovyDeg_) * 0.5);
  znear_ = distance_ / 100.0;
  zfar_ = distance_ * 100.0;
}

Camera OrbitCamera::camera() const {
  Camera c;
  c.target = target_;
  c.eye = target_ + eyeOffsetDir() * distance_;
  c.up = up_;
  c.fovyDeg = fovyDeg_;
  c.znear = znear_;
  c.zfar = zfar_;
  return c.roundTripped();
}

}  // namespace rast
