// Vertex stage: per-draw model-view-projection matrices, then every drawn vertex
// to clip space (and to world space when the shading needs positions/normals).
// Each vertex is also snapped to window space here, once, rather than once per
// triangle that uses it (about six in a closed mesh) in the setup. Skinned
// draws (docs/animation.md) blend their joints' matrices first, in kernels
// instantiated only for scenes that have skins.
#include "backends/cpu_clones.h"
#include "pipeline/rules/raster_rules.h"
#include "pipeline/geometry/geometry.h"

#include <cstring>
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

// Linear blend skinning of one vertex (glTF 2.0, 3.7.3): its joints'
// matrices and normal matrices blended by its weights, Σ w · J, in a fixed
// order without contraction, then the position and normal through the
// blend, so every backend gives the same bits. Weights of 0 are skipped
// (their joint may be any index). kNormals: the draw's normals are needed
// (world outputs), else they are not blended.
template <bool kNormals = true>
KOKKOS_INLINE_FUNCTION void skinVertex(const DrawGPU& dr, uint32_t local, const uint16_t* sj, const float* sw, const mat4f* joints,
                                       const mat3f* normals, float3& p, float3& n) {
  const uint32_t k0 = dr.skinVertex + local * 4 * dr.skinSets;
  mat4f m;
  mat3f nm;
  for (int c = 0; c < 16; ++c) m.m[c] = 0.0f;
  for (int c = 0; c < 9; ++c) nm.m[c] = 0.0f;
  for (uint32_t k = 0; k < 4 * dr.skinSets; ++k) {
    const float w = sw[k0 + k];
    if (w == 0.0f) continue;
    const uint32_t j = uint32_t(dr.skinJoint) + sj[k0 + k];
    const mat4f& J = joints[j];
    for (int c = 0; c < 4; ++c)  // the three rows mulPoint reads, column by column
      for (int r = 0; r < 3; ++r) m.m[c * 4 + r] = m.m[c * 4 + r] + w * J.m[c * 4 + r];
    if constexpr (kNormals) {
      const mat3f& N = normals[j];
      for (int c = 0; c < 9; ++c) nm.m[c] = nm.m[c] + w * N.m[c];
    }
  }
  m.m[15] = 1.0f;
  p = mulPoint(m, p);
  if constexpr (kNormals) n = mul(nm, n);
}

template <bool kWorld, bool kSkin = false>
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
  // Skins (kSkin only: scenes without skins do not read them).
  DView<uint16_t> skinJoints;
  DView<float> skinWeights;
  DView<mat4f> joints;
  DView<mat3f> jointNormals;

  KOKKOS_INLINE_FUNCTION void operator()(const uint32_t v) const {
    // The upload this frame read is out of the staging buffer (the copy came
    // before this kernel): the host may refill it (backends/backend_cuda.cpp).
    if (v == 0 && uploadSeen) *uploadSeen = frame(0).frame;
    one(v, drawOf(vertDraw, drawVertStart, numDraws, v));
  }

  // Drawn vertex v of draw d.
  KOKKOS_INLINE_FUNCTION void one(const uint32_t v, const uint32_t d) const {
    const DrawGPU& dr = draws(d);
    const uint32_t src = dr.srcVertex + (v - dr.dstVertex);
    float3 p = positions(src);
    float3 n{0.0f, 0.0f, 0.0f};
    if (kWorld) n = normals(src);
    if (kSkin && dr.skinJoint >= 0)  // in the world: the draw's model is the identity
      skinVertex<kWorld>(dr, v - dr.dstVertex, skinJoints.data(), skinWeights.data(), joints.data(), jointNormals.data(), p, n);
    const float4 c = mul(mvp(d), p);
    clip(v) = c;
    snap(v) = snapOrFlag(c, vp, gx, gy);
    if (kWorld) {
      worldPos(v) = mulPoint(dr.modelF, p);
      worldNormal(v) = normalize(mul(dr.normalMatrix, n));
    }
  }
};

}  // namespace

