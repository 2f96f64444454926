// The renderer: the scene's upload checked against the memory budget, the
// frame buffers prepared and grown, each frame planned once (frame_plan.h),
// recorded or launched stage by stage, checked for overflow after it, and the
// supersampling and post passes around it.
#include "pipeline/frame/renderer.h"

#include "backends/frame_graphs.h"
#include "backends/stage_timer.h"
#include "pipeline/blend/blend.h"
#include "host/scene/memory_budget.h"
#include "pipeline/cpu/cpu_shade.h"
#include "pipeline/geometry/geometry.h"
#include "pipeline/post/accumulate.h"
#include "pipeline/post/chain.h"
#include "pipeline/post/ssao.h"
#include "pipeline/raster/raster.h"
#include "pipeline/raster/raster_lines.h"
#include "pipeline/rules/raster_rules.h"
#include "pipeline/rules/sample_pattern.h"
#include "pipeline/shade/shade.h"
#include "pipeline/shade/texture_sampling.h"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cstring>

namespace rast {

namespace {

uint64_t drawnVertices(const Scene& s) {
  uint64_t n = 0;
  for (const Draw& d : s.draws) n = addSat(n, d.prim < s.prims.size() ? s.prims[d.prim].vertexCount : 0);
  return n;
}

// Device bytes of a raster triangle buffer of n entries and the buffers sized
// with it: the triangle, its first work item (4 bytes), its search hint (8)
// and its occluder candidacy (start and triangle, 4 each). One count for the
// budget check before the first frame and for a buffer grown by clipping.
uint64_t rasterTriBytes(uint64_t n) { return mulSat(n, sizeof(RasterTri) + 5 * sizeof(uint32_t)); }

// What the device scene, the raster triangles of a first frame and the
// vertex-stage buffers will take, checked before any of it is allocated: a
// small file can draw one large mesh from many nodes.
// The host Scene's own arrays (the caller keeps it while rendering).
uint64_t hostSceneBytes(const Scene& s) {
  uint64_t b = mulSat(s.positions.size() + s.normals.size(), sizeof(float3));
  b = addSat(b, mulSat(s.uvs.size() + s.uvs1.size(), sizeof(float2)));
  b = addSat(b, mulSat(s.colors.size() + s.tangents.size(), sizeof(float4)));
  b = addSat(b, mulSat(s.indices.size() + s.lineIndices.size() + s.pointIndices.size(), sizeof(uint32_t)));
  b = addSat(b, mulSat(s.draws.size(), sizeof(Draw)));
  for (const Texture& t : s.textures) b = addSat(b, mulSat(t.rgba.size(), sizeof(uint32_t)));
  return b;
}

const Scene& admitScene(const Scene& s, uint64_t budget) {
  uint64_t texels = 0;
  for (const Texture& t : s.textures) texels = addSat(texels, mulSat(uint64_t(t.width), uint64_t(t.height)));
  uint64_t sceneBytes = mulSat(s.positions.size(), 2 * sizeof(float3));
  sceneBytes = addSat(sceneBytes, mulSat(s.uvs.size() + s.uvs1.size(), sizeof(float2)));
  sceneBytes = addSat(sceneBytes, mulSat(s.colors.size() + s.tangents.size(), sizeof(float4)));
  sceneBytes = addSat(sceneBytes, mulSat(s.indices.size(), sizeof(uint32_t)));
  sceneBytes = addSat(sceneBytes, mulSat(s.draws.size(), sizeof(DrawGPU) + 2 * sizeof(uint32_t)));
  sceneBytes = addSat(sceneBytes, mulSat(texels, 2 * 4 * 4 / 3));  // device texels with mipmaps, host copy
  if (drawTables(s.draws.size()))  // triDraw, vertDraw (with a host copy each while uploading)
    sceneBytes = addSat(sceneBytes, mulSat(addSat(s.triangleCount(), drawnVertices(s)), 2 * sizeof(DrawIndex)));
  MemoryLedger ledger(budget);
  ledger.charge("the scene in host memory", hostSceneBytes(s));
  ledger.charge("the scene on the device (" + std::to_string(s.positions.size()) + " vertices, " +
                    std::to_string(s.indices.size() / 3) + " triangles, " + std::to_string(texels) + " texels)",
                sceneBytes);
  ledger.charge("the raster triangle buffer (" + std::to_string(s.triangleCount()) + " drawn triangles)",
                rasterTriBytes(uint64_t(s.triangleCount()) + 1024));
  ledger.charge("the vertex stage buffers (" + std::to_string(drawnVertices(s)) + " drawn vertices)",
                mulSat(drawnVertices(s), sizeof(float4) + sizeof(SnapVert) + 2 * sizeof(float3)));
  return s;
}

}  // namespace

Renderer::Renderer(const Scene& scene, uint64_t memoryBudget)
    : budget_(memoryBudget ? memoryBudget : defaultMemoryBudget()),
      hostSceneBytes_(hostSceneBytes(scene)),
      perVertexBytes_(sizeof(float4) + sizeof(SnapVert) + 2 * sizeof(float3)),
      scene_(DeviceScene::upload(admitScene(scene, budget_))),
      hostTextures_(scene.textures),
      graphs_(new FrameGraphs) {
  frame_.uploadSeen = graphs_->uploadSeen();
  frame_.counters = allocZeroed<uint32_t>("frame.counters", kNumCounters);
  // Most triangles yield at most one raster triangle; clipping can yield more,
  // and then the buffer grows after the first frame that needs it.
  frame_.triCapacity = scene_.numTris + 1024;
  frame_.tris = allocUninit<RasterTri>("frame.tris", frame_.triCapacity);
}

Renderer::~Renderer() = default;

RasterMethod Renderer::resolveMethod(const RenderSettings& rs) const { return chooseMethod(rs, autoStats_); }

void Renderer::checkFrameBudget(const RenderSettings& rs) const {
  const uint64_t n = uint64_t(rs.width) * uint64_t(rs.height);
  const bool super = rs.ssaa > 1 || rs.reference;
  const int msaa = super ? 1 : rs.msaa;
  uint64_t perPixel = 8 * uint64_t(msaa) + 4;                      // visibility keys, colour
  if (rs.wantDepth) perPixel += 4;
  if (rs.wantPrimId) perPixel += 4;
  if (rs.wantNormals) perPixel += 12;
  if (super) perPixel += sizeof(float4);                           // supersampling accumulator
  if (super || rs.post.needsFloat() || blendFilm()) perPixel += sizeof(float4);   // the float film
  if (blendPasses()) {  // the transparency method's fixed buffers (its fragment store: lastFrameFit)
    BlendPlan b;
    b.method = chooseTransparency(rs, blendFallback_);
    b.k = rs.blendK;
    b.lists = walksTileLists(b.method, blendFallback_);
    perPixel += uint64_t(msaa) * blendBytesPerSample(b);
  }
  if (rs.post.ssao) perPixel += sizeof(float4) + 3 * sizeof(float);  // geometry, depth, AO and its blur
  uint64_t frame = mulSat(n, perPixel);
  // Bloom: two half-resolution float films.
  if (rs.post.bloom) frame = addSat(frame, mulSat(uint64_t(rs.width / 2 + 1) * uint64_t(rs.height / 2 + 1), 2 * sizeof(float4)));
  if (split_) frame = addSat(frame, split_->frameBytes(rs.width, rs.height, msaa));  // the exchange's buffers
  // Held besides the frame: the scene (here and in the caller's host Scene),
  // the raster triangles and per-vertex buffers; and, when the frame is done,
  // the host copies its outputs are written from (one output at a time, the
  // largest: a float film of 16 bytes a pixel).
  const uint64_t held = scene_.bytes() + viewBytes(frame_.tris) + viewBytes(frame_.counters) +
                        mulSat(scene_.numVerts, perVertexBytes_) + hostSceneBytes_;
  MemoryLedger ledger(budget_);
  ledger.charge("the scene and its triangle buffers", held);
  ledger.charge("the host copy of an output image", mulSat(n, sizeof(float4)));
  ledger.check("a " + std::to_string(rs.width) + "x" + std::to_string(rs.height) + " framebuffer with " +
                   std::to_string(msaa) + (msaa == 1 ? " sample" : " samples") + " per pixel",
               frame);
}

void Renderer::prepare(const RenderSettings& rs) {
  if (rs.width < 1 || rs.height < 1 || rs.width > kMaxFramebufferSide || rs.height > kMaxFramebufferSide)
    throw Error("image size " + std::to_string(rs.width) + "x" + std::to_string(rs.height) + " is outside 1.." +
                std::to_string(kMaxFramebufferSide) + " per side");
  const size_t n = size_t(rs.width) * size_t(rs.height);
  if (frame_.vp.width != rs.width || frame_.vp.height != rs.height || frame_.vp.samples.count != rs.msaa ||
      (rs.wantDepth && !frame_.depth.data()) || (rs.wantPrimId && !frame_.primId.data()) ||
      (rs.wantNormals && !frame_.normal.data()))
    checkFrameBudget(rs);
  if (frame_.vp.width != rs.width || frame_.vp.height != rs.height || frame_.vp.samples.count != rs.msaa) {
    frame_.vp = Viewport{rs.width, rs.height, samplePattern(rs.msaa)};
    // Exact size: a smaller frame releases the larger buffers.
    frame_.vis = allocUninit<uint64_t>("frame.vis", n * size_t(rs.msaa));
    frame_.visClear = false;
    frame_.color = allocUninit<uint32_t>("frame.color", n);
    frame_.depth = DView<float>();
    frame_.primId = DView<uint32_t>();
    frame_.normal = DView<float3>();
    frame_.accum = DView<float4>();
    frame_.post.release();
    frame_.blend.release();
  }
  if (!supersampling_)
    frame_.post.trim(rs.post.needsFloat() || rs.ssaa > 1 || rs.reference || blendFilm(), rs.post.ssao, rs.post.bloom);
  // Mipmaps are built the first time a frame needs them.
  const bool wantMips = rs.filter == TexFilter::Trilinear || rs.shading == ShadingMode::MipLevel ||
                        (rs.filter == TexFilter::Auto && readsGltfMaterial(rs.shading));
  if (wantMips && scene_.hasTextures && !scene_.hasMipmaps) {
    // The pyramids (a third more than the textures) are built on the host and
    // uploaded: a host and a device copy of every level while they are made.
    uint64_t texels = 0;
    for (const Texture& t : hostTextures_) texels = addSat(texels, uint64_t(t.rgba.size()) * 4);
    MemoryLedger ledger(budget_);
    ledger.charge("the scene, its host copy and the frame buffers", addSat(deviceBytes(), hostSceneBytes_));
    ledger.check("the textures' mipmap levels (filtering asks for them)", mulSat(texels / 3, 8));
    scene_.uploadTextures(hostTextures_, true);
  }
  if (rs.shading == ShadingMode::Pbr && rs.environment != "none") {
    EnvOptions eo;
    eo.intensity = rs.envIntensity;
    eo.rotationDegrees = rs.envRotation;
    if (!envIsLoaded_ || rs.environment != envLoaded_) {
      env_ = EnvironmentGPU();  // the old one's memory first
      MemoryLedger ledger(budget_);
      ledger.charge("the scene and frame buffers", deviceBytes());
      env_ = loadEnvironment(rs.environment, eo, ledger);
      envLoaded_ = rs.environment;
      envIsLoaded_ = true;
    } else {
      setEnvironmentLook(env_, eo);  // intensity and rotation need no filtering
    }
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
  if (!frame_.uploaded.data()) {
    frame_.uploaded = allocUninit<mat4f>("frame.uploaded", kUniformSlots + scene_.numDraws);
    frame_.uniforms = DView<FrameUniforms>(reinterpret_cast<FrameUniforms*>(frame_.uploaded.data()), 1);
    frame_.mvp = DView<mat4f>(frame_.uploaded.data() + kUniformSlots, scene_.numDraws);
  }
}

void Renderer::enqueue(const Camera& cam, const RenderSettings& rs, StageTimer* timer) {
  countersPublished_ = false;  // until this frame's keys are taken
  if (split_) {  // every part prepares, or none renders
    std::string error;
    try {
      prepare(rs);
    } catch (const std::exception& e) {
      error = e.what();
    }
    split_->agree(error);
  } else {
    prepare(rs);
  }
  FrameUniforms u{};
  const glm::dmat4 vp = cam.viewProjection(rs.width, rs.height);
  for (int k = 0; k < 16; ++k) u.viewProj.m[k] = glm::value_ptr(vp)[k];
  u.camera.eye = float3{float(cam.eye.x), float(cam.eye.y), float(cam.eye.z)};
  u.camera.znear = float(cam.znear);
  u.camera.zfar = float(cam.zfar);
  const glm::dmat4 view = cam.view();
  for (int k = 0; k < 16; ++k) u.camera.view.m[k] = float(glm::value_ptr(view)[k]);
  if (frameNumber_ == ~0u) {  // tags would repeat: start again from zeroed status
    frameNumber_ = 0;
    frame_.setupStatus = DView<uint64_t>();
    frame_.workHint = DView<uint64_t>();
  }
  u.frame = ++frameNumber_;
  // The upload: the uniforms, then (few draws) the draws' matrices.
  const bool hostMatrices = scene_.hostMvps();
  upload_.assign(kUniformSlots + (hostMatrices ? scene_.numDraws : 0), mat4f{});
  std::memcpy(upload_.data(), &u, sizeof u);
  if (hostMatrices)
    for (uint32_t d = 0; d < scene_.numDraws; ++d) upload_[kUniformSlots + d] = drawMvp(u.viewProj, scene_.hostModels[d]);
  const bool statsDue = rs.raster == RasterMethod::Auto && (!autoStats_.valid || autoFrames_ % kAutoStatsEvery == 0);
  if (rs.raster == RasterMethod::Auto) ++autoFrames_;
  PlanInputs in;
  in.scene = &scene_;
  in.frame = &frame_;
  in.stats = autoStats_;
  in.statsDue = statsDue;
  in.supersampling = supersampling_;
  in.blendFallback = blendFallback_;
  in.keepKeys = split_ != nullptr;
  in.blendPasses = blendPasses();
  in.blendFilm = blendFilm();
  plan_ = planFrame(rs, in);
  plan_.shadeParams.useEnv = rs.shading == ShadingMode::Pbr && rs.environment != "none" && env_.valid() ? 1 : 0;
  if (plan_.shadeParams.useEnv) plan_.shadeParams.env = env_;
  uint64_t visClear = frame_.visClear ? 1 : 0;

  if (timer) timer->start();
  // Launched directly: the split's exchange waits on the host; heavyweight
  // kernels (the general shading kernel, the MASK pass and some BLEND methods
  // on a GPU: pipeline/data/device.h) copy their functors before launch,
  // which a recorded frame would not redo.
  const bool heavy = kOnDevice && (plan_.blend.mask || !blendLaunchesLightweight(plan_.blend, plan_.shadeParams) ||
                                   !shadeLaunchesLightweight(plan_.shadeParams, plan_.samples));
  if (split_ || heavy) {
    Kokkos::View<const mat4f*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>> h(upload_.data(), upload_.size());
    Kokkos::deep_copy(Kokkos::subview(frame_.uploaded, std::make_pair(size_t(0), upload_.size())), h);
    launchFrame(plan_, timer);
    if (plan_.film && !supersampling_ && !plan_.blend.encode && (!split_ || split_->holdsFrame())) runPost(cam, rs, timer);
    return;
  }
  // The camera reaches the kernels through device memory, copied first; the
  // launches after it are the same from frame to frame for the same key.
  graphs_->run(plan_.key, timer, visClear, {upload_.data(), frame_.uploaded.data(), upload_.size() * sizeof(mat4f), u.frame}, [&] {
    frame_.visClear = visClear != 0;
    launchFrame(plan_, timer);
    visClear = frame_.visClear ? 1 : 0;
  });
  frame_.visClear = visClear != 0;
  if (plan_.film && !supersampling_ && !plan_.blend.encode) runPost(cam, rs, timer);  // else encoded by the resolve
}

void Renderer::launchFrame(const FramePlan& plan, StageTimer* timer) {
  Kokkos::Profiling::pushRegion("rast::vertex");
  vertexStage(scene_, frame_, plan.needWorld);
  Kokkos::Profiling::popRegion();
  if (timer) timer->mark("vertex");

  Kokkos::Profiling::pushRegion("rast::setup");
  primitiveSetup(scene_, frame_, plan.cull, plan.numberBlocks, plan.occluders, plan.blend.blend);
  Kokkos::Profiling::popRegion();
  if (plan.autoStats) rasterStatistics(frame_);
  if (timer) timer->mark("setup");

  Kokkos::Profiling::pushRegion("rast::raster");
  const bool fused = plan.shade == ShadePath::FusedBinned;
  if (!plan.fill) {
    clearVisibility(frame_);  // triangles drawn as edges or corners only
  } else switch (plan.method) {
    case RasterMethod::Naive:
      clearVisibility(frame_);
      rasterNaive(frame_);
      break;
    case RasterMethod::Binned:
      if (fused) {
        rasterLinesAndPoints(scene_, frame_, plan.lines);  // none to draw; records the pass for shading
        rasterBinnedShaded(scene_, frame_, plan.shadeParams, lights_);
      } else {
        rasterBinned(frame_);
      }
      break;
    case RasterMethod::VisBuffer:
    case RasterMethod::Auto:  // never planned: chooseMethod resolves it
      clearVisibility(frame_);
      rasterVisBuffer(frame_, plan.occluders, plan.rowLanes);
      break;
  }
  // MASK triangles after the method's (binned writes every pixel), with the
  // same keys: their passes read the work lists of both alpha classes.
  if (plan.blend.mask || plan.blend.blend) alphaWorkLists(scene_, frame_, plan.blend);
  if (plan.blend.mask) rasterMask(scene_, frame_, plan.shadeParams);
  // Points and lines after the triangles: binned writes every pixel. Keys
  // were written (the fused path writes none); shading may clear them.
  if (!fused) {
    rasterLinesAndPoints(scene_, frame_, plan.lines);
    frame_.visClear = false;
  }
  Kokkos::Profiling::popRegion();
  if (timer) timer->mark("raster");
  if (split_) split_->afterRaster(scene_, frame_, plan, lights_, timer);  // marks "composite"
  // BLEND fragments in front of the opaque depth, before shading clears it.
  if (plan.blend.blend) {
    Kokkos::Profiling::pushRegion("rast::blend");
    // Split: the composited keys hold the whole scene's opaque depth.
    blendCollect(scene_, frame_, plan.shadeParams, lights_, plan.blend, split_ ? split_->compositedKeys() : frame_.vis);
    Kokkos::Profiling::popRegion();
    if (timer) timer->mark("blend");
  }

  Kokkos::Profiling::pushRegion("rast::shade");
  switch (plan.shade) {
    case ShadePath::Pixels:
    {
      ShadeBlend sb;
      if (plan.blend.shadeDepth) sb.opaqueDepth = frame_.blend.opaque;
      if (plan.blend.shadeComposite) {
        sb.composite = frame_.blend.blockComposite;
        sb.frags = frame_.blend.blockFrags;
        sb.encode = plan.blend.encode;
        sb.raw = plan.blend.raw;
        sb.straight = plan.blend.straight;
        sb.filmless = plan.blend.filmless;
      }
      shadeStage(scene_, frame_, plan.shadeParams, lights_, sb);
      break;
    }
    case ShadePath::Spans: shadeSpansStage(scene_, frame_, plan.shadeParams, lights_); break;
    case ShadePath::FusedBinned: break;  // shaded with the raster
    case ShadePath::None: break;         // the keys are the output (the caller clears none: visClear is false)
  }
  Kokkos::Profiling::popRegion();
  if (timer) timer->mark("shade");
  if (split_) split_->afterShade(scene_, frame_, plan, lights_, timer);  // marks "merge"
  if (plan.blend.blend) {
    Kokkos::Profiling::pushRegion("rast::blend");
    blendResolve(scene_, frame_, plan.shadeParams, lights_, plan.blend);
    Kokkos::Profiling::popRegion();
    if (timer) timer->mark("blend_resolve");
  }
}

void Renderer::runPost(const Camera& cam, const RenderSettings& rs, StageTimer* timer) {
  PostView v;
  v.width = rs.width;
  v.height = rs.height;
  const glm::dmat4 proj = cam.projection(rs.width, rs.height);
  v.tanX = float(1.0 / proj[0][0]);
  v.tanY = float(1.0 / proj[1][1]);
  v.ssaoRadius = ssaoRadiusFor(rs.post, glm::length(cam.eye - cam.target));
  runPostChain(frame_.post, v, rs.post, frame_.color, scene_.srgbEncodePacked, isRawShading(rs.shading), timer,
               rs.background.w < 1.0f);
}

FrameKeys Renderer::takeKeys() {
  if (plan_.shade != ShadePath::None || plan_.samples != 1 || frame_.visClear)
    throw Error("internal: takeKeys() after a frame that was shaded, multisampled or already taken");
  FrameKeys k;
  k.vis = frame_.vis;
  k.tris = frame_.tris;
  k.blockFrame = frame_.blockFrame;
  k.blockDepth = frame_.blockDepth;
  k.frame = frame_.uniforms;
  const uint32_t numBlocks = visBlocks(frame_.vp, k.blocksPerRow);
  k.tagged = plan_.shadeParams.blockFrames && frame_.blockFrame.data() ? 1 : 0;
  k.resetBlocks = frame_.blockDepth.data() && frame_.blockDepth.extent(0) >= numBlocks ? 1 : 0;
  frame_.visClear = true;
  if (kPinnedFromDevice) {  // else lastFrameFit copies them, as after other frames
    hostCounters();
    k.counters = frame_.counters;
    k.countersOut = countersHost_.data();
    countersPublished_ = true;
  }
  return k;
}

void Renderer::hostCounters() {
  if (countersHost_.extent(0) != frame_.counters.extent(0))
    countersHost_ = decltype(countersHost_)("frame.countersHost", frame_.counters.extent(0));
}

bool Renderer::lastFrameFit(FrameStats* stats) {
  hostCounters();
  const auto& h = countersHost_;
  if (!countersPublished_) Kokkos::deep_copy(Exec(), h, frame_.counters);  // else the keys' pass wrote them
  countersPublished_ = false;
  Exec().fence();
  const uint32_t need = h(kRasterTris);
  if (plan_.autoStats) {
    auto sum = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), frame_.sumArea);
    auto mx = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), frame_.maxArea);
    auto occ = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), frame_.occArea);
    autoStats_ = AutoStats{need <= frame_.triCapacity, sum(), mx(), need, occ()};
  }
  if (stats) {
    stats->trianglesIn = scene_.numTris;
    stats->rasterTris = need;
    stats->rasterWork = h(kRasterWork);
    stats->method = plan_.method;
    stats->rowLanes = plan_.rowLanes;
    stats->occluderArea = autoStats_.occArea;
    stats->deviceBytes = deviceBytes();
    stats->minimumBytes = scene_.bytes() + viewBytes(frame_.vis) + viewBytes(frame_.color);
    stats->filmBytes = frame_.post.bytes() + viewBytes(frame_.accum);
  }
  bool fit = true;
  if (need > frame_.triCapacity) {
    // Clipping can multiply triangles: the larger buffer must fit the budget too.
    MemoryLedger ledger(budget_);
    ledger.charge("the scene and frame buffers", deviceBytes() - viewBytes(frame_.tris));
    ledger.check("the raster triangle buffer (" + std::to_string(need) + " triangles after clipping)",
                 rasterTriBytes(uint64_t(need) + need / 8));
    frame_.triCapacity = need + need / 8;
    frame_.tris = allocUninit<RasterTri>("frame.tris", frame_.triCapacity);
    fit = false;
  }
  // The listed methods' tile lists: grown to the frame's need, or, when that
  // would exceed the budget, the frame is drawn with kbuffer instead (weighted:
  // its fixed-memory sums; FrameStats::blendFallback says so), whose fixed
  // buffers must fit.
  if (fit && plan_.blend.blend) {
    // The lists' buffer reallocated for `need` entries, where the budget holds them.
    const auto growLists = [&](const uint64_t need) {
      MemoryLedger ledger(budget_);
      ledger.charge("the scene and frame buffers", deviceBytes() - viewBytes(frame_.blend.tileTris));
      if (need >= (uint64_t(1) << 32) || addSat(ledger.used(), mulSat(need, kBytesPerListEntry)) > ledger.limit())
        return false;
      frame_.blend.tileTris = DView<uint32_t>();
      frame_.blend.tileCapacity = need;
      frame_.blend.tileTris = allocUninit<uint32_t>("blend.tileTris", need);
      return true;
    };
    auto t = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), frame_.blend.totals);
    const bool listed = plan_.blend.lists;
    if (listed) {
      blendNeed_ = t(kBlendFrags);
      frame_.blend.longestList = t(kBlendLongest);
    }
    if (stats) {
      stats->blendFragments = blendNeed_;  // the fixed-memory passes count none: the last listed frame's
      stats->blendMaxDepth = t(kBlendMaxDepth);
      stats->transparency = plan_.blend.method;
      stats->blendFallback = blendFallback_;
    }
    if (listed && frame_.blend.listStride && t(kBlendLongest) > frame_.blend.listStride) {
      fit = false;  // a list outgrew the strided layout's room: drawn again, counted (listStrideFor)
    } else if (listed && t(kBlendListed) > frame_.blend.tileCapacity) {
      const uint64_t need = t(kBlendListed) + t(kBlendListed) / 8;
      if (!growLists(need)) {
        blendFallback_ = true;
        frame_.blend.tileTris = frame_.blend.tileCount = frame_.blend.tileEnd = frame_.blend.opaque = DView<uint32_t>();
        frame_.blend.blockFrags = frame_.blend.walkedBlocks = DView<uint32_t>();
        frame_.blend.blockComposite = DView<float4>();
        frame_.blend.tileCapacity = 0;
        BlendPlan k = plan_.blend;
        if (k.method != Transparency::Weighted) k.method = Transparency::KBuffer;  // as chooseTransparency
        k.lists = false;
        MemoryLedger held(budget_);
        held.charge("the scene and frame buffers", deviceBytes());
        held.check(std::string(k.method == Transparency::Weighted ? "the weighted sums" : "the k-buffer") +
                         " that replace the transparency's tile lists (" + std::to_string(need) + " entries do not fit)",
                     mulSat(uint64_t(frame_.vp.width) * uint64_t(frame_.vp.height) * uint64_t(frame_.vp.samples.count),
                            blendBytesPerSample(k)));
      }
      fit = false;
    }
    // The strided layout's room for the next frames, where their lists
    // (this frame's, which fitted) allow it and the budget holds it.
    const uint64_t room = stridedListRoom(frame_);
    if (fit && listed && room > frame_.blend.tileCapacity) growLists(room);  // else counted
  }
  // The binned method's list has its own capacity (its count is only valid
  // when every raster triangle was kept).
  if (fit && plan_.method == RasterMethod::Binned && h(kRasterWork) > frame_.workCapacity) {
    frame_.workCapacity = h(kRasterWork) + h(kRasterWork) / 8;
    fit = false;
  }
  return fit;
}

