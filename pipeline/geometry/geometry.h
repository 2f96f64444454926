// The geometry stages' front: the vertex stage (every drawn vertex through its
// draw's matrix) and the primitive setup (index fetch, homogeneous clipping,
// culling and snapping into raster triangles). Each enqueues named Kokkos
// kernels (rast::vertex::..., rast::setup::...) on rast::Exec and returns
// without waiting.
#pragma once

#include "pipeline/data/frame_buffers.h"

namespace rast {

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
// f.chunkBlocks, f.counters(kRasterWork); primitive_setup.cpp). With blend
// (a frame with BLEND triangles), where setupNumbersBlendItems, also the BLEND
// class's work items (f.blend.blendStart, f.blend.totals(kBlendItems)) and the
// frame's other BLEND totals cleared: the alpha classes' scan is then not run
// for that class (alphaWorkLists).
// Which back faces the setup culls: none, all (--cull back), or those of
// single-sided materials (the glTF model, --shading pbr).
enum class CullFaces : int32_t { None = 0, All = 1, SingleSided = 2 };
void primitiveSetup(const DeviceScene& s, FrameBuffers& f, CullFaces cull, bool numberBlocks, bool occluders,
                    bool blend);

// Whether the setup of a scene of numTris drawn triangles numbers the BLEND
// class's work items in its single-pass scan: where it runs one (GPUs, and
// TestHooks::gpuSetupOnHostTeam), for up to kSetupLookBackMaxChunks chunks.
bool setupNumbersBlendItems(uint32_t numTris);

}  // namespace rast
