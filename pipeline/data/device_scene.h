// The scene uploaded to the device once, sized to what it uses: attribute
// streams a scene does not have are not allocated.
#pragma once

#include "pipeline/data/device.h"
#include "pipeline/data/gpu_types.h"
#include "host/scene/scene.h"

#include <cstdint>
#include <limits>

namespace rast {

// An entry of the draw tables (DeviceScene::triDraw, vertDraw): a draw index.
using DrawIndex = uint16_t;

struct DeviceScene {
  DView<float3> positions;  // object space, per source vertex
  DView<float3> normals;
  DView<float2> uvs;      // empty when no material samples a texture
  DView<float2> uvs1;     // the second coordinates (Scene::uvs1), empty when no material samples them
  DView<float4> colors;   // empty when no primitive has COLOR_0
  DView<float4> tangents;  // normal mapping's (Scene::tangents), object space; empty when no material has a normal map
  DView<uint32_t> indices;  // 3 per source triangle, relative to the primitive's first vertex
  DView<DrawGPU> draws;
  DView<uint32_t> drawTriStart;   // dstTri of each draw, for triangle -> draw lookup
  DView<uint32_t> drawVertStart;  // dstVertex of each draw, for vertex -> draw lookup
  // The same lookups as tables, for scenes of many draws (kDrawTableMinDraws);
  // empty otherwise. drawOf() takes either.
  DView<DrawIndex> triDraw, vertDraw;
  DView<MaterialGPU> materials;
  DView<ClearcoatGPU> clearcoats;  // per material, uploaded only when some material has a clear coat
  bool hasClearcoat = false;
  DView<TextureGPU> textures;
  DView<uint32_t> texels;  // all textures, sRGB RGBA8
  DView<float> srgbToLinear;  // 256-entry decode table
  DView<float> unormToFloat;  // 256-entry table i / 255, for linear textures (normals, metal/rough, occlusion)
  DView<PunctualGPU> lights;  // the file's KHR_lights_punctual lights (empty: none)
  DView<uint32_t> srgbEncodePacked;  // sRGB encoder, one entry per bucket (srgbEncodePacked(), packSrgb8Packed)
  // Skins (host/scene/animation.h), only when a draw is skinned: per skinned
  // draw's vertex 4 joints and 4 weights per influence set (DrawGPU::skinVertex),
  // and the joint palette of the current pose (world * inverse bind, and its
  // inverse transpose for normals), rewritten by updatePose.
  DView<uint16_t> skinJoints;
  DView<float> skinWeights;
  DView<mat4f> joints;
  DView<mat3f> jointNormals;
  bool hasSkins = false;

  // Drawn line segments, then drawn points, in scene traversal order
  // (primitive ids after the triangles'; docs/points-lines.md).
  DView<LineGPU> lines, points;
  uint32_t numLines = 0, numPoints = 0;

  uint32_t numDraws = 0, numTris = 0, numVerts = 0;  // drawn counts
  std::vector<mat4d> hostModels;  // draws' model matrices, kept only when hostMvps()
  // Whether the host computes the draws' MVPs and uploads them with the
  // camera (Renderer::enqueue), or the vertex stage computes them.
  bool hostMvps() const { return numDraws <= kHostMatricesMaxDraws; }
  bool hasUV = false, hasColor = false, hasTextures = false, hasTangents = false, hasUV1 = false;
  // No material samples a texture but its base colour (and none has a clear
  // coat): the glTF shading then samples that one texture without the loop
  // over the material's slots (kPbrBaseTexture, pipeline/shade/pbr_fragment.h).
  bool baseTexturesOnly = false;
  // MASK and BLEND materials (docs/transparency.md): per draw its class and
  // cutoff, uploaded only when some drawn primitive has one of them.
  DView<AlphaDraw> alphaDraws;
  bool hasMask = false, hasBlend = false;
  bool hasAlphaClasses() const { return hasMask || hasBlend; }

  static DeviceScene upload(const Scene& scene);
  // A new pose of the same scene (host/scene/animation.h: poseScene): the
  // draws' matrices and, when the scene has skins or morph targets, the
  // vertices, copied into the buffers the scene already has (no allocation).
  void updatePose(const Scene& scene);
  void uploadLinesAndPoints(const Scene& scene);  // core/device_lines.cpp
  void uploadAlphaDraws(const Scene& scene);      // device_alpha.cpp
  // (Re)uploads the textures, with full mipmap pyramids when asked (built on
  // the host with 2x2 averaging: colour in linear light, data textures'
  // stored values). Trilinear filtering needs them; other filters do not pay for them.
  void uploadTextures(const std::vector<Texture>& textures, bool mipmaps);
  // Per texture: 1 when materials sample it only as data (normal,
  // metal/rough, occlusion, coat maps), whose levels average the stored values.
  std::vector<uint8_t> dataTextures_;
  bool hasMipmaps = false;
  size_t bytes() const;
  std::vector<DrawGPU> uploadedDraws_;  // the draws as uploaded: updatePose keeps their ranges and skins
};

// Largest i with starts(i) <= key; starts is ascending with starts(0) == 0.
// lo: a range known to start at or before key (0 when nothing is known).
KOKKOS_INLINE_FUNCTION uint32_t findRange(const DView<uint32_t>& starts, uint32_t n, uint32_t key, uint32_t lo = 0) {
  uint32_t hi = n;  // invariant: starts(lo) <= key < starts(hi) (hi == n: +inf)
  while (hi - lo > 1) {
    const uint32_t mid = lo + (hi - lo) / 2;
    if (starts(mid) <= key) lo = mid; else hi = mid;
  }
  return lo;
}
// The draw of drawn triangle or vertex `key`: from its table when the scene
// has one (DeviceScene::triDraw, vertDraw), else findRange over the starts.
// The same draw either way (an empty draw owns no key).
KOKKOS_INLINE_FUNCTION uint32_t drawOf(const DView<DrawIndex>& table, const DView<uint32_t>& starts, uint32_t n,
                                       uint32_t key) {
  if (n <= 1) return 0;  // findRange's answer too; one draw tests for no table
  return table.data() ? uint32_t(table(key)) : findRange(starts, n, key);
}
// Whether a scene of `draws` draws gets the tables: more than
// kDrawTableMinDraws, and every draw's index fits an entry.
inline bool drawTables(uint64_t draws) {
  return draws > kDrawTableMinDraws && draws <= uint64_t(std::numeric_limits<DrawIndex>::max()) + 1;
}

}  // namespace rast
