// Helpers shared by the tests: render a scene to host buffers, build small
// scenes from triangles, find test data.
#pragma once

#include "pipeline/data/device.h"
#include "pipeline/frame/renderer.h"
#include "host/scene/scene.h"

#include <string>
#include <vector>

namespace rast::test {

// A device view's contents on the host.
template <class T>
std::vector<T> download(const DView<T>& d) {
  std::vector<T> v(d.extent(0));
  Kokkos::View<T*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>> h(v.data(), v.size());
  Kokkos::deep_copy(h, d);
  return v;
}

struct Frame {
  int width = 0, height = 0;
  std::vector<uint32_t> color;  // top row first
  std::vector<uint32_t> ids;    // bottom row first (OpenGL order): ids[y * width + x]
  std::vector<float> depth;     // bottom row first
  FrameStats stats;
  uint32_t id(int x, int y) const { return ids[size_t(y) * width + x]; }
};

// Renders with ids and depth requested.
Frame renderFrame(const Scene& s, const Camera& cam, RenderSettings rs);
// The settings of a width x height frame with ids and depth requested.
RenderSettings withIdsAndDepth(int width, int height);

// A scene of raw triangles (object space = world space), one draw, one material.
Scene trianglesScene(const std::vector<float3>& positions, const std::vector<uint32_t>& indices,
                     const std::vector<float2>* uvs = nullptr);

// Identity view-projection: positions are NDC (clip space with w = 1), so a
// test can place vertices at exact window positions with windowToNdc().
Camera identityCamera();

// The benchmark's view of ../shared/models/milktruck.glb from inside its cab
// (scripts/device/scenes.txt, milktruck_cab).
Camera milktruckCabCamera();
float3 windowToNdc(double x, double y, double z, int width, int height);

std::string sharedDir();                       // "" when ../shared is absent
std::string assimpDir();                       // "" when assimp-testmodels is absent
bool fileExists(const std::string& p);
// A path for a scratch file in the system's temporary folder (not the build
// folder, which a test binary carried to another machine does not have).
std::string scratchPath(const std::string& name);

// Marks the running test case skipped (ctest's SKIP_REGULAR_EXPRESSION matches
// "SKIPPED:") and records why for the report after ctest's summary
// (tests/support/skip_report.cmake). The caller returns afterwards.
void skipTest(const std::string& reason);

}  // namespace rast::test
