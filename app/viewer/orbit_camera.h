// Orbit / pan / zoom camera of the viewer, kept apart from any window code so
// that its math is unit-tested (tests/unit/test_orbit_camera.cpp).
//
// The camera is stored as a target, a distance and two angles around a fixed
// world "up" axis (taken from the initial camera):
//   eye = target + distance * (cos(pitch) * (sin(yaw) * X + cos(yaw) * Z) + sin(pitch) * U)
// where U = up, Z = the initial camera's backward direction projected off U
// (so the initial camera has yaw 0) and X = U x Z. The field of view, near and
// far planes come from the initial camera and do not change.
#pragma once

#include "host/scene/camera.h"

#include <glm/glm.hpp>

namespace rast {

class OrbitCamera {
 public:
  // Interaction gains.
  static constexpr double kDegPerPixel = 0.25;  // orbit: a 360-pixel drag turns 90 degrees
  static constexpr double kZoomPerWheelStep = 0.9;  // distance factor per wheel step (up = closer)
  static constexpr double kZoomPerPixel = 1.005;  // middle drag: distance factor per pixel (down = away)
  static constexpr double kMaxPitchDeg = 89.0;  // the view never becomes parallel to up

  OrbitCamera() = default;
  explicit OrbitCamera(const Camera& initial) { reset(initial); }

  // Takes over a camera: its target, distance, angles, up, fovy, near, far.
  void reset(const Camera& c);

  // Left drag by (dx, dy) window pixels (y down): dragging right turns the scene
  // to the right (the eye moves left); dragging down raises the eye.
  void orbit(double dxPixels, double dyPixels);
  // Right drag: moves target and eye in the view plane so that points at the
  // target's depth follow the cursor in a viewport of the given height.
  void pan(double dxPixels, double dyPixels, int viewportHeight);
  // Wheel: positive steps (wheel up) move the eye towards the target.
  void zoomSteps(double steps);
  // Middle drag: dragging down moves the eye away.
  void zoomDrag(double dyPixels);
  // F: keeps the viewing direction, moves the target to the box centre and sets
  // the distance, near and far exactly as autoFrame does for that box.
  void frame(const glm::dvec3& lo, const glm::dvec3& hi);

  // The camera to render. Values are rounded through their %.9g text, so that
  // Camera::flags() of the result reproduces the same frame in `rast render`.
  Camera camera() const;

  const glm::dvec3& target() const { return target_; }
  double distance() const { return distance_; }
  double yawDeg() const { return yaw_; }
  double pitchDeg() const { return pitch_; }
  const glm::dvec3& up() const { return up_; }

 private:
  glm::dvec3 eyeOffsetDir() const;  // unit vector from the target towards the eye
  void clampDistance();

  glm::dvec3 target_{0, 0, 0};
  glm::dvec3 up_{0, 1, 0}, axisX_{1, 0, 0}, axisZ_{0, 0, 1};
  double distance_ = 3.0, yaw_ = 0.0, pitch_ = 0.0;  // degrees
  double fovyDeg_ = 45.0, znear_ = 0.1, zfar_ = 1000.0;
};

}  // namespace rast
