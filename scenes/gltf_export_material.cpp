// Writes a Scene's glTF material and light model into the exported glTF
// (scenes/gltf_export_material.h says what and why): the feature probes
// (scenes/material_probes.cpp) reach the Khronos Sample Renderer this way.
#include "scenes/gltf_export_material.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace rast {
namespace {

void useExtension(tinygltf::Model& m, const std::string& name) {
  if (std::find(m.extensionsUsed.begin(), m.extensionsUsed.end(), name) == m.extensionsUsed.end())
    m.extensionsUsed.push_back(name);
}

// Appends float data as a buffer view and accessor of buffer 0; returns the accessor.
int floatAccessor(tinygltf::Model& m, const float* data, size_t count, int comps) {
  std::vector<unsigned char>& bin = m.buffers[0].data;
  while (bin.size() % 4) bin.push_back(0);
  tinygltf::BufferView v;
  v.buffer = 0;
  v.byteOffset = bin.size();
  v.byteLength = count * comps * 4;
  v.target = TINYGLTF_TARGET_ARRAY_BUFFER;
  const auto* p = reinterpret_cast<const unsigned char*>(data);
  bin.insert(bin.end(), p, p + v.byteLength);
  m.bufferViews.push_back(v);
  tinygltf::Accessor a;
  a.bufferView = int(m.bufferViews.size() - 1);
  a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
  a.count = count;
  a.type = comps == 2 ? TINYGLTF_TYPE_VEC2 : TINYGLTF_TYPE_VEC4;
  m.accessors.push_back(a);
  return int(m.accessors.size() - 1);
}

tinygltf::Material material(const Material& mat, tinygltf::Model& m) {
  tinygltf::Material g;
  auto& pbr = g.pbrMetallicRoughness;
  pbr.baseColorFactor = {mat.baseColorFactor.x, mat.baseColorFactor.y, mat.baseColorFactor.z, mat.baseColorFactor.w};
  pbr.metallicFactor = mat.metallic;
  pbr.roughnessFactor = mat.roughness;
  const auto set = [&](uint32_t slot) { return (mat.uv1Slots >> slot) & 1u ? 1 : 0; };
  pbr.baseColorTexture.index = mat.texture;
  pbr.baseColorTexture.texCoord = set(SlotBaseColor);
  pbr.metallicRoughnessTexture.index = mat.metallicRoughnessTexture;
  pbr.metallicRoughnessTexture.texCoord = set(SlotMetalRough);
  g.normalTexture.index = mat.normalTexture;
  g.normalTexture.texCoord = set(SlotNormal);
  g.normalTexture.scale = mat.normalScale;
  g.occlusionTexture.index = mat.occlusionTexture;
  g.occlusionTexture.texCoord = set(SlotOcclusion);
  g.occlusionTexture.strength = mat.occlusionStrength;
  g.emissiveTexture.index = mat.emissiveTexture;
  g.emissiveTexture.texCoord = set(SlotEmissive);
  // Scene keeps emissiveFactor x strength: a factor above 1 needs KHR_materials_emissive_strength.
  const double peak = std::max({double(mat.emissive.x), double(mat.emissive.y), double(mat.emissive.z)});
  const double strength = peak > 1.0 ? peak : 1.0;
  g.emissiveFactor = {mat.emissive.x / strength, mat.emissive.y / strength, mat.emissive.z / strength};
  if (strength > 1.0) {
    tinygltf::Value::Object o;
    o["emissiveStrength"] = tinygltf::Value(strength);
    g.extensions["KHR_materials_emissive_strength"] = tinygltf::Value(o);
    useExtension(m, "KHR_materials_emissive_strength");
  }
  if (mat.hasClearcoat()) {  // KHR_materials_clearcoat: the factors and the textures it has
    tinygltf::Value::Object o;
    o["clearcoatFactor"] = tinygltf::Value(double(mat.clearcoat));
    o["clearcoatRoughnessFactor"] = tinygltf::Value(double(mat.clearcoatRoughness));
    const auto tex = [&](const char* key, int32_t index, TextureSlot slot, const double* scale) {
      if (index < 0) return;
      tinygltf::Value::Object t;
      t["index"] = tinygltf::Value(int(index));
      t["texCoord"] = tinygltf::Value(set(slot));
      if (scale) t["scale"] = tinygltf::Value(*scale);
      o[key] = tinygltf::Value(t);
    };
    const double scale = mat.clearcoatNormalScale;
    tex("clearcoatTexture", mat.clearcoatTexture, SlotClearcoat, nullptr);
    tex("clearcoatRoughnessTexture", mat.clearcoatRoughnessTexture, SlotClearcoatRoughness, nullptr);
    tex("clearcoatNormalTexture", mat.clearcoatNormalTexture, SlotClearcoatNormal, &scale);
    g.extensions["KHR_materials_clearcoat"] = tinygltf::Value(o);
    useExtension(m, "KHR_materials_clearcoat");
  }
  if (mat.unlit) {
    g.extensions["KHR_materials_unlit"] = tinygltf::Value(tinygltf::Value::Object());
    useExtension(m, "KHR_materials_unlit");
  }
  g.alphaMode = mat.alphaMode == AlphaMode::Mask ? "MASK" : mat.alphaMode == AlphaMode::Blend ? "BLEND" : "OPAQUE";
  g.alphaCutoff = mat.alphaCutoff;
  g.doubleSided = mat.doubleSided;
  return g;
}

// The rotation (x, y, z, w) taking -Z to the unit vector d.
std::vector<double> rotationFromMinusZ(const float3& d) {
  const glm::dvec3 a(0, 0, -1), b = glm::normalize(glm::dvec3(d.x, d.y, d.z));
  const double w = 1.0 + glm::dot(a, b);
  if (w < 1e-9) return {1.0, 0.0, 0.0, 0.0};  // opposite: half a turn about X
  const glm::dvec3 c = glm::cross(a, b);
  const double n = std::sqrt(glm::dot(c, c) + w * w);
  return {c.x / n, c.y / n, c.z / n, w / n};
}

void addNode(tinygltf::Model& m, tinygltf::Node n) {
  m.nodes.push_back(std::move(n));
  m.scenes[0].nodes.push_back(int(m.nodes.size() - 1));
}

void addCamera(tinygltf::Model& m, const FileCamera& c) {
  tinygltf::Camera g;
  g.name = c.name;
  if (c.orthographic) {
    g.type = "orthographic";
    g.orthographic.xmag = c.xmag;
    g.orthographic.ymag = c.ymag;
    g.orthographic.znear = c.znear;
    g.orthographic.zfar = c.zfar;
  } else {
    g.type = "perspective";
    g.perspective.yfov = c.yfovRad;
    g.perspective.aspectRatio = c.aspectRatio;
    g.perspective.znear = c.znear;
    g.perspective.zfar = c.zfar;
  }
  m.cameras.push_back(g);
  tinygltf::Node n;
  n.camera = int(m.cameras.size() - 1);
  n.matrix.assign(&c.world[0][0], &c.world[0][0] + 16);
  addNode(m, n);
}

}  // namespace