// One draw's run of vertices [v, end) on a host backend: the arithmetic of
// TransformVertices::operator(), compiled also for AVX-512 and AVX2 and picked
// at load time (backends/cpu_clones.h). The baseline x86-64 build has no
// rounding instruction, and the four floors of each vertex's snapping
// (fineCoord) made the stage 8.4 ms for tiny's 500,000 vertices (2 cores);
// with the wide variants it took 4.25. Same IEEE operations (no
// contraction), so the same bits. Outside the anonymous namespace: a GPU
// build, which never calls it, would warn of an unused internal function.
struct VertexRun {
  const float3* positions;
  const float3* normals;
  float4* clip;
  SnapVert* snap;
  float3* worldPos;    // null: no world-space outputs
  float3* worldNormal;
  mat4f mvp, model;
  mat3f normalMatrix;
  Viewport vp;
  float gx, gy;
};
RAST_CPU_CLONES void transformRun(const VertexRun& r, uint32_t src0, uint32_t v0, uint32_t end) {
  for (uint32_t v = v0, src = src0; v < end; ++v, ++src) {
    const float3 p = r.positions[src];
    const float4 c = mul(r.mvp, p);
    r.clip[v] = c;
    r.snap[v] = snapOrFlag(c, r.vp, r.gx, r.gy);
  }
  if (!r.worldPos) return;
  for (uint32_t v = v0, src = src0; v < end; ++v, ++src) {
    r.worldPos[v] = mulPoint(r.model, r.positions[src]);
    r.worldNormal[v] = normalize(mul(r.normalMatrix, r.normals[src]));
  }
}

// A skinned draw's run of vertices [v, end) on a host backend: the arithmetic
// of TransformVertices::one() with skins (the same bits), cloned for AVX-512
// and AVX2 as transformRun is, the draw's fields read once.
struct SkinRun {
  VertexRun base;
  DrawGPU draw;
  const uint16_t* joints;
  const float* weights;
  const mat4f* palette;
  const mat3f* paletteNormals;
};
#if defined(__GNUC__) && !defined(__CUDACC__) && !defined(__HIPCC__)
// skinVertex on the host's vector units (GCC/Clang vector extensions, eight
// floats a value: one AVX2 register, two SSE2 ones): a joint's matrix is
// blended as sixteen contiguous floats, its normal matrix as eight and one,
// instead of element by element (GCC keeps the blend in scalar registers
// otherwise). The last row, which mulPoint does not read, is blended too;
// every element read is the same multiply and add as skinVertex's, so the
// same bits.
template <bool kNormals>
inline void skinVertexHost(const DrawGPU& dr, uint32_t local, const uint16_t* sj, const float* sw, const mat4f* joints,
                           const mat3f* normals, float3& p, float3& n) {
  typedef float Lanes __attribute__((vector_size(32)));
  const uint32_t k0 = dr.skinVertex + local * 4 * dr.skinSets;
  Lanes m0 = {}, m1 = {}, n0 = {};
  float n8 = 0.0f;
  for (uint32_t k = 0; k < 4 * dr.skinSets; ++k) {
    const float w = sw[k0 + k];
    if (w == 0.0f) continue;
    const uint32_t j = uint32_t(dr.skinJoint) + sj[k0 + k];
    Lanes a, b;
    std::memcpy(&a, joints[j].m, sizeof(Lanes));
    std::memcpy(&b, joints[j].m + 8, sizeof(Lanes));
    m0 = m0 + w * a;
    m1 = m1 + w * b;
    if constexpr (kNormals) {
      std::memcpy(&a, normals[j].m, sizeof(Lanes));
      n0 = n0 + w * a;
      n8 = n8 + w * normals[j].m[8];
    }
  }
  mat4f m;
  std::memcpy(m.m, &m0, sizeof(Lanes));
  std::memcpy(m.m + 8, &m1, sizeof(Lanes));
  m.m[15] = 1.0f;
  p = mulPoint(m, p);
  if constexpr (kNormals) {
    mat3f nm;
    std::memcpy(nm.m, &n0, sizeof(Lanes));
    nm.m[8] = n8;
    n = mul(nm, n);
  }
}
#else
template <bool kNormals>
KOKKOS_INLINE_FUNCTION void skinVertexHost(const DrawGPU& dr, uint32_t local, const uint16_t* sj, const float* sw,
                                           const mat4f* joints, const mat3f* normals, float3& p, float3& n) {
  skinVertex<kNormals>(dr, local, sj, sw, joints, normals, p, n);
}
#endif

