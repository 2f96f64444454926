// The viewer's orbit camera (app/viewer/orbit_camera.cpp, compiled into the
// tests by app/viewer/CMakeLists.txt): orbit, pan, zoom and frame math, without
// a window.
#include <catch2/catch.hpp>

#include "app/viewer/orbit_camera.h"
#include "scenes/procedural.h"

#include <glm/glm.hpp>

#include <cmath>

using namespace rast;

namespace {

constexpr double kPi = 3.14159265358979323846;

double angleDeg(const glm::dvec3& a, const glm::dvec3& b) {
  const double c = glm::dot(glm::normalize(a), glm::normalize(b));
  return std::acos(std::max(-1.0, std::min(1.0, c))) * 180.0 / kPi;
}

// Elevation of the eye above the target's horizontal plane (up = +Y), degrees.
double elevationDeg(const Camera& c) {
  const glm::dvec3 d = glm::normalize(c.eye - c.target);
  return std::asin(d.y) * 180.0 / kPi;
}

// Window position (pixels, y down) of a world point.
glm::dvec2 project(const Camera& c, const glm::dvec3& p, int w, int h) {
  const glm::dvec4 q = c.viewProjection(w, h) * glm::dvec4(p, 1.0);
  return {(q.x / q.w * 0.5 + 0.5) * w, (0.5 - q.y / q.w * 0.5) * h};
}

Camera autoCamera() {
  static const Scene s = defaultScene();
  return autoFrame(s);
}

}  // namespace

TEST_CASE("orbit camera: taking over a camera keeps it exactly", "[viewer][orbit]") {
  const Camera c = autoCamera();
  const OrbitCamera o(c);
  const Camera r = o.camera();
  // The viewer's print-camera and `rast render` must see the same numbers.
  CHECK(r.flags() == c.flags());
  CHECK(o.yawDeg() == 0.0);
  // autoFrame's direction (0, 0.25, 1), as far as its 9-digit eye tells.
  CHECK(o.pitchDeg() == Approx(std::atan(0.25) * 180.0 / kPi).epsilon(1e-7));
  CHECK(o.distance() == Approx(glm::length(c.eye - c.target)).epsilon(1e-12));
}

TEST_CASE("orbit camera: left drag turns around the target", "[viewer][orbit]") {
  const Camera c = autoCamera();
  OrbitCamera o(c);
  const double d0 = o.distance();
  const double elev0 = elevationDeg(c);

  SECTION("horizontal drag: yaw only, distance and target kept") {
    o.orbit(360.0, 0.0);  // 360 px * 0.25 deg/px = 90 degrees
    const Camera r = o.camera();
    CHECK(glm::length(r.target - c.target) == Approx(0.0).margin(1e-6));
    CHECK(glm::length(r.eye - r.target) == Approx(d0).epsilon(1e-7));
    CHECK(elevationDeg(r) == Approx(elev0).margin(1e-5));
    // Horizontal directions 90 degrees apart; dragging right moves the eye left
    // (towards -X when it started on +Z).
    glm::dvec3 h0 = c.eye - c.target, h1 = r.eye - r.target;
    h0.y = h1.y = 0.0;
    CHECK(angleDeg(h0, h1) == Approx(90.0).margin(1e-5));
    CHECK(h1.x < 0.0);
  }
  SECTION("vertical drag: dragging down raises the eye") {
    o.orbit(0.0, 40.0);  // +10 degrees
    CHECK(elevationDeg(o.camera()) == Approx(elev0 + 10.0).margin(1e-5));
    o.orbit(0.0, -200.0);  // -50 degrees: below the ground plane of the default scene
    CHECK(elevationDeg(o.camera()) == Approx(elev0 - 40.0).margin(1e-5));
    CHECK(o.camera().eye.y < c.target.y);
  }
  SECTION("a full turn and an undone drag come back") {
    o.orbit(1440.0, 0.0);
    CHECK(glm::length(o.camera().eye - c.eye) == Approx(0.0).margin(1e-6 * d0));
    o.orbit(123.0, -77.0);
    o.orbit(-123.0, 77.0);
    CHECK(glm::length(o.camera().eye - c.eye) == Approx(0.0).margin(1e-6 * d0));
  }
  SECTION("pitch stops short of the up axis") {
    o.orbit(0.0, 1e6);
    CHECK(o.pitchDeg() == OrbitCamera::kMaxPitchDeg);
    const Camera r = o.camera();
    CHECK(glm::length(glm::cross(r.target - r.eye, r.up)) > 0.0);
    CHECK(angleDeg(r.eye - r.target, r.up) == Approx(90.0 - OrbitCamera::kMaxPitchDeg).margin(1e-5));
    o.orbit(0.0, -2e6);
    CHECK(o.pitchDeg() == -OrbitCamera::kMaxPitchDeg);
  }
}

