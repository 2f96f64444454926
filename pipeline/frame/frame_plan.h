// One frame's decisions, made once and read by every stage (as cudaraster hands
// one CRParams from stage to stage). A user's choice (--raster, --aa, polygon
// mode, outputs) and the previous frame's statistics become the method, its
// options (occluders, row lanes, block numbering and tags), the sample count,
// the shading path (per pixel, CPU spans, or fused with the binned raster),
// the point/line pass and the shading parameters; the frame's launches depend
// on nothing else besides device memory, so the plan's key is also the key
// under which a recorded frame is replayed (backends/frame_graphs.h).
//
// To add a raster method: a file in pipeline/raster/, an enumerator in
// RasterMethod (host/settings/render_settings.h), a case in Renderer::launchFrame's
// switch and in chooseMethod below (the compiler warns of a missing case).
#pragma once

#include "pipeline/blend/blend.h"
#include "pipeline/geometry/geometry.h"

#include "pipeline/cpu/cpu_shade.h"
#include "pipeline/data/device_scene.h"
#include "pipeline/data/frame_buffers.h"
#include "pipeline/data/line_pass.h"
#include "pipeline/shade/shade.h"
#include "host/settings/render_settings.h"

#include <cstdint>
#include <string>

namespace rast {

// What `auto` decides from: statistics of a previous frame's raster triangles
// (read with the counters after a frame, so no extra round trip).
struct AutoStats {
  bool valid = false;
  uint64_t sumArea = 0, maxArea = 0;
  uint32_t tris = 0;
  uint64_t occArea = 0;  // summed area of the occluder candidates (rasterStatistics)
};

// How the frame's pixels are shaded.
enum class ShadePath {
  Pixels,       // the per-pixel kernel (every backend; clears the keys behind it)
  Spans,        // the CPU's span kernel (host backends)
  FusedBinned,  // shaded per tile inside the binned raster (host backends); no keys written
  None,         // not shaded: the keys are the frame's output (RenderSettings::keysOnly)
};

struct FramePlan {
  RasterMethod method = RasterMethod::VisBuffer;  // never Auto: auto's choice
  bool autoStats = false;     // the raster statistics pass runs (auto, every kAutoStatsEvery frames)
  int samples = 1;            // coverage samples per pixel (MSAA; 1 in each supersampling pass)
  bool fill = true;           // triangles filled (polygon mode fill), else only edges or corners
  CullFaces cull = CullFaces::None;  // back faces the setup culls
  bool occluders = false;     // the visbuffer's occluder pass (raster_visbuffer.cpp)
  bool rowLanes = false;      // the visbuffer raster's block rows on lanes (RasterBlockRows)
  bool numberBlocks = false;  // the setup numbers the visbuffer's work items
  bool tagsBlocks = false;    // the raster tags the 8x8 blocks it wrote (ShadeParams::blockFrames)
  bool needWorld = false;     // the vertex stage writes world positions and normals
  bool film = false;          // shading writes the float film (post passes, HDR output, supersampling)
  ShadePath shade = ShadePath::Pixels;
  LinePass lines;             // the point/line pass
  ShadeParams shadeParams{};
  BlendPlan blend;            // MASK and BLEND passes (pipeline/blend/)
  std::string key;            // every value the launches depend on (frame graphs)
};

// The raster method for rs given the statistics of earlier frames (auto), by
// kind of machine (backends/tuning.h).
RasterMethod chooseMethod(const RenderSettings& rs, const AutoStats& stats);

// Everything besides rs that a plan depends on.
struct PlanInputs {
  const DeviceScene* scene = nullptr;
  const FrameBuffers* frame = nullptr;  // prepared for rs (viewport, uniforms)
  AutoStats stats;
  bool statsDue = false;       // auto: this frame runs the statistics pass
  bool supersampling = false;  // a pass of a supersampled frame: film, no post chain
  bool blendFallback = false;  // the tile lists would exceed the memory budget (chooseTransparency, walksTileLists)
  bool keepKeys = false;       // a split frame (renderer.h): keys are exchanged before shading, never fused
  // BLEND (renderer.h): this renderer runs the passes; frames render to the
  // film for them (under a split, on every part when the whole scene blends).
  bool blendPasses = false, blendFilm = false;
};

// The transparency method a frame uses (never Auto): `auto` takes exact (the
// fragment store sized to the frame's need), and kbuffer once the store
// would exceed the memory budget; so do exact and sorted.
Transparency chooseTransparency(const RenderSettings& rs, bool fallback);

FramePlan planFrame(const RenderSettings& rs, const PlanInputs& in);

}  // namespace rast
