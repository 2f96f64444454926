// The renderer: owns the device scene and the frame buffers, plans each frame
// once (frame_plan.h) and runs its stages in order: vertex, setup, raster,
// shade, post.
#pragma once

#include "host/scene/camera.h"
#include "pipeline/data/device_scene.h"
#include "pipeline/data/frame_buffers.h"
#include "pipeline/frame/frame_keys.h"
#include "pipeline/frame/frame_plan.h"
#include "pipeline/shade/shade.h"
#include "host/settings/render_settings.h"


#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace rast {

class StageTimer;
class FrameGraphs;

struct FrameStats {
  uint32_t trianglesIn = 0;   // drawn triangles submitted
  uint32_t rasterTris = 0;    // after clipping, culling and snapping
  uint32_t rasterWork = 0;    // work items of the raster method
  RasterMethod method = RasterMethod::VisBuffer;
  bool rowLanes = false;      // the visbuffer raster ran a block's rows on lanes (RasterBlockRows)
  uint64_t occluderArea = 0;  // `auto`: the opaque occluder candidates' pixels in the viewport (last statistics)
  int attempts = 1;           // > 1 when buffers had to grow and the frame was redone
  size_t deviceBytes = 0;     // scene + frame buffers
  size_t minimumBytes = 0;    // scene + one framebuffer (visibility + colour)
  size_t filmBytes = 0;       // the float film and post buffers (0 when no float path ran)
  // BLEND surfaces (docs/transparency.md): the method used, whether the exact
  // method's tile lists would have exceeded the memory budget (then kbuffer
  // was used), the fragments in front of the opaque depth (alpha 0 ones
  // included) and the most of one sample (exact and sorted).
  Transparency transparency = Transparency::Exact;
  bool blendFallback = false;
  uint64_t blendFragments = 0, blendMaxDepth = 0;
};

// A frame split by geometry (sort-last, pipeline/distributed/): several
// renderers each draw a part of the scene, and between their raster and shade
// stages exchange visibility keys, whose minimum is the whole scene's; after
// shading they merge what each shaded. The renderer calls it at those two
// points, and before and after a frame's fallible host steps so that every
// part fails together. Split frames are launched directly (never recorded:
// the exchange waits on the host) and never fuse shading into the raster.
class FrameSplit {
 public:
  virtual ~FrameSplit() = default;
  // Every part passes "" or its error; throws one Error on every part if any failed.
  virtual void agree(const std::string& error) = 0;
  // True on every part when `ok` is true on all.
  virtual bool all(bool ok) = 0;
  virtual void afterRaster(const DeviceScene& s, FrameBuffers& f, const FramePlan& plan, const DView<LightGPU>& lights,
                           StageTimer* timer) = 0;
  virtual void afterShade(const DeviceScene& s, FrameBuffers& f, const FramePlan& plan, const DView<LightGPU>& lights,
                          StageTimer* timer) = 0;
  // Whether this part holds the merged frame (and runs the post chain on it).
  virtual bool holdsFrame() const = 0;
  // glTF BLEND (docs/distributed.md): whether the whole scene draws BLEND
  // triangles (then every part renders to the float film, which the merge
  // combines), and whether this part composites them: the part that holds
  // the frame, with every BLEND draw whole, over the merged opaque film. The
  // others keep theirs marked (skipped by the raster) and run no BLEND pass.
  virtual bool sceneBlends() const = 0;
  virtual bool blendsHere() const = 0;
  // After afterRaster: every sample's composited key, whose depth bits are the
  // whole scene's opaque depth (this part's own keys hold only its pixels).
  virtual const DView<uint64_t>& compositedKeys() const = 0;
  // Bytes its own buffers take for a frame of this size (charged with the frame's).
  virtual uint64_t frameBytes(int width, int height, int samples) const = 0;
};

class Renderer {
 public:
  // memoryBudget: bytes the renderer may hold (scene on the device and frame
  // buffers), checked before each allocation; 0: defaultMemoryBudget().
  explicit Renderer(const Scene& scene, uint64_t memoryBudget = 0);
  ~Renderer();

  // Takes a new pose of the scene it was made with (animation frames):
  // matrices and moved vertices into the buffers it holds.
  void updatePose(const Scene& scene) { scene_.updatePose(scene); }

  // Renders one frame and waits for it. If the frame needed larger buffers
  // than it had, they grow and the frame is rendered again (never capped).
  FrameStats render(const Camera& cam, const RenderSettings& rs);

  // Enqueues one frame with no host-device traffic (for benchmarks); call
  // lastFrameFit() afterwards to check that no buffer overflowed.
  void enqueue(const Camera& cam, const RenderSettings& rs, StageTimer* timer = nullptr);

  // After enqueue() with RenderSettings::keysOnly (one sample a pixel): the
  // frame's keys, for one pass of the caller's over every pixel, queued next
  // on the default instance (FrameKeys::take). The next frame counts on that
  // pass having cleared them, and lastFrameFit on one of its threads having
  // published the counters (FrameKeys::publish).
  FrameKeys takeKeys();

  // Reads the device counters of the last frame (a small copy that waits for
  // it); grows the buffers for next time and returns false if it overflowed.
  bool lastFrameFit(FrameStats* stats = nullptr);

