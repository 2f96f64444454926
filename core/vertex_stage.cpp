// Vertex stage: per-draw model-view-projection matrices, then every drawn vertex
// to clip space (and to world space when the shading needs positions/normals).
// Each vertex is also snapped to window space here, once, rather than once per
// triangle that uses it (about six in a closed mesh) in the setup.
#include "raster_common.h"
#include "stages.h"

namespace rast {
namespace {

// MVP = viewProj * model in double, rounded to float once: the same matrix
// glref hands OpenGL. Plain products and sums (device code is built without
// FMA contraction), so the host and every device compute the same bits.
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

struct DrawMatrices {
  DView<DrawGPU> draws;
  DView<mat4f> mvp;
  mat4d vp;

  KOKKOS_INLINE_FUNCTION void operator()(const int d) const { mvp(d) = drawMvp(vp, draws(d).model); }
};

// A scene of one draw gets its matrix computed on the host and passed in the
// vertex kernel's arguments: one launch fewer, which on a GPU is worth more
// than 16 products. (Not an array of a few: indexed by the draw, a kernel
// argument is copied to each thread's local memory, which on the H100 tripled
// the vertex stage of every scene.)

template <bool kWorld>
struct TransformVertices {
  DView<DrawGPU> draws;
  DView<uint32_t> drawVertStart;
  uint32_t numDraws;
  DView<mat4f> mvp;
  mat4f argMvp;  // used instead of mvp when numDraws == 1
  DView<float3> positions, normals;
  DView<float4> clip;
  DView<SnapVert> snap;
  DView<float3> worldPos, worldNormal;
  Viewport vp;
  float gx, gy;

  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t v) const {
    const uint32_t d = findRange(drawVertStart, numDraws, v);
    const DrawGPU& dr = draws(d);
    const uint32_t src = dr.srcVertex + (v - dr.dstVertex);
    const float3 p = positions(src);
    const float4 c = numDraws == 1 ? mul(argMvp, p) : mul(mvp(d), p);
    clip(v) = c;
    snap(v) = snapOrFlag(c, vp, gx, gy);
    if (kWorld) {
      mat4f model;
      for (int k = 0; k < 16; ++k) model.m[k] = float(dr.model.m[k]);
      worldPos(v) = mulPoint(model, p);
      worldNormal(v) = normalize(mul(dr.normalMatrix, normals(src)));
    }
  }
};

}  // namespace

void vertexStage(const DeviceScene& s, FrameBuffers& f, const mat4d& viewProj, bool needWorld) {
  ensureCapacity(f.mvp, "frame.mvp", s.numDraws);
  ensureCapacity(f.clip, "frame.clip", s.numVerts);
  ensureCapacity(f.snap, "frame.snap", s.numVerts);
  const float gx = guardBand(f.vp.width), gy = guardBand(f.vp.height);
  mat4f arg{};
  if (s.numDraws == 1)
    arg = drawMvp(viewProj, s.hostModels[0]);
  else
    Kokkos::parallel_for("rast::vertex::draw_matrices", Range(0, s.numDraws), DrawMatrices{s.draws, f.mvp, viewProj});
  using Policy = Kokkos::RangePolicy<Exec, Kokkos::IndexType<uint32_t>>;
  if (needWorld) {
    ensureCapacity(f.worldPos, "frame.worldPos", s.numVerts);
    ensureCapacity(f.worldNormal, "frame.worldNormal", s.numVerts);
    Kokkos::parallel_for("rast::vertex::transform", lightweight(Policy(0, s.numVerts)),
                         TransformVertices<true>{s.draws, s.drawVertStart, s.numDraws, f.mvp, arg, s.positions, s.normals,
                                                 f.clip, f.snap, f.worldPos, f.worldNormal, f.vp, gx, gy});
  } else {
    Kokkos::parallel_for("rast::vertex::transform", lightweight(Policy(0, s.numVerts)),
                         TransformVertices<false>{s.draws, s.drawVertStart, s.numDraws, f.mvp, arg, s.positions, s.normals,
                                                  f.clip, f.snap, f.worldPos, f.worldNormal, f.vp, gx, gy});
  }
}

}  // namespace rast
