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
  rs.wantPrimId = p.primIds;
  rs.wantNormals = p.normals;
  return rs;
}

struct Renderer::Impl {
  std::shared_ptr<const Scene::Impl> scene;  // kept alive with the renderer
  ::rast::Renderer renderer;
  Frame frame;
  Impl(std::shared_ptr<const Scene::Impl> s, uint64_t budget) : scene(std::move(s)), renderer(scene->scene, budget) {}
};

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
  f.trianglesIn = st.trianglesIn;
  f.trianglesRasterised = st.rasterTris;
  f.method = toString(st.method);
  return f;
}

}  // namespace lib
}  // namespace rast