RAST_CPU_CLONES void skinnedRun(const SkinRun& s, uint32_t src0, uint32_t v0, uint32_t end) {
  const VertexRun& r = s.base;
  if (!r.worldPos) {  // clip space only: the normals are not blended
    for (uint32_t v = v0, src = src0; v < end; ++v, ++src) {
      float3 p = r.positions[src], n{0.0f, 0.0f, 0.0f};
      skinVertexHost<false>(s.draw, v - s.draw.dstVertex, s.joints, s.weights, s.palette, s.paletteNormals, p, n);
      const float4 c = mul(r.mvp, p);
      r.clip[v] = c;
      r.snap[v] = snapOrFlag(c, r.vp, r.gx, r.gy);
    }
    return;
  }
  for (uint32_t v = v0, src = src0; v < end; ++v, ++src) {
    float3 p = r.positions[src], n = r.normals[src];
    skinVertexHost<true>(s.draw, v - s.draw.dstVertex, s.joints, s.weights, s.palette, s.paletteNormals, p, n);
    const float4 c = mul(r.mvp, p);
    r.clip[v] = c;
    r.snap[v] = snapOrFlag(c, r.vp, r.gx, r.gy);
    r.worldPos[v] = mulPoint(r.model, p);
    r.worldNormal[v] = normalize(mul(r.normalMatrix, n));
  }
}

namespace {

// The host backends' vertex stage: a work item takes kHostVertexChunk
// consecutive vertices and walks the draws they belong to, so that the draw
// lookup (a binary search) and its matrices are fetched once per draw and
// chunk rather than once per vertex.
constexpr uint32_t kHostVertexChunk = 1024;
template <bool kWorld, bool kSkin>
struct TransformVerticesHost {
  TransformVertices<kWorld, kSkin> t;
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
      const VertexRun r{t.positions.data(), t.normals.data(), t.clip.data(), t.snap.data(),
                        kWorld ? t.worldPos.data() : nullptr, kWorld ? t.worldNormal.data() : nullptr,
                        t.mvp(d), dr.modelF, dr.normalMatrix, t.vp, t.gx, t.gy};
      if (kSkin && dr.skinJoint >= 0)
        skinnedRun(SkinRun{r, dr, t.skinJoints.data(), t.skinWeights.data(), t.joints.data(), t.jointNormals.data()},
                   dr.srcVertex + (v - dr.dstVertex), v, end);
      else
        transformRun(r, dr.srcVertex + (v - dr.dstVertex), v, end);
      v = end;
    }
  }
};

// Launches the vertex transform: per vertex on GPUs, per chunk of vertices on
// host backends (not built for GPUs).
template <bool kHost, bool kWorld, bool kSkin>
void launchTransform(const TransformVertices<kWorld, kSkin>& t, uint32_t numVerts) {
  if constexpr (kHost) {
    using Host = std::conditional_t<kHost, TransformVerticesHost<kWorld, kSkin>, void>;  // dependent: not built for GPUs
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
  }
  // Four instantiations: world outputs or not, skins or not (a scene without
  // skins runs the kernels it always ran).
  const auto launch = [&](auto world, auto skin) {
    TransformVertices<decltype(world)::value, decltype(skin)::value> t{
        s.draws, s.drawVertStart, s.vertDraw, s.numDraws, f.mvp, s.positions, s.normals, f.clip, f.snap, f.worldPos,
        f.worldNormal, f.vp, gx, gy, f.uniforms, f.uploadSeen, s.skinJoints, s.skinWeights, s.joints, s.jointNormals};
    launchTransform<!kOnDevice>(t, s.numVerts);
  };
  using Yes = std::true_type;
  using No = std::false_type;
  if (needWorld) {
    if (s.hasSkins) launch(Yes{}, Yes{});
    else launch(Yes{}, No{});
  } else {
    if (s.hasSkins) launch(No{}, Yes{});
    else launch(No{}, No{});
  }
}

}  // namespace rast
