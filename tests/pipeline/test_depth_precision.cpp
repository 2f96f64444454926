// Window depth against the exact depth of the drawn triangle (ray through the
// pixel centre meets the triangle's plane, in long double: depth_reference.h),
// on thin triangles at grazing angles, clipped by the near plane or not, where
// snapping the corners and clipping in float used to tilt the depth plane.
#include <catch2/catch.hpp>

#include "host/gltf/gltf_loader.h"
#include "tests/support/depth_reference.h"
#include "scenes/gltf_export.h"
#include "tests/support/test_support.h"

#include <cstdlib>

using namespace rast;
using namespace rast::test;

namespace {

// OpenGL through Mesa's llvmpipe stays within 3.8e-6 of the exact depth on the
// milk truck seen from inside (issue #10); rast must do at least as well. What
// is left is mostly the float rounding of the clip coordinates (both renderers
// have it), moved along steep depth gradients.
constexpr double kLlvmpipeTruckError = 3.8e-6;

// The two sliver scenes below, rendered by llvmpipe through
// ../shared/tools/glref (scripts/measure/depth_error.py --slivers, which writes them
// with RAST_DEPTH_SCENES), are off the exact depth by up to these:
constexpr double kLlvmpipeCrossingError = 2.52e-5;
constexpr double kLlvmpipeInFrontError = 2.61e-5;

// A portable generator (std:: distributions differ between standard libraries).
struct Lcg {
  uint64_t s;
  float operator()() {  // uniform in [-1, 1)
    s = s * 6364136223846793005ull + 1442695040888963407ull;
    return float(int32_t(uint32_t(s >> 32))) / 2147483648.0f;
  }
};

// Long slivers at grazing angles around a camera at the origin looking down -z
// with its near plane at 0.1: `crossing` of them start behind the near plane
// (so clipping cuts them), the others start just in front of it.
Scene sliverScene(int crossing, int inFront, uint64_t seed) {
  Lcg u{seed};
  std::vector<rast::float3> p;
  std::vector<uint32_t> idx;
  for (int i = 0; i < crossing + inFront; ++i) {
    const bool cross = i < crossing;
    // The near corner sits close to the eye, off to the side; the far edge is
    // short and lies 5 to 40 units away, so the triangle is a long thin wedge
    // whose depth changes steeply across its width on screen.
    const rast::float3 a{0.3f * u(), 0.3f * u(), cross ? 0.05f + 0.04f * u() : -0.12f - 0.01f * u()};
    const float dist = 22.5f + 17.5f * u();
    const rast::float3 b{dist * 0.4f * u(), dist * 0.3f * u(), -dist};
    const float w = 0.002f * dist * (1.5f + u());  // a fraction of a pixel to a few pixels wide
    const rast::float3 c{b.x + w * u(), b.y + w * u(), b.z - dist * 0.05f * u()};
    const uint32_t base = uint32_t(p.size());
    p.push_back(a);
    p.push_back(b);
    p.push_back(c);
    idx.insert(idx.end(), {base, base + 1, base + 2});
  }
  Scene s = trianglesScene(p, idx);
  // For measuring another renderer on the same triangles (scripts/measure/depth_error.py).
  if (const char* dir = std::getenv("RAST_DEPTH_SCENES"))
    exportGlb(s, std::string(dir) + (crossing ? "/slivers_crossing.glb" : "/slivers_in_front.glb"));
  return s;
}

Camera sliverCamera() {
  Camera cam;
  cam.eye = {0, 0, 0};
  cam.target = {0, 0, -1};
  cam.znear = 0.1;
  cam.zfar = 100;
  return cam;
}

DepthError measure(const Scene& s, const Camera& cam, RenderSettings rs, int which = 0) {
  const Frame f = renderFrame(s, cam, rs);
  return depthError(drawnTrianglesInClipSpace(s, cam.viewProjection(rs.width, rs.height)), rs.width, rs.height, f.ids,
                    f.depth, which);
}

}  // namespace

TEST_CASE("depth of thin triangles cut by the near plane is exact to float precision", "[depth]") {
  const Scene s = sliverScene(150, 0, 7);  // camera: --eye 0,0,0 --target 0,0,-1 --near 0.1 --far 100
  const Camera cam = sliverCamera();
  RenderSettings rs;
  rs.width = 320;
  rs.height = 240;
  for (RasterMethod m : allRasterMethods()) {
    rs.raster = m;
    const DepthError e = measure(s, cam, rs, 1);
    INFO(toString(m) << ": max error " << e.maxErr << " at " << e.maxX << "," << e.maxY << " (primitive " << e.maxId
                     << ": " << e.maxGot << ", exact " << e.maxWant << "), mean " << e.sumErr / double(e.pixels));
    CHECK(e.pixels > 2000);  // the slivers are on screen and most cross the near plane
    CHECK(e.maxErr < kLlvmpipeCrossingError / 10);  // 7.9e-5 before the fix, 3.1e-7 after
  }
}

TEST_CASE("depth of unclipped slivers at grazing angles follows their plane, not their snapped corners", "[depth]") {
  const Scene s = sliverScene(0, 150, 11);
  const Camera cam = sliverCamera();
  RenderSettings rs;
  rs.width = 320;
  rs.height = 240;
  const DepthError e = measure(s, cam, rs, 2);
  INFO("max error " << e.maxErr << " at " << e.maxX << "," << e.maxY << " (primitive " << e.maxId << ": " << e.maxGot
                    << ", exact " << e.maxWant << "), mean " << e.sumErr / double(e.pixels));
  CHECK(e.pixels > 2000);
  CHECK(e.maxErr < kLlvmpipeInFrontError / 4);  // 1.7e-4 before the fix, 2.8e-6 after
}

TEST_CASE("milk truck seen from inside: depth within llvmpipe's error of the exact depth", "[depth][shared]") {
  const std::string d = sharedDir();
  if (d.empty()) {
    skipTest("../shared is absent (a user's clone has none): no milk truck");
    return;
  }
  const Scene s = loadGltf(d + "/models/milktruck.glb");
  Camera cam;  // in the cab, the near plane cutting through the body (scripts/measure/depth_error.py)
  cam.eye = {0.5, 1.3, 0.2};
  cam.target = {3, 1.0, 0.5};
  cam.znear = 0.5;
  cam.zfar = 807.250969;
  RenderSettings rs;
  rs.width = 960;
  rs.height = 540;
  const DepthError all = measure(s, cam, rs, 0), clipped = measure(s, cam, rs, 1);
  INFO("max error " << all.maxErr << " at " << all.maxX << "," << all.maxY << " (primitive " << all.maxId
                    << "); on triangles cut by the near plane " << clipped.maxErr << " over " << clipped.pixels
                    << " pixels");
  CHECK(clipped.pixels > 1000);
  CHECK(all.maxErr < kLlvmpipeTruckError);  // 6.6e-5 before the fix, 1.0e-6 after
}