  // Results of the last frame. Colour is sRGB RGBA8 (R in the low byte) with the
  // top row first, as image files store it; depth, ids and normals keep
  // OpenGL's bottom-up row order.
  std::vector<uint32_t> colorTopDown() const;
  // The same colour buffer where the pipeline keeps it, with no copy: sRGB
  // RGBA8, bottom row first, width x height of the last frame, in the
  // execution space's memory (device memory when colorOnDevice()). Valid until
  // the next frame. Lets a display copy device to device (rast-viewer's
  // graphics interop) or upload straight from host memory.
  const uint32_t* colorData() const { return frame_.color.data(); }
  static constexpr bool colorOnDevice() { return kOnDevice; }
  // Every buffer of the last frame where it lives (colour, depth, ids, normals:
  // frame_buffers.h), for callers that wrap them without a copy (api/, the
  // library's Frame). Valid until the next frame.
  const FrameBuffers& frameBuffers() const { return frame_; }
  // What the last frame decided (raster method, shading path, transparency).
  const FramePlan& lastPlan() const { return plan_; }
  std::vector<float> depthBottomUp() const;
  std::vector<uint32_t> primIdsBottomUp() const;
  std::vector<float3> normalsBottomUp() const;
  // The float film after the post chain (linear; only when the frame used it:
  // RenderSettings::post.needsFloat(), or supersampling).
  std::vector<float4> filmBottomUp() const;
  // SSAO's input and output of the last frame with SSAO on: view-space normal
  // and depth per pixel, and the (blurred) ambient occlusion.
  std::vector<float4> geometryBottomUp() const;
  std::vector<float> aoBottomUp() const;

  const DeviceScene& scene() const { return scene_; }
  // The method a frame with these settings uses (auto: chosen from the
  // previous frame's statistics; see chooseAuto in renderer.cpp).
  RasterMethod resolveMethod(const RenderSettings& rs) const;
  size_t deviceBytes() const { return scene_.bytes() + frame_.bytes() + env_.bytes(); }

  // Splits every later frame by geometry (null: whole frames, as by default).
  // The split outlives the renderer's frames.
  void setSplit(FrameSplit* split) { split_ = split; }

  // Called after each pass of a supersampled frame with (passes done, total):
  // lets a command line show progress on long reference renders. Empty: silent.
  std::function<void(int, int)> onPass;

 private:
  void prepare(const RenderSettings& rs);
  FrameStats renderSupersampled(const Camera& cam, const RenderSettings& rs);
  void runPost(const Camera& cam, const RenderSettings& rs, StageTimer* timer);
  // The frame's kernels after the camera's upload: all that a recorded frame replays.
  void launchFrame(const FramePlan& plan, StageTimer* timer);
  // Throws a one-line Error when the frame buffers for rs would not fit the budget.
  void checkFrameBudget(const RenderSettings& rs) const;
  // BLEND: whether frames render to the float film for it (the whole scene's
  // BLEND under a split), and whether this renderer runs its passes.
  bool blendFilm() const { return split_ ? split_->sceneBlends() : scene_.hasBlend; }
  bool blendPasses() const { return split_ ? split_->blendsHere() : scene_.hasBlend; }

  uint64_t budget_;  // before scene_: the upload is checked against it
  // The caller's host Scene, alive while it renders: on the same budget.
  uint64_t hostSceneBytes_ = 0;
  uint64_t perVertexBytes_ = 0;  // vertex-stage buffers, per drawn vertex (worst case)
  DeviceScene scene_;
  std::vector<Texture> hostTextures_;  // kept to build mipmaps when first needed
  FrameBuffers frame_;
  DView<LightGPU> lights_;
  // The glTF shading's environment, filtered once per file (RenderSettings::environment).
  EnvironmentGPU env_;
  std::string envLoaded_;
  bool envIsLoaded_ = false;
  std::vector<DirectionalLight> uploadedLights_;
  FramePlan plan_;  // the last frame's decisions
  uint32_t autoFrames_ = 0;
  uint32_t frameNumber_ = 0;  // FrameUniforms::frame of the last frame
  std::vector<mat4f> upload_;  // the frame's upload (FrameUniforms, draws' MVPs), host side
  // The counters' copy in host memory the device writes directly (page-locked
  // on GPUs), read by lastFrameFit: an asynchronous copy and a wait on the
  // instance, instead of a staged copy between two waits on the whole device.
  // After takeKeys() the caller's pass writes them there itself
  // (FrameKeys::publish), and lastFrameFit only waits (countersPublished_).
  Kokkos::View<uint32_t*, PinnedSpace> countersHost_;
  bool countersPublished_ = false;
  void hostCounters();  // countersHost_ sized to the counters
  bool supersampling_ = false;
  bool blendFallback_ = false;  // the tile lists would exceed the budget: kbuffer, weighted's sums (lastFrameFit)
  uint64_t blendNeed_ = 0;      // BLEND fragments the last exact or sorted frame composited  // inside renderSupersampled: passes shade to the film, no post chain
  std::unique_ptr<FrameGraphs> graphs_;  // recorded frames, per settings (backends/frame_graphs.h)

  AutoStats autoStats_;  // what `auto` decides from (frame_plan.h)
  FrameSplit* split_ = nullptr;
};

}  // namespace rast
