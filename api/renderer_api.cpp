// The library's renderer (include/rast/rast.h): the pipeline's Renderer behind
// public settings, with a frame's outputs handed out as views of its own
// buffers, reused frame after frame.
#include "api/api_internal.h"

#include "pipeline/frame/renderer.h"

namespace rast {
namespace lib {

RenderSettings toSettings(const Settings& p, const ::rast::Scene& scene) {
  RenderSettings rs;
  if (p.width < 1 || p.height < 1 || p.width > 16384 || p.height > 16384)
    throw Error("--size: " + std::to_string(p.width) + "x" + std::to_string(p.height) + " is outside 1..16384 per side");
  rs.width = p.width;
  rs.height = p.height;
  rs.shading = parseShading(p.shading);
  rs.cull = parseCull(p.cull);
  rs.filter = parseFilter(p.filter);
  rs.raster = parseRaster(p.raster);
  parseAA(p.aa.empty() ? "none" : p.aa, rs);
  if (p.background) {
    for (float c : *p.background)
      if (!std::isfinite(c)) throw Error("--background: '" + std::to_string(c) + "' is not a list of finite numbers");
    rs.background = float4{(*p.background)[0], (*p.background)[1], (*p.background)[2], 1.0f};
  }
  if (p.sceneLook) {  // as SceneOptions::applySceneLook for a frame that is not a still (no forced MSAA)
    if (!p.background && scene.look.background) rs.background = *scene.look.background;
    for (const float4& l : scene.look.lights) rs.lights.push_back(DirectionalLight{float3{l.x, l.y, l.z}, l.w});
  }
  rs.wantDepth = p.depth;
  rs.wantPrimId = p.primIds || p.barycentrics;
  rs.wantNormals = p.normals;
  return rs;
}

struct Renderer::Impl {
  std::shared_ptr<const Scene::Impl> scene;  // kept alive with the renderer
  ::rast::Renderer renderer;
  Frame frame;
  View<float* [9]> triWorld;       // per drawn triangle: its corners in world space (barycentrics only)
  View<float** [3]> barycentrics;  // reused while the size holds
  Impl(std::shared_ptr<const Scene::Impl> s, uint64_t budget) : scene(std::move(s)), renderer(scene->scene, budget) {}
  void computeBarycentrics(const ::rast::Camera& cam, int width, int height);
};

namespace {
struct Mat4 {
  double m[16];  // column-major
};

// The kernel of Renderer::Impl::computeBarycentrics, at namespace scope: nvcc
// refuses an extended lambda inside a private nested class's member.
void frameBarycentrics(const View<const uint32_t**>& ids, const View<const float* [9]>& tw,
                       const View<float** [3]>& out, const Mat4 m, const uint32_t nTri, const int width,
                       const int height) {
  Kokkos::parallel_for(
      "rast::api::frame_barycentrics",
      Kokkos::MDRangePolicy<ExecutionSpace, Kokkos::Rank<2>>({0, 0}, {int64_t(height), int64_t(width)}),
      KOKKOS_LAMBDA(const int64_t y, const int64_t x) {
        const uint32_t id = ids(y, x);
        if (id == 0 || id > nTri) {
          for (int k = 0; k < 3; ++k) out(y, x, k) = 0.0f;
          return;
        }
        double px[3], py[3], iw[3];
        for (int k = 0; k < 3; ++k) {
          const double wx = tw(id - 1, 3 * k), wy = tw(id - 1, 3 * k + 1), wz = tw(id - 1, 3 * k + 2);
          const double cx = m.m[0] * wx + m.m[4] * wy + m.m[8] * wz + m.m[12];
          const double cy = m.m[1] * wx + m.m[5] * wy + m.m[9] * wz + m.m[13];
          const double cw = m.m[3] * wx + m.m[7] * wy + m.m[11] * wz + m.m[15];
          iw[k] = 1.0 / cw;
          px[k] = cx * iw[k];
          py[k] = cy * iw[k];
        }
        const PixelBarycentrics w = pixelBarycentrics(x, y, width, height, px, py, iw);
        for (int k = 0; k < 3; ++k) out(y, x, k) = float(w.p[k]);
      });
  Kokkos::fence();
}
}  // namespace

// The corners of every drawn triangle in draw order (the order of primitive
// ids), placed in the world once; then, per pixel, the corners in clip space
// and the same arithmetic as rasterize().
void Renderer::Impl::computeBarycentrics(const ::rast::Camera& cam, int width, int height) {
  const ::rast::Scene& s = scene->scene;
  if (!triWorld.data()) {
    auto h = Kokkos::create_mirror_view(Kokkos::HostSpace(),
                                        View<float* [9]>("rast::api::triWorld", std::max<size_t>(1, s.triangleCount())));
    size_t t = 0;
    for (const Draw& d : s.draws) {
      const MeshPrim& p = s.prims[d.prim];
      for (uint32_t i = 0; i < p.triCount; ++i, ++t)
        for (int k = 0; k < 3; ++k) {
          const float3 v = s.positions[p.firstVertex + s.indices[3 * size_t(p.firstTri + i) + k]];
          const glm::dvec4 w = d.model * glm::dvec4(v.x, v.y, v.z, 1.0);
          h(t, 3 * k) = float(w.x);
          h(t, 3 * k + 1) = float(w.y);
          h(t, 3 * k + 2) = float(w.z);
        }
    }
    triWorld = Kokkos::create_mirror_view_and_copy(MemorySpace(), h);
  }
  if (barycentrics.extent(0) != size_t(height) || barycentrics.extent(1) != size_t(width))
    barycentrics = View<float** [3]>("rast::api::barycentrics", size_t(height), size_t(width));
  const glm::dmat4 vp = cam.viewProjection(width, height);
  Mat4 m;
  for (int i = 0; i < 16; ++i) m.m[i] = vp[i / 4][i % 4];
  frameBarycentrics(frame.primIds, triWorld, barycentrics, m, s.triangleCount(), width, height);
}

Renderer::Renderer(const Scene& scene, uint64_t memoryBudget) {
  if (!scene.impl) throw Error("renderer: empty scene");
  impl_ = std::make_unique<Impl>(scene.impl, memoryBudget);
}
Renderer::~Renderer() = default;
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;

const Frame& Renderer::render(const ExecutionSpace& exec, const Camera& camera, const Settings& settings) {
  const ::rast::Camera cam = toCamera(camera);
  const RenderSettings rs = toSettings(settings, impl_->scene->scene);
  exec.fence();  // the caller's work on exec (e.g. filling a view) comes first
  const FrameStats st = impl_->renderer.render(cam, rs);
  const FrameBuffers& fb = impl_->renderer.frameBuffers();
  Frame& f = impl_->frame;
  const size_t h = size_t(rs.height), w = size_t(rs.width);
  f = Frame{};
  f.width = rs.width;
  f.height = rs.height;
  f.color = View<const uint32_t**>(fb.color.data(), h, w);
  if (rs.wantDepth) f.depth = View<const float**>(fb.depth.data(), h, w);
  if (rs.wantPrimId) f.primIds = View<const uint32_t**>(fb.primId.data(), h, w);
  if (rs.wantNormals) {
    static_assert(sizeof(float3) == 3 * sizeof(float), "float3 is three packed floats");
    f.normals = View<const float** [3]>(reinterpret_cast<const float*>(fb.normal.data()), h, w);
  }
  if (settings.barycentrics) {
    impl_->computeBarycentrics(cam, rs.width, rs.height);
    f.barycentrics = impl_->barycentrics;
  }
  if (!settings.primIds) f.primIds = {};  // asked for only as the barycentrics' input
  f.trianglesIn = st.trianglesIn;
  f.trianglesRasterised = st.rasterTris;
  f.method = toString(st.method);
  return f;
}

}  // namespace lib
}  // namespace rast
