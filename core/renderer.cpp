#include "renderer.h"

#include "../backends/stage_timer.h"
#include "raster_common.h"
#include "texture_sampling.h"

#include <glm/gtc/type_ptr.hpp>

namespace rast {

size_t FrameBuffers::bytes() const {
  return viewBytes(mvp) + viewBytes(clip) + viewBytes(worldPos) + viewBytes(worldNormal) + viewBytes(triOffset) +
         viewBytes(tris) + viewBytes(workOffset) + viewBytes(work) + viewBytes(tileStart) + viewBytes(counters) + viewBytes(vis) +
         viewBytes(color) + viewBytes(depth) + viewBytes(primId) + viewBytes(normal);
}

uint32_t persistentThreads() {
  const int c = Exec().concurrency();
#if defined(RAST_EXEC_CUDA) || defined(RAST_EXEC_HIP)
  return uint32_t(c);  // one resident thread per hardware slot
#else
  return uint32_t(c) * 16;  // interleaved slices per core keep the cores balanced
#endif
}

Renderer::Renderer(const Scene& scene) : scene_(DeviceScene::upload(scene)) {
  frame_.counters = DView<uint32_t>("frame.counters", kNumCounters);
  // Most triangles yield at most one raster triangle; clipping can yield more,
  // and then the buffer grows after the first frame that needs it.
  frame_.triCapacity = scene_.numTris + 1024;
  frame_.tris = allocUninit<RasterTri>("frame.tris", frame_.triCapacity);
}

RasterMethod Renderer::resolveMethod(const RenderSettings& rs) const {
  if (rs.raster != RasterMethod::Auto) return rs.raster;
  // Without statistics yet (first frame), the binned method: bounded work per
  // item and no atomics whatever the scene.
  if (!autoStats_.valid || autoStats_.tris == 0) return RasterMethod::Binned;
  // Only small triangles: one work item per triangle walking its box is the
  // cheapest (no binning, no block expansion). The limit is one binned tile:
  // beyond it a single item's walk starts to dominate its neighbours'.
  constexpr uint64_t kSmallTriangleArea = 32 * 32;
  if (autoStats_.maxArea <= kSmallTriangleArea) return RasterMethod::Naive;
  return RasterMethod::Binned;
}

void Renderer::prepare(const RenderSettings& rs) {
  if (rs.width < 1 || rs.height < 1 || rs.width > kMaxFramebufferSide || rs.height > kMaxFramebufferSide)
    throw Error("image size " + std::to_string(rs.width) + "x" + std::to_string(rs.height) + " is outside 1.." +
                std::to_string(kMaxFramebufferSide) + " per side");
  const size_t n = size_t(rs.width) * size_t(rs.height);
  if (frame_.vp.width != rs.width || frame_.vp.height != rs.height) {
    frame_.vp = Viewport{rs.width, rs.height};
    // Exact size: a smaller frame releases the larger buffers.
    frame_.vis = allocUninit<uint64_t>("frame.vis", n);
    frame_.color = allocUninit<uint32_t>("frame.color", n);
    frame_.depth = DView<float>();
    frame_.primId = DView<uint32_t>();
    frame_.normal = DView<float3>();
  }
  if (rs.lights != uploadedLights_ || !lights_.data()) {
    std::vector<LightGPU> l;
    for (const DirectionalLight& d : rs.lights) l.push_back({normalize(d.direction), d.intensity});
    lights_ = allocUninit<LightGPU>("frame.lights", l.size() ? l.size() : 1);
    if (!l.empty()) {
      Kokkos::View<LightGPU*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>> h(l.data(), l.size());
      Kokkos::deep_copy(Kokkos::subview(lights_, std::make_pair(size_t(0), l.size())), h);
    }
    uploadedLights_ = rs.lights;
  }
}

void Renderer::enqueue(const Camera& cam, const RenderSettings& rs, StageTimer* timer) {
  prepare(rs);
  const glm::dmat4 vpD = cam.viewProjection(rs.width, rs.height);
  mat4d vp;
  for (int k = 0; k < 16; ++k) vp.m[k] = glm::value_ptr(vpD)[k];
  const bool lit = rs.shading == ShadingMode::Lambert || rs.shading == ShadingMode::BlinnPhong;
  const bool needWorld = lit || rs.shading == ShadingMode::Normals || rs.wantNormals;
  lastMethod_ = resolveMethod(rs);
  lastAuto_ = rs.raster == RasterMethod::Auto;

  if (timer) timer->start();
  Kokkos::Profiling::pushRegion("rast::vertex");
  vertexStage(scene_, frame_, vp, needWorld);
  Kokkos::Profiling::popRegion();
  if (timer) timer->mark("vertex");

  Kokkos::Profiling::pushRegion("rast::setup");
  primitiveSetup(scene_, frame_, rs.cull == CullMode::Back);
  Kokkos::Profiling::popRegion();
  if (lastAuto_) rasterStatistics(frame_);
  if (timer) timer->mark("setup");

  Kokkos::Profiling::pushRegion("rast::raster");
  switch (lastMethod_) {
    case RasterMethod::Naive:
      clearVisibility(frame_);
      rasterNaive(frame_);
      break;
    case RasterMethod::Binned:
      rasterBinned(frame_);
      break;
    default:
      clearVisibility(frame_);
      rasterVisBuffer(frame_);
      break;
  }
  Kokkos::Profiling::popRegion();
  if (timer) timer->mark("raster");

  ShadeParams sp{};
  sp.mode = rs.shading;
  sp.filter = rs.filter;
  sp.eye = float3{float(cam.eye.x), float(cam.eye.y), float(cam.eye.z)};
  sp.ambient = rs.ambient;
  sp.specular = rs.specular;
  sp.shininess = rs.shininess;
  sp.background = rs.background;
  sp.backgroundPacked = linearToSrgb8(rs.background.x) | linearToSrgb8(rs.background.y) << 8 |
                        linearToSrgb8(rs.background.z) << 16 | linearToSrgb8(1.0f) << 24;
  sp.znear = float(cam.znear);
  sp.zfar = float(cam.zfar);
  sp.headlight = rs.lights.empty() ? 1 : 0;
  sp.wantDepth = rs.wantDepth;
  sp.wantPrimId = rs.wantPrimId;
  sp.wantNormals = rs.wantNormals;
  Kokkos::Profiling::pushRegion("rast::shade");
  shadeStage(scene_, frame_, sp, lights_);
  Kokkos::Profiling::popRegion();
  if (timer) timer->mark("shade");
}

bool Renderer::lastFrameFit(FrameStats* stats) {
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), frame_.counters);
  const uint32_t need = h(kRasterTris);
  if (lastAuto_) {
    auto sum = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), frame_.sumArea);
    auto mx = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), frame_.maxArea);
    autoStats_ = AutoStats{need <= frame_.triCapacity, sum(), mx(), need};
  }
  if (stats) {
    stats->trianglesIn = scene_.numTris;
    stats->rasterTris = need;
    stats->rasterWork = h(kRasterWork);
    stats->method = lastMethod_;
    stats->deviceBytes = deviceBytes();
    stats->minimumBytes = scene_.bytes() + viewBytes(frame_.vis) + viewBytes(frame_.color);
  }
  bool fit = true;
  if (need > frame_.triCapacity) {
    frame_.triCapacity = need + need / 8;
    frame_.tris = allocUninit<RasterTri>("frame.tris", frame_.triCapacity);
    fit = false;
  }
  // The binned method's list has its own capacity (its count is only valid
  // when every raster triangle was kept).
  if (fit && lastMethod_ == RasterMethod::Binned && h(kRasterWork) > frame_.workCapacity) {
    frame_.workCapacity = h(kRasterWork) + h(kRasterWork) / 8;
    fit = false;
  }
  return fit;
}

