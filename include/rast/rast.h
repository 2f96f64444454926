// rast as a library (docs/library.md): the installed C++ API. It includes only
// Kokkos and the standard library, so a consumer needs nothing of rast's own
// dependencies. The caller owns the program: it initialises and finalises
// Kokkos; rast never exits the process and reports bad input as rast::Error
// with the message the CLI prints.
//
//   find_package(rast REQUIRED)   target_link_libraries(app PRIVATE rast::rast)
#pragma once

#include <rast/config.h>  // generated: build/<preset>/generated/include, or the install's include/
#include "error.h"

#include <Kokkos_Core.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace rast {

// The execution space this library was built for (Kokkos::OpenMP in an OpenMP
// build) and its memory: views passed in and handed out live there.
using ExecutionSpace = RAST_LIB_EXECUTION_SPACE;
using MemorySpace = ExecutionSpace::memory_space;
template <class T>
using View = Kokkos::View<T, Kokkos::LayoutRight, MemorySpace>;

namespace lib {

std::string version();  // "0.1.0"
std::string backend();  // the execution space's name, e.g. "OpenMP"

// A caller's triangle mesh in host memory, borrowed for the call (copied into
// the scene). Required: positions (3 floats a vertex) and indices (3 a
// triangle). Optional (nullptr: none): normals (3 a vertex; none: flat),
// uvs (2), colours (4, linear RGBA), and a material per triangle (an index
// into materials, each a linear RGBA base colour).
struct MeshArrays {
  const float* positions = nullptr;
  size_t vertexCount = 0;
  const uint32_t* indices = nullptr;
  size_t triangleCount = 0;
  const float* normals = nullptr;
  const float* uvs = nullptr;
  const float* colors = nullptr;
  const int32_t* triangleMaterial = nullptr;
  std::vector<std::array<float, 4>> materials;
};

// The same mesh as Kokkos Views in the library's memory space. Empty views
// mean "none" for the optional streams.
struct MeshViews {
  View<const float* [3]> positions;
  View<const uint32_t* [3]> indices;
  View<const float* [3]> normals;
  View<const float* [2]> uvs;
  View<const float* [4]> colors;
  View<const int32_t*> triangleMaterial;
  std::vector<std::array<float, 4>> materials;
};

// A scene: geometry, materials, textures, lights. Cheap to copy (shared, immutable).
class Scene {
 public:
  // A glTF 2.0 file (.gltf, .glb), "builtin:<name>" or "" (the embedded default
  // scene), loaded as `rast render` loads it (docs/security.md: external files
  // only with allowExternalFiles; maxMemory 0: half the machine's memory).
  static Scene load(const std::string& pathOrBuiltin, bool allowExternalFiles = false, uint64_t maxMemory = 0);
  static Scene fromArrays(const MeshArrays& mesh);
  // Waits for `exec` before reading the views.
  static Scene fromViews(const ExecutionSpace& exec, const MeshViews& mesh);

  uint32_t triangleCount() const;
  // World-space bounding box: lo then hi.
  std::array<double, 6> bounds() const;

  struct Impl;
  std::shared_ptr<const Impl> impl;
};

// A pinhole camera, OpenGL conventions. viewProjection, when set, replaces
// projection * view (16 values, column-major as glm and OpenGL store them).
struct Camera {
  std::array<double, 3> eye{0, 0, 3}, target{0, 0, 0}, up{0, 1, 0};
  double fovyDeg = 45.0, znear = 0.1, zfar = 1000.0;
  std::optional<std::array<double, 16>> viewProjection;

