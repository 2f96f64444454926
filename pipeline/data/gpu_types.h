// Plain structs shared by the pipeline stages on the device.
#pragma once

#include "base/vec.h"

namespace rast {

// Snapped window coordinates are fixed point with 8 sub-pixel bits.
constexpr int kSubBits = 8;
constexpr int32_t kSubOne = 1 << kSubBits;      // one pixel in fixed point
constexpr int32_t kSubHalf = kSubOne / 2;       // pixel centre offset

// One placed mesh primitive. Source ranges index the scene's object-space
// streams (stored once per mesh primitive); destination ranges index the
// per-frame streams (one entry per drawn vertex / triangle).
struct DrawGPU {
  uint32_t srcVertex, dstVertex, vertexCount;
  uint32_t srcTri, dstTri, triCount;
  int32_t material;  // -1: default material
  int32_t mirrored;  // node transform has a negative determinant: front faces are clockwise
  int32_t singleSided;  // the material is not doubleSided: back faces culled when the frame culls per material
  mat4d model;
  mat3f normalMatrix;  // transpose(inverse(mat3(model)))
  mat4f modelF;        // model rounded to float once, for world positions (the vertex stage)
  // Skinning in the vertex stage (docs/animation.md): the draw's first joint
  // in DeviceScene::joints (-1: not skinned), its first entry in
  // DeviceScene::skinJoints/skinWeights and its influence sets (4 joints each).
  int32_t skinJoint;
  uint32_t skinVertex, skinSets;
};

// A glTF metallic-roughness material (host/scene/scene.h Material). The
// Lambert and Blinn-Phong shading read baseColor and texture alone; the
// rest is the glTF model's (pipeline/shade/pbr_shading.h).
struct MaterialGPU {
  float4 baseColor;  // linear
  int32_t texture;   // base colour (sRGB), -1: none
  int32_t mrTexture, normalTexture, occlusionTexture, emissiveTexture;  // -1: none
  float metallic, roughness, normalScale, occlusionStrength;
  float3 emissive;   // linear, emissive strength applied
  int32_t flags;     // kMaterialUnlit | kMaterialDoubleSided | kMaterialOpaque | kMaterialClearcoat
};
// kMaterialClearcoat: the material has a KHR_materials_clearcoat layer, its
// ClearcoatGPU at the same index of DeviceScene::clearcoats.
constexpr int32_t kMaterialUnlit = 1, kMaterialDoubleSided = 2, kMaterialOpaque = 4, kMaterialClearcoat = 8;
// flags >> kMaterialUv1Shift: Material::uv1Slots, the texture slots
// (TextureSlot) that sample the second coordinates (DeviceScene::uvs1).
constexpr int32_t kMaterialUv1Shift = 4;

// A material's KHR_materials_clearcoat layer (host/scene/scene.h Material),
// kept apart from MaterialGPU so that the shading of a scene without one
// loads and holds none of it.
struct ClearcoatGPU {
  float factor, roughness, normalScale;
  int32_t texture, roughnessTexture, normalTexture;  // -1: none
};

// A KHR_lights_punctual light in world space (host/scene/scene.h PunctualLight).
struct PunctualGPU {
  float3 color;      // colour x intensity
  int32_t type;      // LightType: 0 directional, 1 point, 2 spot
  float3 position;
  float range;       // 0: unlimited
  float3 direction;  // the way the light shines
  float lightAngleScale, lightAngleOffset;  // spot: cone smoothing (KHR_lights_punctual's recommended form)
};

// A draw of a scene with MASK or BLEND materials (docs/transparency.md): its
// alpha class (AlphaClass, raster_rules.h: opaque, mask, blend), the mask's
// cutoff, and the centre of its primitive's bounding box in object space (the
// `sorted` transparency orders draws by its depth).
struct AlphaDraw {
  int32_t cls;
  float cutoff;
  float3 centre;
};

struct TextureGPU {
  uint32_t offset;  // first texel of level 0 in the shared texel buffer
  int32_t width, height, wrapS, wrapT;
  int32_t levels;   // mipmap levels stored after level 0 (1: none)
  int32_t magFilter, minFilter;  // the glTF sampler's (GL enums), for `--filter auto`
};

// A vertex in window space: x, y in fixed point with kFineBits (16) fractional
// bits, which hold the position snapped to 1/256 pixel and the rounding
// residual (depth_plane.h); window depth, 1/w.
// Computed once per drawn vertex by the vertex stage for the vertices that need
// no clipping, and per clipped vertex by the setup; both call snapVertex
// (raster_rules.h), so a triangle gets the same bits either way.
struct SnapVert {
  int32_t x, y;
  float z, invW;  // invW <= 0: the vertex needs clipping or cannot be drawn (see snapOrFlag)
};

// A triangle ready for rasterisation: a clipped, culled, snapped piece of one
// drawn triangle, counter-clockwise (positive area) in window space.
// 16-byte aligned (96 bytes, six 16-byte pieces, as the setup writes it):
// a GPU then reads neighbouring fields in wide loads (the shader's inverse
// area, primitive and corner barycentrics in two 16-byte loads, not eight).
struct alignas(16) RasterTri {
  int32_t x[3], y[3];               // window position, fixed point with kSubBits fractional bits, y up
  int32_t minX, minY, maxX, maxY;   // pixels whose centres the bounding box holds, clamped to the viewport
  float z[3];                       // window depth
  float invW[3];                    // 1 / clip w, for perspective-correct interpolation
  float invArea;                    // 1 / (twice the fixed-point area)
  uint32_t prim;                    // drawn triangle index (primitive id - 1)
  float bary[3][2];                 // barycentrics (b1, b2) of each vertex in the drawn triangle
};

// A drawn point or line segment: drawn vertex indices (v1 == v0 for a point),
// the source vertex of v0 (for its colour) and the draw's material.
struct LineGPU {
  uint32_t v0, v1, src0;
  int32_t material;
};

// Sample positions within a pixel, in 1/256 pixel relative to its centre (y
// up). One sample at the centre without multisampling; the standard D3D/Vulkan
// patterns for 2, 4 and 8 samples (see samplePattern()).
constexpr int kMaxSamples = 8;
struct SamplePattern {
  int32_t count = 1;
  int32_t ox[kMaxSamples] = {0}, oy[kMaxSamples] = {0};
  int32_t minX = 0, maxX = 0, minY = 0, maxY = 0;  // extent of the offsets
};

// Values that change per frame but not per element, passed by value to kernels.
struct Viewport {
  int32_t width, height;
  SamplePattern samples;
};

}  // namespace rast
