// Per-frame device buffers, reused across frames and grown (never capped) when a
// frame needs more; and the entry points of the pipeline stages.
#pragma once

#include "pipeline/data/device.h"
#include "pipeline/data/device_scene.h"
#include "pipeline/data/gpu_types.h"
#include "pipeline/data/post_buffers.h"
#include "pipeline/data/blend_buffers.h"
#include "pipeline/data/line_pass.h"

namespace rast {

// Slots of FrameBuffers::counters, written on the device during a frame and
// read back only after it (to grow buffers and report statistics).
enum Counter : int {
  kRasterTris = 0,  // raster triangles the setup produced (may exceed the capacity)
  kRasterWork = 1,  // work items of the raster method (chunks, bin entries, ...)
  kSetupDone = 2,   // setup: chunk tickets drawn, or count-pass teams finished (back to 0 by the last; primitive_setup.cpp)
  kNumCounters = 4
};

// The camera's values that the frame's kernels read, copied to device memory
// at the start of each frame (FrameGraphs::run's upload) instead of travelling
// as kernel arguments: every launch of the frame is then the same from one
// frame to the next, and a GPU can replay them as one recorded unit
// (backends/frame_graphs.h) while the camera moves.
struct FrameCamera {
  float3 eye;
  float znear, zfar;  // for the depth visualisation
  mat4f view;         // world -> view space (SSAO's geometry)
};
struct FrameUniforms {
  mat4d viewProj;  // the draws' matrices are computed from it (on the device beyond kHostMatricesMaxDraws)
  FrameCamera camera;
  uint32_t frame;  // counts the renderer's frames (from 1): tags the blocks a frame wrote (RasterBlocks)
};

// The upload's layout, in mat4f slots: FrameUniforms, then one MVP per draw.
constexpr size_t kUniformSlots = (sizeof(FrameUniforms) + sizeof(mat4f) - 1) / sizeof(mat4f);

// In the order the stages hand data on: each group is written by the stage
// named in its heading and read by the ones after it.
struct FrameBuffers {
  Viewport vp{0, 0, SamplePattern{}};
  DView<uint32_t> counters;  // sizes only the device knows (Counter), read back after a frame

  // upload (the camera) and the vertex stage
  DView<mat4f> uploaded;     // what a frame uploads: kUniformSlots of FrameUniforms, then the draws' MVPs
  DView<FrameUniforms> uniforms; // one: this frame's camera (in `uploaded`)
  uint32_t* uploadSeen = nullptr; // host memory the vertex stage tells the frame number it read (FrameGraphs::uploadSeen), or null
  DView<mat4f> mvp;          // per draw: model-view-projection (in `uploaded`)
  DView<float4> clip;        // per drawn vertex
  DView<SnapVert> snap;      // per drawn vertex: window position, or why it needs clipping
  DView<float3> worldPos;    // per drawn vertex, only when shading needs it
  DView<float3> worldNormal; // per drawn vertex, only when shading needs it

  // primitive setup
  DView<uint32_t> chunkOffset; // per chunk of drawn triangles (GPUs): raster triangles, then their exclusive prefix sum
  DView<uint32_t> chunkBlocks; // per chunk of drawn triangles (GPUs, after a count pass): the visbuffer's first work item
  DView<uint64_t> setupStatus; // per chunk of drawn triangles (GPUs with few chunks, hosts): the setup's look-back status, tagged by frame
  DView<uint8_t> clipCount;    // per drawn triangle that needs clipping: its raster triangles (GPUs: setup's count -> write)
  DView<uint32_t> clipBlocks;  // the same triangles' visbuffer work items (GPUs, count pass -> write)
  DView<RasterTri> tris;     // raster triangles

  // raster: work lists, visbuffer block state, the visibility buffer
  DView<uint32_t> workOffset;  // per raster triangle, for methods that expand work (visbuffer: its first item)
  DView<uint64_t> workHint;    // visbuffer: the raster triangle of every kWorkHintItems-th item, tagged by frame (pipeline/rules/visbuffer_blocks.h)
  DView<uint32_t> blockDepth;  // visbuffer method: per 8x8 block, a bound on its pixels' depth
  DView<uint32_t> blockFrame;  // visbuffer and naive methods: per 8x8 block, the last frame (FrameUniforms::frame) that wrote a key in it
  DView<uint64_t> occCount;    // visbuffer: the setup's occluder list (OccluderList, pipeline/rules/visbuffer_blocks.h): blocks << 32 | candidates; one word, zeroed by the raster
  DView<uint32_t> occStart, occTri;  // per occluder candidate: its first block in the list, its raster triangle
  DView<uint32_t> work;        // method-specific work list (bin entries)
  DView<uint32_t> tileStart;   // binned method: first list entry of each tile
  DView<uint64_t> vis;       // per pixel: depth and raster triangle (see visKey)
  // Whether every key of `vis` holds kClearKey once the kernels queued so far
  // have run: the per-pixel shade kernel clears each key after reading it, so
  // the next frame needs no clearing pass (on the H100 that pass cost 0.012 ms
  // at 1080p, the write folded into shading costs less). Host-side bookkeeping
  // only: a new allocation and every raster pass make it false.
  bool visClear = false;
  Kokkos::View<uint64_t, Mem> sumArea, maxArea, occArea;  // raster statistics for RasterMethod::Auto
  LineFrame lines;           // the point/line pass (pipeline/raster/raster_lines.h)
  BlendBuffers blend;        // MASK and BLEND passes (pipeline/blend/), only for scenes that have them

  // shade: colour and the AOVs; post: the film
  DView<uint32_t> color;     // per pixel: sRGB RGBA8
  DView<float4> accum;       // per pixel: linear colour sum of supersampling passes
  PostBuffers post;          // the float film and the post passes' buffers, only when used
  DView<float> depth;        // AOV, allocated on request
  DView<uint32_t> primId;    // AOV, allocated on request
  DView<float3> normal;      // AOV, allocated on request
  Kokkos::View<Kokkos::MinMaxScalar<float>, Mem> depthRange;  // depth visualisation only

  // Capacities chosen by the host; the device writes nothing past them and
  // reports the sizes it needed in `counters`.
  uint32_t triCapacity = 0, workCapacity = 0;

  size_t bytes() const;
};

}  // namespace rast
