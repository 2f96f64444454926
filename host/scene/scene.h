// Host-side scene: the geometry, materials and textures a frame needs, sized to
// what the scene actually uses.
//
// Geometry is stored once per mesh primitive (object space, indices local to the
// primitive); a Draw places a primitive in the world with a node transform. A
// mesh used by several nodes is therefore stored once and drawn once per node,
// as glTF (and ../shared/tools/glref) do.
#pragma once

#include "base/error.h"
#include "base/vec.h"

#include <glm/glm.hpp>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace rast {

// glTF sampler wrap modes (the GL enums, as stored in glTF files).
enum Wrap : int32_t { WrapRepeat = 10497, WrapClamp = 33071, WrapMirror = 33648 };

struct SceneRig;  // host/scene/animation.h

struct Texture {
  int32_t width = 0, height = 0;
  std::vector<uint32_t> rgba;  // sRGB-encoded RGBA8 (R in the low byte), first row = top of the image
  int32_t wrapS = WrapRepeat, wrapT = WrapRepeat;
  // The sampler's filters (GL enums as glTF stores them; a file without
  // them gets linear and linear-mipmap-linear, as the Khronos renderer does).
  // Used under `--filter auto` by the glTF shading.
  int32_t magFilter = 9729, minFilter = 9987;
};

// glTF alphaMode (3.9.4): OPAQUE ignores alpha, MASK discards below the
// cutoff, BLEND composites.
enum class AlphaMode : int32_t { Opaque = 0, Mask = 1, Blend = 2 };

// The texture slots of a material, for Material::uv1Slots.
enum TextureSlot : int32_t {
  SlotBaseColor = 0, SlotMetalRough = 1, SlotNormal = 2, SlotOcclusion = 3, SlotEmissive = 4,
  SlotClearcoat = 5, SlotClearcoatRoughness = 6, SlotClearcoatNormal = 7  // KHR_materials_clearcoat
};

// A glTF 2.0 metallic-roughness material (3.9), factors linear. Texture
// fields index Scene::textures (-1: none). Its textures sample the
// primitive's first coordinates (Scene::uvs: the base colour's set and
// transform, or the first textured slot's), except those of uv1Slots, which
// sample the second (Scene::uvs1: another set or another transform;
// docs/gltf-support.md).
struct Material {
  float4 baseColorFactor{1.0f, 1.0f, 1.0f, 1.0f};  // linear
  int32_t texture = -1;                             // baseColorTexture (sRGB)
  float metallic = 1.0f, roughness = 1.0f;
  int32_t metallicRoughnessTexture = -1;  // G: roughness, B: metallic (linear)
  int32_t normalTexture = -1;             // tangent space, linear
  float normalScale = 1.0f;
  int32_t occlusionTexture = -1;          // R: occlusion of indirect light (linear)
  float occlusionStrength = 1.0f;
  float3 emissive{0.0f, 0.0f, 0.0f};      // emissiveFactor x KHR_materials_emissive_strength
  int32_t emissiveTexture = -1;           // sRGB
  AlphaMode alphaMode = AlphaMode::Opaque;
  float alphaCutoff = 0.5f;
  bool doubleSided = false;
  bool unlit = false;                     // KHR_materials_unlit
  uint32_t uv1Slots = 0;                  // bit k: slot k (TextureSlot) samples Scene::uvs1
  // KHR_materials_clearcoat (docs/gltf-support.md): a second, dielectric
  // GGX layer (f0 0.04) over the base. clearcoat 0: no layer (the default).
  float clearcoat = 0.0f, clearcoatRoughness = 0.0f;
  int32_t clearcoatTexture = -1;           // R: times clearcoat (linear)
  int32_t clearcoatRoughnessTexture = -1;  // G: times clearcoatRoughness (linear)
  int32_t clearcoatNormalTexture = -1;     // tangent space, linear; none: the geometry's normal
  float clearcoatNormalScale = 1.0f;
  bool hasClearcoat() const { return clearcoat > 0.0f; }
  bool anyTexture() const {
    return texture >= 0 || metallicRoughnessTexture >= 0 || normalTexture >= 0 || occlusionTexture >= 0 ||
           emissiveTexture >= 0 || clearcoatTexture >= 0 || clearcoatRoughnessTexture >= 0 ||
           clearcoatNormalTexture >= 0;
  }
  // Whether the material needs a tangent frame (a normal map of either layer).
  bool anyNormalMap() const { return normalTexture >= 0 || clearcoatNormalTexture >= 0; }
};

