// The pipeline stages, in frame order. Each enqueues named Kokkos kernels on
// rast::Exec and returns without waiting for them.
//
//   vertexStage      model-view-projection of every drawn vertex
//   primitiveSetup   index fetch, clipping, culling, snapping -> RasterTri list
//   raster*          coverage + depth test -> visibility buffer (one per method)
//   shadeStage       perspective-correct attributes, texturing, lighting -> colour
#pragma once

#include "frame_buffers.h"
#include "render_settings.h"

namespace rast {

// Exclusive prefix sum of data[0, n) in place; the total goes to counters(slot)
// on the device.
void scanExclusive(const char* label, const DView<uint32_t>& data, uint32_t n, const DView<uint32_t>& counters,
                   int slot);

// Every draw's model-view-projection matrix from f.uniforms into f.mvp (unless
// the host uploaded them: kHostMatricesMaxDraws), then every drawn vertex
// through it.
void vertexStage(const DeviceScene& s, FrameBuffers& f, bool needWorld);

// MVP = viewProj * model in double, rounded to float once: the same matrix
// glref hands OpenGL. Plain products and sums (built without FMA contraction,
// CMakeLists.txt), so the host and every device compute the same bits.
KOKKOS_INLINE_FUNCTION mat4f drawMvp(const mat4d& vp, const mat4d& m) {
  mat4f out;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) {
      double acc = 0.0;
      for (int k = 0; k < 4; ++k) acc += vp.m[k * 4 + r] * m.m[c * 4 + k];
      out.m[c * 4 + r] = float(acc);
    }
  return out;
}

// Writes f.tris (up to f.triCapacity) and f.counters(kRasterTris); with
// numberBlocks, also the visbuffer method's work items (f.workOffset,
// f.chunkBlocks, f.counters(kRasterWork); primitive_setup.cpp).
void primitiveSetup(const DeviceScene& s, FrameBuffers& f, bool cullBack, bool numberBlocks, bool occluders);

// Tests: from now on a host backend sets up primitives as a GPU does
// (primitive_setup.cpp's WriteChunks: a team per chunk, here of teamSize
// threads; the look-back for few chunks, a count pass for more), so that the
// GPU's setup runs, and can hang or fail, on the CPU too; 0 restores the
// host's own. Images must not change (tests/test_cpu_paths.cpp). GPUs ignore it.
void setGpuSetupOnHostForTests(int teamSize);
// Tests: the host's setup (primitive_setup.cpp's SetupChunksHost) stages at
// most `staged` raster triangles a chunk before it writes the rest directly
// (0: as many as it has room for), and copies them with streaming stores
// (stream > 0), plain ones (< 0) or as the scene's size decides (0). Images
// must not change. GPUs ignore it.
void setHostSetupForTests(int staged, int stream);

// Tests: true makes the per-pixel shade kernel take its general form for
// every frame, including the lit frames that normally take the kernel
// compiled for lit shading alone (shade_fragment.h, Shade::litOnly), so that
// the two can be compared; false restores the choice. Images must not change.
void setGeneralShadeForTests(bool general);
// The visbuffer raster's layout for tests: 1 a block's rows on lanes
// (RasterBlockRows) on any backend, -1 never, 0 as the renderer decides.
void setRowLanesForTests(int mode);
int rowLanesForTests();

void clearVisibility(FrameBuffers& f);

// Raster methods: each reads f.tris / f.counters(kRasterTris) and min-combines
// visKey values into f.vis. All produce bit-identical visibility buffers.
void rasterNaive(FrameBuffers& f);
// occluders: large triangles first lower the depth bounds of the blocks they
// cover whole (raster_visbuffer.cpp), for frames of high depth complexity;
// the setup must have been told too (primitiveSetup). rowLanes: a block's
// rows on consecutive lanes (RasterBlockRows), for frames of large triangles
// (Renderer::useRowLanes); the same keys either way.
void rasterVisBuffer(FrameBuffers& f, bool occluders, bool rowLanes = false);
void rasterBinned(FrameBuffers& f);  // writes every pixel: needs no clearVisibility

// Cheap statistics of the raster triangles (sum and maximum of their pixel
// bounding-box areas, and the summed area of the occluder candidates) into
// f.sumArea / f.maxArea / f.occArea, for choosing a method.
void rasterStatistics(FrameBuffers& f);

struct LightGPU {
  float3 direction;  // normalised, towards the light
  float intensity;
};

struct ShadeParams {
  ShadingMode mode;
  TexFilter filter;
  DView<FrameUniforms> frame;  // the camera's eye, view, near and far: FrameBuffers::uniforms
  float ambient, specular, shininess;
  float4 background;
  uint32_t backgroundPacked;  // sRGB RGBA8, encoded once on the host
  int32_t headlight;  // 1: one light at the eye, per fragment
  int32_t wantDepth, wantPrimId, wantNormals;
  int32_t perspective;  // 0: affine interpolation (for comparison only)
  // The float film (core/post/): shading writes linear colour to f.post.hdr
  // instead of packing RGBA8, and with wantGeom view-space normal and depth
  // to f.post.geom for every pixel.
  int32_t floatOut, wantGeom;
  float4 backgroundFilm;  // the background as the film holds it
  int32_t shadeRun;       // pixels per shading work item along a row; 0: the backend's kShadeRun
  // Only the visbuffer or naive raster wrote keys this frame, one sample per pixel:
  // an 8x8 block whose FrameBuffers::blockFrame is not this frame's holds
  // only clear keys, and the GPU's shading skips reading them.
  int32_t blockFrames;
};

void shadeStage(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights);

// The binned raster and the shade stage in one pass on host backends: each
// tile is shaded as soon as its triangles are depth-tested, from the tile's
// depth and ids in cache, and no visibility buffer is written (f.vis is left
// as it was). Same ids, depth and colours as rasterBinned + shadeStage.
// Usable where the span kernel covers the frame and no points or lines are
// drawn afterwards into the visibility buffer.
bool fusedBinnedShadeUsable(const FrameBuffers& f, const ShadeParams& p, bool linesOrPoints);
void rasterBinnedShaded(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights);

// Supersampling by accumulation in float: add the pass's film (f.post.hdr)
// into f.accum, then put the average back in the film (encoded by the post
// chain's encoder).
void accumulateColor(FrameBuffers& f, bool first);
void resolveAccumulated(FrameBuffers& f, int passes);

// The standard D3D/Vulkan sample positions for 1, 2, 4 or 8 samples (y up).
SamplePattern samplePattern(int count);

}  // namespace rast
