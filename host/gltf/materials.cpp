// glTF materials and KHR_lights_punctual lights as rast holds them (#37):
// the metallic-roughness model's factors, textures and alpha rules
// (glTF 2.0, 3.9), KHR_materials_emissive_strength, KHR_materials_unlit,
// KHR_materials_clearcoat, and
// the file's punctual lights placed by their nodes. Kept apart from the model
// walk (model_walk.cpp) because every value here comes from strangers and is
// checked against the specification's ranges: a NaN or out-of-range factor is
// one clear Error naming the material, not a frame of garbage.
#include "host/gltf/gltf_internal.h"

#include <glm/gtc/type_ptr.hpp>

#include <cmath>

namespace rast::gltf_detail {
namespace {

std::string materialAt(int mi) { return "materials[" + std::to_string(mi) + "]"; }

float unitFactor(double v, const std::string& what) {
  if (!std::isfinite(v) || v < 0.0 || v > 1.0) throw Error(what + " must be a number in [0, 1]");
  return float(v);
}

// A finite, non-negative number from an extension's JSON object (or its default).
double extNumber(const tinygltf::Value& x, const char* key, double dflt, const std::string& at) {
  if (!x.Has(key)) return dflt;
  const tinygltf::Value& v = x.Get(key);
  if (!v.IsNumber() || !std::isfinite(v.GetNumberAsDouble())) throw Error(at + key + " must be a finite number");
  return v.GetNumberAsDouble();
}

}  // namespace

ExtTexture extTexture(const tinygltf::Model& m, const tinygltf::Value& ext, const char* key, const std::string& at) {
  ExtTexture t;
  if (!ext.Has(key)) return t;
  const std::string x = at + key;
  const tinygltf::Value& v = ext.Get(key);
  if (!v.IsObject()) throw Error(x + " must be an object");
  if (!v.Has("index") || !v.Get("index").IsInt()) throw Error(x + ".index must be an integer");
  t.index = v.Get("index").GetNumberAsInt();
  if (t.index < 0 || size_t(t.index) >= m.textures.size())
    throw Error(x + ".index " + std::to_string(t.index) + " does not exist (the file has " +
                std::to_string(m.textures.size()) + " textures)");
  if (v.Has("texCoord")) {
    if (!v.Get("texCoord").IsInt() || v.Get("texCoord").GetNumberAsInt() < 0)
      throw Error(x + ".texCoord must be a non-negative integer");
    t.texCoord = v.Get("texCoord").GetNumberAsInt();
  }
  t.scale = extNumber(v, "scale", 1.0, x + ".");
  if (v.Has("extensions") && v.Get("extensions").IsObject()) {
    const tinygltf::Value& e = v.Get("extensions");
    for (const std::string& k : e.Keys()) t.extensions[k] = e.Get(k);
  }
  return t;
}

const tinygltf::Value* clearcoatOf(const tinygltf::Material& gm, const std::string& at) {
  const auto it = gm.extensions.find("KHR_materials_clearcoat");
  if (it == gm.extensions.end()) return nullptr;
  if (!it->second.IsObject()) throw Error(at + " KHR_materials_clearcoat: must be an object");
  return &it->second;
}

Material readMaterial(const tinygltf::Model& m, int mi, const std::function<int32_t(int, const char*)>& texture) {
  const tinygltf::Material& gm = m.materials[mi];
  const std::string at = materialAt(mi);
  const auto& pbr = gm.pbrMetallicRoughness;
  Material mat;
  if (!pbr.baseColorFactor.empty()) {
    if (pbr.baseColorFactor.size() != 4) throw Error(at + " baseColorFactor must have 4 numbers");
    float c[4];
    for (int k = 0; k < 4; ++k) c[k] = unitFactor(pbr.baseColorFactor[k], at + " baseColorFactor");
    mat.baseColorFactor = {c[0], c[1], c[2], c[3]};
  }
  mat.metallic = unitFactor(pbr.metallicFactor, at + " metallicFactor");
  mat.roughness = unitFactor(pbr.roughnessFactor, at + " roughnessFactor");
  if (pbr.baseColorTexture.index >= 0) mat.texture = texture(pbr.baseColorTexture.index, "baseColorTexture");
  if (pbr.metallicRoughnessTexture.index >= 0)
    mat.metallicRoughnessTexture = texture(pbr.metallicRoughnessTexture.index, "metallicRoughnessTexture");
  if (gm.normalTexture.index >= 0) {
    mat.normalTexture = texture(gm.normalTexture.index, "normalTexture");
    if (!std::isfinite(gm.normalTexture.scale)) throw Error(at + " normalTexture.scale must be finite");
    mat.normalScale = float(gm.normalTexture.scale);
  }
  if (gm.occlusionTexture.index >= 0) {
    mat.occlusionTexture = texture(gm.occlusionTexture.index, "occlusionTexture");
    mat.occlusionStrength = unitFactor(gm.occlusionTexture.strength, at + " occlusionTexture.strength");
  }
  if (!gm.emissiveFactor.empty()) {
    if (gm.emissiveFactor.size() != 3) throw Error(at + " emissiveFactor must have 3 numbers");
    float e[3];
    for (int k = 0; k < 3; ++k) e[k] = unitFactor(gm.emissiveFactor[k], at + " emissiveFactor");
    mat.emissive = {e[0], e[1], e[2]};
  }
  if (gm.emissiveTexture.index >= 0) mat.emissiveTexture = texture(gm.emissiveTexture.index, "emissiveTexture");
  const auto strength = gm.extensions.find("KHR_materials_emissive_strength");
  if (strength != gm.extensions.end()) {
    const std::string x = at + " KHR_materials_emissive_strength: ";
    if (!strength->second.IsObject()) throw Error(x + "must be an object");
    const double s = extNumber(strength->second, "emissiveStrength", 1.0, x);
    if (s < 0.0) throw Error(x + "emissiveStrength must not be negative");
    mat.emissive = mat.emissive * float(s);
  }
  if (gm.alphaMode == "MASK") mat.alphaMode = AlphaMode::Mask;
  else if (gm.alphaMode == "BLEND") mat.alphaMode = AlphaMode::Blend;
  else if (gm.alphaMode != "OPAQUE" && !gm.alphaMode.empty())
    throw Error(at + " alphaMode must be OPAQUE, MASK or BLEND");
  if (!std::isfinite(gm.alphaCutoff) || gm.alphaCutoff < 0.0) throw Error(at + " alphaCutoff must be a non-negative number");
  mat.alphaCutoff = float(gm.alphaCutoff);
  mat.doubleSided = gm.doubleSided;
  mat.unlit = gm.extensions.count("KHR_materials_unlit") > 0;
  // KHR_materials_clearcoat: factors in [0, 1] (default 0), three textures
  // (R: the coat, G: its roughness, a normal map with its scale). A coat of
  // 0 is no layer at all: its textures are not even loaded.
  if (const tinygltf::Value* cc = clearcoatOf(gm, at)) {
    const std::string x = at + " KHR_materials_clearcoat: ";
    mat.clearcoat = unitFactor(extNumber(*cc, "clearcoatFactor", 0.0, x), x + "clearcoatFactor");
    mat.clearcoatRoughness =
        unitFactor(extNumber(*cc, "clearcoatRoughnessFactor", 0.0, x), x + "clearcoatRoughnessFactor");
    const ExtTexture t = extTexture(m, *cc, "clearcoatTexture", x);
    const ExtTexture r = extTexture(m, *cc, "clearcoatRoughnessTexture", x);
    const ExtTexture n = extTexture(m, *cc, "clearcoatNormalTexture", x);
    if (mat.hasClearcoat()) {
      if (t.index >= 0) mat.clearcoatTexture = texture(t.index, "clearcoatTexture");
      if (r.index >= 0) mat.clearcoatRoughnessTexture = texture(r.index, "clearcoatRoughnessTexture");
      if (n.index >= 0) {
        mat.clearcoatNormalTexture = texture(n.index, "clearcoatNormalTexture");
        mat.clearcoatNormalScale = float(n.scale);
      }
    }
  }
  return mat;
}

PunctualLight readLight(const tinygltf::Model& m, int li, const std::string& nodeName, const glm::dmat4& world) {
  const std::string at = "KHR_lights_punctual lights[" + std::to_string(li) + "]";
  if (li < 0 || size_t(li) >= m.lights.size()) throw Error(at + " does not exist");
  const tinygltf::Light& gl = m.lights[li];
  PunctualLight l;
  l.name = !gl.name.empty() ? gl.name : nodeName;
  if (gl.type == "directional") l.type = LightType::Directional;
  else if (gl.type == "point") l.type = LightType::Point;
  else if (gl.type == "spot") l.type = LightType::Spot;
  else throw Error(at + ": type must be directional, point or spot");
  if (!gl.color.empty()) {
    if (gl.color.size() != 3) throw Error(at + ": color must have 3 numbers");
    float c[3];
    for (int k = 0; k < 3; ++k) c[k] = unitFactor(gl.color[k], at + ": color");
    l.color = {c[0], c[1], c[2]};
  }
  if (!std::isfinite(gl.intensity) || gl.intensity < 0.0) throw Error(at + ": intensity must not be negative");
  l.intensity = float(gl.intensity);
  if (!std::isfinite(gl.range) || gl.range < 0.0) throw Error(at + ": range must be positive");
  l.range = l.type == LightType::Directional ? 0.0f : float(gl.range);
  if (l.type == LightType::Spot) {
    const double inner = gl.spot.innerConeAngle, outer = gl.spot.outerConeAngle;
    if (!(std::isfinite(inner) && std::isfinite(outer) && inner >= 0.0 && inner < outer && outer <= M_PI / 2))
      throw Error(at + ": spot cone angles must satisfy 0 <= innerConeAngle < outerConeAngle <= pi/2");
    l.innerConeAngle = float(inner);
    l.outerConeAngle = float(outer);
  }
  const glm::dvec3 p = glm::dvec3(world[3]);
  const glm::dvec3 d = glm::dvec3(world * glm::dvec4(0.0, 0.0, -1.0, 0.0));
  const double len = glm::length(d);
  if (!(len > 0.0) || !std::isfinite(len)) throw Error(at + ": its node's transform has no direction");
  l.position = {float(p.x), float(p.y), float(p.z)};
  l.direction = {float(d.x / len), float(d.y / len), float(d.z / len)};
  return l;
}

}  // namespace rast::gltf_detail
