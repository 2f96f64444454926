// Vertex stage: per-draw model-view-projection matrices, then every drawn vertex
// to clip space (and to world space when the shading needs positions/normals).
// Each vertex is also snapped to window space here, once, rather than once per
// triangle that uses it (about six in a closed mesh) in the setup.
#include "raster_common.h"
#include "stages.h"

#include <type_traits>

namespace rast {
namespace {

// The view-projection comes from device memory (the frame's uploaded
// uniforms), so that this launch is the same whatever the camera.
struct DrawMatrices {
  DView<DrawGPU> draws;
  DView<mat4f> mvp;
  DView<FrameUniforms> frame;

  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t d) const { mvp(d) = drawMvp(frame(0).viewProj, draws(d).model); }
};

template <bool kWorld>
struct TransformVertices {
  DView<DrawGPU> draws;
  DView<uint32_t> drawVertStart;
  DView<DrawIndex> vertDraw;  // DeviceScene::vertDraw (empty: search drawVertStart)
  uint32_t numDraws;
  DView<mat4f> mvp;
  DView<float3> positions, normals;
  DView<float4> clip;
  DView<SnapVert> snap;
  DView<float3> worldPos, worldNormal;
  Viewport vp;
  float gx, gy;
  DView<FrameUniforms> frame;
  uint32_t* uploadSeen;  // FrameBuffers::uploadSeen (GPUs)

  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t v) const {
    // The upload this frame read is out of the staging buffer (the copy came
    // before this kernel): the host may refill it (backends/backend_cuda.cpp).
    if (v == 0 && uploadSeen) *uploadSeen = frame(0).frame;
    const uint32_t d = drawOf(vertDraw, drawVertStart, numDraws, v);
    const DrawGPU& dr = draws(d);
    const uint32_t src = dr.srcVertex + (v - dr.dstVertex);
    const float3 p = positions(src);
    const float4 c = mul(mvp(d), p);
    clip(v) = c;
    snap(v) = snapOrFlag(c, vp, gx, gy);
    if (kWorld) {
      worldPos(v) = mulPoint(dr.modelF, p);
      worldNormal(v) = normalize(mul(dr.normalMatrix, normals(src)));
    }
  }
};

// The host backends' vertex stage: a work item takes kHostVertexChunk
// consecutive vertices and walks the draws they belong to, so that the draw
// lookup (a binary search) and its matrices are fetched once per draw and
// chunk rather than once per vertex. The same arithmetic per vertex.
constexpr uint32_t kHostVertexChunk = 1024;
template <bool kWorld>
struct TransformVerticesHost {
  TransformVertices<kWorld> t;
  uint32_t numVerts;

  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t chunk) const {
    const uint32_t v0 = chunk * kHostVertexChunk;
    const uint32_t v1 = v0 + kHostVertexChunk < numVerts ? v0 + kHostVertexChunk : numVerts;
    uint32_t d = findRange(t.drawVertStart, t.numDraws, v0);  // the draw of v0; later draws in order
    for (uint32_t v = v0; v < v1; ++d) {
      const uint32_t next = d + 1 < t.numDraws ? t.drawVertStart(d + 1) : v1;
      const uint32_t end = next < v1 ? next : v1;
      if (v >= end) continue;  // a draw without vertices
      const DrawGPU& dr = t.draws(d);
      const mat4f m = t.mvp(d);
      const mat4f model = dr.modelF;
      for (; v < end; ++v) {  // TransformVertices::operator()'s arithmetic
        const uint32_t src = dr.srcVertex + (v - dr.dstVertex);
        const float3 p = t.positions(src);
        const float4 c = mul(m, p);
        t.clip(v) = c;
        t.snap(v) = snapOrFlag(c, t.vp, t.gx, t.gy);
        if (kWorld) {
          t.worldPos(v) = mulPoint(model, p);
          t.worldNormal(v) = normalize(mul(dr.normalMatrix, t.normals(src)));
        }
      }
    }
  }
};

// Launches the vertex transform: per vertex on GPUs, per chunk of vertices on
// host backends (not built for GPUs).
template <bool kHost, bool kWorld>
void launchTransform(const TransformVertices<kWorld>& t, uint32_t numVerts) {
  if constexpr (kHost) {
    using Host = std::conditional_t<kHost, TransformVerticesHost<kWorld>, void>;  // dependent: not built for GPUs
    const uint32_t chunks = (numVerts + kHostVertexChunk - 1) / kHostVertexChunk;
    Kokkos::parallel_for("rast::vertex::transform", Kokkos::RangePolicy<Exec, Kokkos::IndexType<uint32_t>>(0, chunks),
                         Host{t, numVerts});
  } else {
    Kokkos::parallel_for("rast::vertex::transform",
                         lightweight(Kokkos::RangePolicy<Exec, Kokkos::IndexType<uint32_t>>(0, numVerts)), t);
  }
}

}  // namespace

void vertexStage(const DeviceScene& s, FrameBuffers& f, bool needWorld) {
  if (!s.hostMvps())  // else uploaded with the camera (Renderer::enqueue)
    Kokkos::parallel_for("rast::vertex::draw_matrices",
                         lightweight(Kokkos::RangePolicy<Exec, Kokkos::IndexType<uint32_t>>(0, s.numDraws)),
                         DrawMatrices{s.draws, f.mvp, f.uniforms});
  ensureCapacity(f.clip, "frame.clip", s.numVerts);
  ensureCapacity(f.snap, "frame.snap", s.numVerts);
  const float gx = guardBand(f.vp.width), gy = guardBand(f.vp.height);
  if (needWorld) {
    ensureCapacity(f.worldPos, "frame.worldPos", s.numVerts);
    ensureCapacity(f.worldNormal, "frame.worldNormal", s.numVerts);
    launchTransform<!kOnDevice>(TransformVertices<true>{s.draws, s.drawVertStart, s.vertDraw, s.numDraws, f.mvp, s.positions,
                                                        s.normals, f.clip, f.snap, f.worldPos, f.worldNormal, f.vp, gx, gy,
                                                        f.uniforms, f.uploadSeen},
                                s.numVerts);
  } else {
    launchTransform<!kOnDevice>(TransformVertices<false>{s.draws, s.drawVertStart, s.vertDraw, s.numDraws, f.mvp, s.positions,
                                                         s.normals, f.clip, f.snap, f.worldPos, f.worldNormal, f.vp, gx, gy,
                                                         f.uniforms, f.uploadSeen},
                                s.numVerts);
  }
}

}  // namespace rast