void exportMaterialModel(const Scene& s, tinygltf::Model& m) {
  const bool asIs = !s.sourceFiles.empty() || s.look.gltfMaterials;
  // The samplers' filters (the others' exports stay as they were: no filters, the reader's choice).
  for (size_t i = 0; asIs && i < s.textures.size() && i < m.samplers.size(); ++i) {
    m.samplers[i].magFilter = s.textures[i].magFilter;
    m.samplers[i].minFilter = s.textures[i].minFilter;
  }
  if (asIs)
    for (size_t i = 0; i < s.materials.size() && i < m.materials.size(); ++i) m.materials[i] = material(s.materials[i], m);
  for (size_t i = 0; i < s.prims.size() && i < m.meshes.size(); ++i) {
    const MeshPrim& p = s.prims[i];
    if (p.material < 0 || p.pointCount > 0 || p.lineCount > 0) continue;
    const Material& mat = s.materials[size_t(p.material)];
    tinygltf::Primitive& gp = m.meshes[i].primitives[0];
    if (asIs && mat.anyNormalMap() && !s.tangents.empty()) {
      const float4* t = &s.tangents[p.firstVertex];
      // glTF tangents are unit with w = +-1: a vertex without one (0,0,0,0) leaves the reader to generate them.
      const bool all = std::all_of(t, t + p.vertexCount, [](const float4& v) { return v.w == 1.0f || v.w == -1.0f; });
      if (all) gp.attributes["TANGENT"] = floatAccessor(m, &t->x, p.vertexCount, 4);
    }
    if (asIs && mat.uv1Slots != 0 && !s.uvs1.empty())
      gp.attributes["TEXCOORD_1"] = floatAccessor(m, &s.uvs1[p.firstVertex].x, p.vertexCount, 2);
  }
  for (const PunctualLight& l : s.lights) {
    tinygltf::Light g;
    g.name = l.name;
    g.color = {l.color.x, l.color.y, l.color.z};
    g.intensity = l.intensity;
    g.range = l.range;
    g.type = l.type == LightType::Directional ? "directional" : l.type == LightType::Point ? "point" : "spot";
    g.spot.innerConeAngle = l.innerConeAngle;
    g.spot.outerConeAngle = l.outerConeAngle;
    m.lights.push_back(g);
    tinygltf::Node n;
    n.name = l.name;
    n.translation = {l.position.x, l.position.y, l.position.z};
    n.rotation = rotationFromMinusZ(l.direction);
    tinygltf::Value::Object o;
    o["light"] = tinygltf::Value(int(m.lights.size() - 1));
    n.extensions["KHR_lights_punctual"] = tinygltf::Value(o);
    addNode(m, n);
  }
  for (const FileCamera& c : s.cameras) addCamera(m, c);
  // A built-in scene's own view, as a camera of the file (`--camera 0`), when it has no file cameras.
  if (asIs && s.cameras.empty() && s.camera) {
    const SceneCamera& sc = *s.camera;
    FileCamera c;
    c.name = "view";
    c.yfovRad = glm::radians(sc.fovyDeg);
    c.znear = sc.znear;
    c.zfar = sc.zfar;
    c.world = glm::inverse(glm::lookAt(sc.eye, sc.target, sc.up));
    addCamera(m, c);
  }
}

}  // namespace rast