  // The camera `rast render` uses without camera flags: the scene's own, or the
  // scene framed automatically.
  static Camera framing(const Scene& scene, double fovyDeg = 45.0);
  // The same camera as rast command-line flags (--eye ... --far ...).
  std::string flags() const;
};

// What a frame does; names as on the command line (rast help render).
struct Settings {
  int width = 1920, height = 1080;
  std::string shading = "lambert";   // lambert|blinn-phong|normals|depth|uv|miplevel
  std::string cull = "none";         // none|back
  std::string filter = "bilinear";   // nearest|bilinear|trilinear
  std::string raster = "auto";       // auto|naive|visbuffer|binned
  std::string aa = "none";           // none|ssaa2|ssaa4|msaa2|msaa4|msaa8
  std::optional<std::array<float, 3>> background;  // linear RGB; none: the scene's, else black
  bool sceneLook = true;  // take background and lights from the scene when not given, as the CLI does
  bool depth = true, primIds = true, normals = false;  // which outputs besides colour
  bool barycentrics = false;  // perspective-correct barycentrics of each pixel's triangle (implies primIds)
};

// One frame's outputs, as views of the renderer's own buffers (no copy): valid
// until the renderer's next frame, which reuses them. [height][width], the
// bottom row first (OpenGL's order). Outputs not asked for are empty views.
struct Frame {
  int width = 0, height = 0;
  View<const uint32_t**> color;   // sRGB RGBA8 packed, R in the low byte
  View<const float**> depth;      // window depth in [0, 1]; 1 where nothing was drawn
  View<const uint32_t**> primIds; // triangle index + 1 in draw order; 0 where nothing was drawn
  View<const float** [3]> normals;  // world-space normals
  // Perspective-correct barycentrics (b0, b1, b2) of the triangle in primIds at
  // the pixel's centre, the weights of its three corners; zero where empty (and
  // on line and point fragments).
  View<const float** [3]> barycentrics;
  uint32_t trianglesIn = 0, trianglesRasterised = 0;
  std::string method;  // the raster method that ran
};

class Renderer {
 public:
  // memoryBudget: bytes the renderer may hold on the device; 0: half the machine's memory.
  explicit Renderer(const Scene& scene, uint64_t memoryBudget = 0);
  ~Renderer();
  Renderer(Renderer&&) noexcept;
  Renderer& operator=(Renderer&&) noexcept;

  // Waits for `exec`, renders one frame and waits for it.
  const Frame& render(const ExecutionSpace& exec, const Camera& camera, const Settings& settings);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// nvdiffrast's dr.rasterize for one image: clip-space positions pos [V][4] and
// triangles tri [T][3] (indices into pos) at width x height. Fills out
// [height][width][4] with (u, v, z/w, triangle id + 1), zero where nothing was
// drawn, u and v the perspective-correct barycentrics of the triangle's first
// and second vertex; and ids [height][width] with the exact triangle index, -1
// where nothing was drawn. Rows bottom first (y = -1 is row 0), as nvdiffrast.
// Coverage and ids follow rast's rules (top-left fill rule, fixed point,
// nearest z/w wins, the lower index on equal depth). Throws Error for
// non-finite positions, w <= 0 (no near-plane clipping here yet), indices out of
// range and mismatched output sizes.
void rasterize(const ExecutionSpace& exec, View<const float* [4]> pos, View<const int32_t* [3]> tri, int width,
               int height, View<float** [4]> out, View<int32_t**> ids);

// The same, as a context kept across calls (nvdiffrast's RasterizeCudaContext):
// its renderer and buffers are made on the first call and reused while the
// vertex and triangle counts and the size stay the same; the caller's
// positions and triangles are then read on the device, with no copy through
// the host. Waits for `exec` before reading and for the frame before returning.
class Rasterizer {
 public:
  Rasterizer();
  ~Rasterizer();
  Rasterizer(Rasterizer&&) noexcept;
  Rasterizer& operator=(Rasterizer&&) noexcept;
  void rasterize(const ExecutionSpace& exec, View<const float* [4]> pos, View<const int32_t* [3]> tri, int width,
                 int height, View<float** [4]> out, View<int32_t**> ids);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The GPU this library runs on (the execution space's device), -1 in host builds.
int deviceIndex();
// The stream the library's work is queued on in GPU builds (the default
// execution space instance's), as an integer; 0 in host builds. A caller's
// DLPack producer given it (`__dlpack__(stream=...)`) orders its pending work
// before the library's reads without a wait on the host.
uintptr_t deviceStream();
// Whether that stream waits for work queued before on the GPU's legacy
// default stream (torch's default stream): callers queuing there need no
// other ordering. False in host builds.
bool deviceStreamFollowsLegacy();

}  // namespace lib
}  // namespace rast