// A KHR_lights_punctual light placed in the world by its node: directional
// (lux), point and spot (candela); colour linear. range 0: unlimited.
enum class LightType : int32_t { Directional = 0, Point = 1, Spot = 2 };
struct PunctualLight {
  LightType type = LightType::Directional;
  float3 color{1.0f, 1.0f, 1.0f};
  float intensity = 1.0f;
  float range = 0.0f;
  float innerConeAngle = 0.0f, outerConeAngle = 0.7853981634f;  // radians (spot)
  float3 position{0.0f, 0.0f, 0.0f};   // world
  float3 direction{0.0f, 0.0f, -1.0f};  // world, the way the light shines (the node's -Z)
  std::string name;
};

// A run of vertices and triangles sharing one material.
struct MeshPrim {
  uint32_t firstVertex = 0, vertexCount = 0;
  uint32_t firstTri = 0, triCount = 0;
  // glTF POINTS / LINES / LINE_LOOP / LINE_STRIP primitives (loops and strips
  // expanded to segments): ranges of Scene::lineIndices (2 per segment) and
  // Scene::pointIndices (1 per point). A primitive has one kind only.
  uint32_t firstLine = 0, lineCount = 0;
  uint32_t firstPoint = 0, pointCount = 0;
  int32_t material = -1;  // -1: default material (white, untextured)
};

struct Draw {
  uint32_t prim = 0;                  // index into Scene::prims
  glm::dmat4 model = glm::dmat4(1.0);  // node-to-world transform
};

// A camera a scene asks to be seen from (procedural stress scenes); glTF
// files are auto-framed instead, as glref does.
struct SceneCamera {
  glm::dvec3 eye{0, 0, 5}, target{0, 0, 0}, up{0, 1, 0};
  double fovyDeg = 45.0, znear = 0.1, zfar = 100.0;
};

// A camera a glTF file declares, placed by the node that uses it (one entry
// per node instance, in scene traversal order). It looks down its node's -Z
// with +Y up (glTF 2.0, 3.10).
struct FileCamera {
  std::string name;            // the camera's name, else its node's, else ""
  bool orthographic = false;
  double yfovRad = 0.0;        // perspective: vertical field of view
  double aspectRatio = 0.0;    // perspective: the file's aspect (0: none); rast uses the image's
  double xmag = 0.0, ymag = 0.0;  // orthographic: half extents of the view volume
  double znear = 0.0, zfar = 0.0;  // zfar 0: infinite (perspective only)
  glm::dmat4 world = glm::dmat4(1.0);
};

// What a file declares beyond what rast draws, for `rast info SCENE`: the
// extensions and how many materials use each material feature. Filled by the
// glTF loader; empty for built-in scenes.
struct FileFacts {
  std::vector<std::string> extensionsUsed, extensionsRequired;
  uint32_t lightsDeclared[3] = {0, 0, 0};  // KHR_lights_punctual: directional, point, spot
  uint32_t lightNodes = 0;                 // nodes that place a light
  uint32_t materials = 0;
  // Materials using: baseColorTexture, metallicRoughnessTexture, normalTexture,
  // occlusionTexture, emission (factor or texture), alphaMode MASK, alphaMode
  // BLEND, doubleSided, KHR_materials_unlit, KHR_texture_transform (any texture),
  // KHR_materials_clearcoat.
  uint32_t materialUses[11] = {};
  // Normal-mapped primitives (as loaded, once per mesh primitive): with the
  // file's TANGENT, and without (tangents generated, host/scene/tangents.h).
  uint32_t tangentPrims = 0, generatedTangentPrims = 0;
  // Materials drawn whose textures sample two sets or transforms (Scene::uvs1).
  uint32_t twoUvMaterials = 0;
};