FrameStats Renderer::render(const Camera& cam, const RenderSettings& rs) {
  FrameStats st;
  for (int attempt = 1;; ++attempt) {
    enqueue(cam, rs);
    if (lastFrameFit(&st)) {
      st.attempts = attempt;
      return st;
    }
    // Counters are deterministic, so the second attempt always fits.
    if (attempt >= 3) throw Error("internal: frame buffers did not converge");
  }
}

template <class T>
static std::vector<T> toHost(const DView<T>& v, size_t n) {
  std::vector<T> out(n);
  if (!v.data()) throw Error("internal: requested output was not rendered");
  Kokkos::View<T*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>> h(out.data(), n);
  Kokkos::deep_copy(h, Kokkos::subview(v, std::make_pair(size_t(0), n)));
  return out;
}

std::vector<uint32_t> Renderer::colorTopDown() const {
  const int w = frame_.vp.width, hgt = frame_.vp.height;
  std::vector<uint32_t> bu = toHost(frame_.color, size_t(w) * hgt), td(bu.size());
  for (int y = 0; y < hgt; ++y)
    std::copy(bu.begin() + size_t(hgt - 1 - y) * w, bu.begin() + size_t(hgt - y) * w, td.begin() + size_t(y) * w);
  return td;
}
std::vector<float> Renderer::depthBottomUp() const { return toHost(frame_.depth, size_t(frame_.vp.width) * frame_.vp.height); }
std::vector<uint32_t> Renderer::primIdsBottomUp() const { return toHost(frame_.primId, size_t(frame_.vp.width) * frame_.vp.height); }
std::vector<float3> Renderer::normalsBottomUp() const { return toHost(frame_.normal, size_t(frame_.vp.width) * frame_.vp.height); }

}  // namespace rast