TEST_CASE("orbit camera: right drag pans with the cursor", "[viewer][orbit]") {
  const Camera c = autoCamera();
  const int W = 640, H = 480;
  OrbitCamera o(c);
  o.pan(50.0, -30.0, H);
  const Camera r = o.camera();
  // The view direction and distance are unchanged...
  CHECK(angleDeg(r.target - r.eye, c.target - c.eye) == Approx(0.0).margin(1e-5));
  CHECK(glm::length(r.eye - r.target) == Approx(glm::length(c.eye - c.target)).epsilon(1e-7));
  // ...and the old target, at the target's depth, followed the cursor.
  const glm::dvec2 p = project(r, c.target, W, H);
  CHECK(p.x == Approx(W / 2.0 + 50.0).margin(1e-3));
  CHECK(p.y == Approx(H / 2.0 - 30.0).margin(1e-3));
  // A drag over the whole height moves by the visible height at that depth.
  OrbitCamera o2(c);
  o2.pan(0.0, double(H), H);
  const double visible = 2.0 * o2.distance() * std::tan(c.fovyDeg * kPi / 360.0);
  CHECK(glm::length(o2.camera().target - c.target) == Approx(visible).epsilon(1e-6));
}

TEST_CASE("orbit camera: wheel and middle drag zoom", "[viewer][orbit]") {
  const Camera c = autoCamera();
  OrbitCamera o(c);
  const double d0 = o.distance();
  o.zoomSteps(1.0);
  CHECK(o.distance() == Approx(d0 * OrbitCamera::kZoomPerWheelStep).epsilon(1e-12));
  o.zoomSteps(-1.0);
  CHECK(o.distance() == Approx(d0).epsilon(1e-12));
  o.zoomDrag(100.0);  // dragging down moves away
  CHECK(o.distance() == Approx(d0 * std::pow(OrbitCamera::kZoomPerPixel, 100.0)).epsilon(1e-12));
  o.zoomDrag(-100.0);
  CHECK(o.distance() == Approx(d0).epsilon(1e-12));
  // Direction and target stay.
  CHECK(angleDeg(o.camera().eye - o.camera().target, c.eye - c.target) == Approx(0.0).margin(1e-5));
  CHECK(glm::length(o.camera().target - c.target) == Approx(0.0).margin(1e-6));
  // Never through the near plane, never out past the far plane.
  o.zoomSteps(1e4);
  CHECK(o.distance() == Approx(2.0 * c.znear));
  o.zoomSteps(-1e5);
  CHECK(o.distance() == Approx(0.5 * c.zfar));
}

TEST_CASE("orbit camera: F frames the scene like autoFrame, from the current direction", "[viewer][orbit]") {
  const Scene s = defaultScene();
  const Camera c = autoFrame(s);
  glm::dvec3 lo, hi;
  s.worldBounds(lo, hi);

  OrbitCamera o(c);
  o.pan(200.0, 100.0, 480);
  o.zoomSteps(5.0);
  o.frame(lo, hi);
  {
    // No orbit: rast render's camera (up to the last printed digit, as the
    // direction comes from autoFrame's rounded eye).
    const Camera r = o.camera();
    CHECK(glm::length(r.eye - c.eye) == Approx(0.0).margin(1e-7 * glm::length(c.eye - c.target)));
    CHECK(r.target == c.target);
    CHECK(r.znear == c.znear);
    CHECK(r.zfar == c.zfar);
  }

  o.orbit(100.0, -60.0);
  const glm::dvec3 dir = glm::normalize(o.camera().eye - o.camera().target);
  o.zoomSteps(-3.0);
  o.pan(-40.0, 10.0, 480);
  o.frame(lo, hi);
  const Camera r = o.camera();
  CHECK(glm::length(r.target - c.target) == Approx(0.0).margin(1e-6));
  CHECK(glm::length(r.eye - r.target) == Approx(glm::length(c.eye - c.target)).epsilon(1e-7));
  CHECK(angleDeg(r.eye - r.target, dir) == Approx(0.0).margin(1e-4));
  CHECK(r.znear == c.znear);
  CHECK(r.zfar == c.zfar);
}

TEST_CASE("orbit camera: degenerate starting cameras", "[viewer][orbit]") {
  Camera c;
  c.eye = {0, 5, 0};  // looking straight down the up axis
  c.target = {0, 0, 0};
  c.up = {0, 1, 0};
  OrbitCamera o(c);
  CHECK(o.pitchDeg() == OrbitCamera::kMaxPitchDeg);
  o.orbit(10.0, 10.0);
  const Camera r = o.camera();
  for (int k = 0; k < 3; ++k) CHECK(std::isfinite(r.eye[k]));
  CHECK(glm::length(glm::cross(r.target - r.eye, r.up)) > 0.0);

  Camera z;  // a Z-up camera: the orbit turns around Z
  z.eye = {3, 0, 1};
  z.target = {0, 0, 0};
  z.up = {0, 0, 1};
  OrbitCamera oz(z);
  oz.orbit(360.0, 0.0);
  CHECK(oz.camera().eye.z == Approx(1.0).epsilon(1e-7));
  CHECK(glm::length(oz.camera().eye) == Approx(std::sqrt(10.0)).epsilon(1e-7));
}