// How a scene asks to be shown when the command line does not say (the embedded
// default scene, the stress scenes): glTF files keep rast's neutral defaults, so
// that they compare pixel for pixel with glref.
struct SceneLook {
  std::optional<float4> background;  // linear
  std::vector<float4> lights;        // directional: xyz towards the light, w intensity
  int msaa = 1;                      // anti-aliasing for single images (`rast render`)
  // A built-in scene made for the glTF material model (the feature probes,
  // scenes/material_probes.h): shaded `--shading pbr` by default, as glTF
  // files are, and exported with its materials as they are.
  bool gltfMaterials = false;
};

struct Scene {
  std::string name;
  std::optional<SceneCamera> camera;
  SceneLook look;
  // Vertex streams. normals always has one entry per vertex (flat normals are
  // generated where a file has none); uvs and colors are empty when no
  // primitive of the scene uses them, so unused attributes cost nothing.
  std::vector<float3> positions;
  std::vector<float3> normals;
  std::vector<float2> uvs;
  // The second coordinates (Material::uv1Slots), with their texture's
  // transform applied; empty when no material needs them.
  std::vector<float2> uvs1;
  std::vector<float4> colors;
  // Normal mapping's tangents (object space; w = +1 or -1, the bitangent
  // being w * cross(N, T); (0, 0, 0, 0): none, the shader derives the
  // triangle's frame). Only for primitives whose material has a normal
  // texture: the file's TANGENT, else generated (tangents.h). Empty when no
  // primitive needs them; else one entry per vertex.
  std::vector<float4> tangents;
  std::vector<uint32_t> indices;  // 3 per triangle, relative to the primitive's firstVertex
  std::vector<uint32_t> lineIndices;   // 2 per line segment, relative to the primitive's firstVertex
  std::vector<uint32_t> pointIndices;  // 1 per point, relative to the primitive's firstVertex
  std::vector<MeshPrim> prims;
  std::vector<Draw> draws;  // in scene traversal order: defines primitive ids
  std::vector<Material> materials;
  std::vector<Texture> textures;
  std::vector<FileCamera> cameras;  // a glTF file's cameras, by node (--camera N|NAME)
  std::vector<PunctualLight> lights;  // KHR_lights_punctual, one per node placing a light
  FileFacts facts;
  // Every file the scene was read from: the scene file and, resolved, each
  // external buffer and image. Outputs must not be any of them (app/).
  std::vector<std::string> sourceFiles;
  // Node hierarchy, animations, skins and morph targets (host/scene/animation.h):
  // null for a scene that does not move.
  std::shared_ptr<const SceneRig> rig;
  // The pose poseScene() last wrote: its time, its animation (-2: none, the
  // rest pose; -1: all) and whether skinned vertices were skinned on the host.
  double poseTime = 0.0;
  int poseAnimation = -2;
  bool skinnedOnHost = true;

  uint32_t triangleCount() const;  // drawn triangles, each instance counted
  uint64_t lineCount() const;      // drawn line segments
  uint64_t pointCount() const;     // drawn points
  void worldBounds(glm::dvec3& lo, glm::dvec3& hi) const;
  // Checks internal consistency (indices in range, streams sized); throws Error.
  void validate() const;
};

// Appends a primitive to the scene from per-vertex data; returns its index.
// Used by the loader and the procedural scenes.
uint32_t addPrim(Scene& s, const std::vector<float3>& pos, const std::vector<float3>* nrm,
                 const std::vector<float2>* uv, const std::vector<float4>* col,
                 const std::vector<uint32_t>& idx, int32_t material);

// Appends a point or line primitive: `segments` holds 2 indices per segment,
// `points` 1 per point (one of them empty). Normals are not needed (point and
// line fragments are unlit) and are stored as +z.
uint32_t addLinePrim(Scene& s, const std::vector<float3>& pos, const std::vector<float4>* col,
                     const std::vector<uint32_t>& segments, const std::vector<uint32_t>& points, int32_t material);

}  // namespace rast