FrameStats Renderer::render(const Camera& cam, const RenderSettings& rs) {
  if (rs.ssaa > 1 || rs.reference) return renderSupersampled(cam, rs);
  FrameStats st;
  for (int attempt = 1;; ++attempt) {
    enqueue(cam, rs);
    bool fit = false;
    if (split_) {  // every part grows its buffers and renders again, or none
      std::string error;
      try {
        fit = lastFrameFit(&st);
      } catch (const std::exception& e) {
        error = e.what();
      }
      split_->agree(error);
      fit = split_->all(fit);  // one part's buffers overflowed: every part renders again
    } else {
      fit = lastFrameFit(&st);
    }
    if (fit) {
      st.attempts = attempt;
      return st;
    }
    // Counters are deterministic: each buffer grows at most once (the
    // raster triangles, whose overflow hides the rest, then the tile lists),
    // and a strided layout's overflow is drawn again counted.
    if (attempt >= 4) throw Error("internal: frame buffers did not converge");
  }
}

FrameStats Renderer::renderSupersampled(const Camera& cam, const RenderSettings& rs) {
  // Sub-pixel sample offsets (in pixels from the centre): the centres of a k x k
  // grid for SSAA; one random point in each cell of a 16 x 16 grid (stratified,
  // fixed seed) for the reference.
  checkFrameBudget(rs);  // with the accumulator, before the first pass allocates
  std::vector<std::pair<double, double>> offsets;
  const int k = rs.reference ? rs.referenceGrid : rs.ssaa;
  if (rs.ssaa != 1 && rs.ssaa != 2 && rs.ssaa != 4 && !rs.reference) throw Error("SSAA supports 2x2 or 4x4");
  if (k < 1 || k > 64) throw Error("reference grid must be 1..64 samples per side");
  uint64_t rng = 0x9e3779b97f4a7c15ull * (rs.referenceSeed + 1);
  auto uniform = [&rng]() {  // splitmix64: the same sequence on every machine
    uint64_t z = (rng += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return double((z ^ (z >> 31)) >> 11) / double(1ull << 53);
  };
  for (int j = 0; j < k; ++j)
    for (int i = 0; i < k; ++i) {
      const double ri = rs.reference ? uniform() : 0.5, rj = rs.reference ? uniform() : 0.5;
      offsets.emplace_back((i + ri) / k - 0.5, (j + rj) / k - 0.5);
    }
  RenderSettings one = rs;
  one.ssaa = 1;
  one.msaa = 1;
  one.reference = false;
  if (rs.reference) one.filter = TexFilter::Bilinear;  // 256 bilinear taps integrate the footprint
  const glm::dmat4 vp = cam.viewProjection(rs.width, rs.height);
  FrameStats st;
  supersampling_ = true;
  struct Reset {
    bool& b;
    ~Reset() { b = false; }
  } reset{supersampling_};
  for (size_t p = 0; p < offsets.size(); ++p) {
    // Sampling at +offset is drawing the scene shifted by -offset.
    Camera c = cam;
    const glm::dvec3 shift(-2.0 * offsets[p].first / rs.width, -2.0 * offsets[p].second / rs.height, 0.0);
    c.viewProjOverride = glm::translate(glm::dmat4(1.0), shift) * vp;
    if (p > 0) {  // outputs of the first pass
      one.wantDepth = one.wantPrimId = one.wantNormals = false;
      one.post.ssao = false;
    }
    st = render(c, one);
    accumulateColor(frame_, p == 0);
    if (onPass) onPass(int(p + 1), int(offsets.size()));
  }
  resolveAccumulated(frame_, int(offsets.size()));
  runPost(cam, rs, nullptr);
  Exec().fence();
  st.filmBytes = frame_.post.bytes() + viewBytes(frame_.accum);
  st.deviceBytes = deviceBytes();
  return st;
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
std::vector<float4> Renderer::filmBottomUp() const { return toHost(frame_.post.hdr, size_t(frame_.vp.width) * frame_.vp.height); }
std::vector<float4> Renderer::geometryBottomUp() const { return toHost(frame_.post.geom, size_t(frame_.vp.width) * frame_.vp.height); }
std::vector<float> Renderer::aoBottomUp() const { return toHost(frame_.post.aoBlur, size_t(frame_.vp.width) * frame_.vp.height); }
std::vector<float3> Renderer::normalsBottomUp() const { return toHost(frame_.normal, size_t(frame_.vp.width) * frame_.vp.height); }

}  // namespace rast
