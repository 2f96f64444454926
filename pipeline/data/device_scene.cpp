#include "pipeline/data/device_scene.h"

#include "base/color.h"
#include "host/scene/animation.h"

#include <glm/gtc/matrix_inverse.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace rast {
namespace {

template <class T>
DView<T> uploadVec(const char* label, const std::vector<T>& v) {
  DView<T> d = allocUninit<T>(label, v.size());
  if (!v.empty()) {
    Kokkos::View<const T*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>> h(v.data(), v.size());
    Kokkos::deep_copy(d, h);
  }
  return d;
}

// A draw as the pipeline reads it: its ranges and its matrices.
DrawGPU drawGpu(const Scene& s, const Draw& dr, const MeshPrim& p, uint32_t vert, uint32_t tri) {
  DrawGPU g{};
  g.srcVertex = p.firstVertex;
  g.vertexCount = p.vertexCount;
  g.srcTri = p.firstTri;
  g.triCount = p.triCount;
  g.dstVertex = vert;
  g.dstTri = tri;
  g.material = p.material;
  g.mirrored = glm::determinant(dr.model) < 0.0 ? 1 : 0;
  g.singleSided = p.material >= 0 && !s.materials[p.material].doubleSided ? 1 : 0;
  for (int k = 0; k < 16; ++k) g.model.m[k] = (&dr.model[0][0])[k];
  for (int k = 0; k < 16; ++k) g.modelF.m[k] = float(g.model.m[k]);
  const glm::dmat3 nm = glm::inverseTranspose(glm::dmat3(dr.model));
  for (int k = 0; k < 9; ++k) g.normalMatrix.m[k] = float((&nm[0][0])[k]);
  g.skinJoint = -1;
  return g;
}

void paletteToFloat(const SkinPalette& pal, std::vector<mat4f>& j, std::vector<mat3f>& n) {
  j.resize(pal.joints.size());
  n.resize(pal.normals.size());
  for (size_t i = 0; i < j.size(); ++i) {
    for (int k = 0; k < 16; ++k) j[i].m[k] = float((&pal.joints[i][0][0])[k]);
    for (int k = 0; k < 9; ++k) n[i].m[k] = float((&pal.normals[i][0][0])[k]);
  }
}

template <class T>
void copyInto(const DView<T>& d, const std::vector<T>& v) {
  if (v.empty()) return;
  Kokkos::View<const T*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>> h(v.data(), v.size());
  Kokkos::deep_copy(Kokkos::subview(d, std::make_pair(size_t(0), v.size())), h);
}

}  // namespace

void DeviceScene::updatePose(const Scene& s) {
  if (s.draws.size() != numDraws || s.positions.size() != positions.extent(0))
    throw Error("internal: a pose must keep the scene's draws and vertices");
  // Only scenes with morph targets send vertices again; skinned draws' stay
  // in their bind pose on the device.
  bool morphs = false;
  if (s.rig)
    for (const DeformedDraw& dd : s.rig->deformed) morphs |= dd.targets > 0;
  std::vector<float3> pos, nrm;
  if (morphs && hasSkins && s.skinnedOnHost) {
    pos = s.positions;
    nrm = s.normals;
  }
  const SkinPalette pal = skinPalette(s, pos.empty() ? nullptr : &pos, pos.empty() ? nullptr : &nrm);
  std::vector<DrawGPU> host = uploadedDraws_;
  for (size_t k = 0; k < s.draws.size(); ++k) {
    const DrawGPU& was = uploadedDraws_[k];
    host[k] = drawGpu(s, s.draws[k], s.prims[s.draws[k].prim], was.dstVertex, was.dstTri);
    host[k].skinJoint = was.skinJoint;
    host[k].skinVertex = was.skinVertex;
    host[k].skinSets = was.skinSets;
    if (hostMvps()) hostModels[k] = host[k].model;
  }
  copyInto(draws, host);
  if (hasSkins) {
    std::vector<mat4f> j;
    std::vector<mat3f> n;
    paletteToFloat(pal, j, n);
    copyInto(joints, j);
    copyInto(jointNormals, n);
  }
  if (morphs) {
    copyInto(positions, pos.empty() ? s.positions : pos);
    copyInto(normals, nrm.empty() ? s.normals : nrm);
    // Morphed tangents (TANGENT deltas, host/scene/animation.h).
    if (hasTangents && s.tangents.size() == tangents.extent(0)) copyInto(tangents, s.tangents);
  }
}

DeviceScene DeviceScene::upload(const Scene& s) {
  s.validate();
  DeviceScene d;
  // Skinned draws travel in their bind pose and are skinned by the vertex stage.
  d.hasSkins = rast::hasSkins(s);
  std::vector<float3> bindPos, bindNrm;
  if (d.hasSkins && s.skinnedOnHost) {
    bindPos = s.positions;
    bindNrm = s.normals;
  }
  const SkinPalette pal = skinPalette(s, bindPos.empty() ? nullptr : &bindPos, bindPos.empty() ? nullptr : &bindNrm);
  d.positions = uploadVec("scene.positions", bindPos.empty() ? s.positions : bindPos);
  d.normals = uploadVec("scene.normals", bindNrm.empty() ? s.normals : bindNrm);
  d.indices = uploadVec("scene.indices", s.indices);

  // Only the attribute streams that some drawn primitive uses travel.
  bool usesTexture = false;
  for (const Material& m : s.materials) usesTexture |= m.anyTexture();
  d.hasUV = usesTexture && !s.uvs.empty();
  d.hasColor = !s.colors.empty();
  d.hasTextures = usesTexture;
  d.baseTexturesOnly = usesTexture;
  for (const Material& m : s.materials)
    d.baseTexturesOnly = d.baseTexturesOnly && m.metallicRoughnessTexture < 0 && m.normalTexture < 0 &&
                         m.occlusionTexture < 0 && m.emissiveTexture < 0 && !m.hasClearcoat();
  // Which textures are data (normal, metal/rough, occlusion, coat maps) and
  // never colour (base colour, emission): their mipmaps average the stored
  // values, as the specification's linear textures ask, not the sRGB-decoded ones.
  d.dataTextures_.assign(s.textures.size(), 0);
  {
    std::vector<uint8_t> colour(s.textures.size(), 0);
    auto mark = [&](std::vector<uint8_t>& v, int32_t t) {
      if (t >= 0 && size_t(t) < v.size()) v[size_t(t)] = 1;
    };
    for (const Material& m : s.materials) {
      mark(colour, m.texture);
      mark(colour, m.emissiveTexture);
      for (int32_t t : {m.metallicRoughnessTexture, m.normalTexture, m.occlusionTexture, m.clearcoatTexture,
                        m.clearcoatRoughnessTexture, m.clearcoatNormalTexture})
        mark(d.dataTextures_, t);
    }
    for (size_t k = 0; k < colour.size(); ++k)
      if (colour[k]) d.dataTextures_[k] = 0;  // both: the colour's pyramid (docs/gltf-support.md)
  }
  if (d.hasUV) d.uvs = uploadVec("scene.uvs", s.uvs);
  if (d.hasColor) d.colors = uploadVec("scene.colors", s.colors);
  bool usesUv1 = false;
  for (const Material& m : s.materials) usesUv1 |= m.uv1Slots != 0;
  d.hasUV1 = d.hasUV && usesUv1 && !s.uvs1.empty();
  if (d.hasUV1) d.uvs1 = uploadVec("scene.uvs1", s.uvs1);
  d.hasTangents = d.hasUV && !s.tangents.empty();
  if (d.hasTangents) d.tangents = uploadVec("scene.tangents", s.tangents);

  std::vector<DrawGPU> draws;
  std::vector<uint32_t> triStart, vertStart;
  std::vector<uint16_t> skinJ;
  std::vector<float> skinW;
  uint64_t tri = 0, vert = 0;
  for (const Draw& dr : s.draws) {
    const MeshPrim& p = s.prims[dr.prim];
    DrawGPU g = drawGpu(s, dr, p, uint32_t(vert), uint32_t(tri));
    const size_t k = draws.size();
    if (pal.start[k] >= 0) {
      const DeformedDraw* dd = nullptr;
      for (const DeformedDraw& x : s.rig->deformed) dd = x.draw == k ? &x : dd;
      g.skinJoint = pal.start[k];
      g.skinVertex = uint32_t(skinJ.size());
      g.skinSets = dd->sets;
      skinJ.insert(skinJ.end(), dd->joints.begin(), dd->joints.end());
      skinW.insert(skinW.end(), dd->weights.begin(), dd->weights.end());
    }
    d.hostModels.push_back(g.model);
    triStart.push_back(g.dstTri);
    vertStart.push_back(g.dstVertex);
    draws.push_back(g);
    tri += p.triCount;
    vert += p.vertexCount;
    if (tri >= 0xffffffffull || vert >= 0xffffffffull) throw Error("scene too large: more than 2^32 drawn triangles or vertices");
  }
  d.numDraws = uint32_t(draws.size());
  if (!d.hostMvps()) d.hostModels = std::vector<mat4d>();  // the vertex stage computes the MVPs
  d.numTris = uint32_t(tri);
  d.numVerts = uint32_t(vert);
  d.draws = uploadVec("scene.draws", draws);
  d.uploadedDraws_ = draws;
  if (d.hasSkins) {
    if (skinJ.size() >= 0xffffffffull) throw Error("scene too large: more than 2^32 skin influences");
    std::vector<mat4f> j;
    std::vector<mat3f> n;
    paletteToFloat(pal, j, n);
    d.skinJoints = uploadVec("scene.skinJoints", skinJ);
    d.skinWeights = uploadVec("scene.skinWeights", skinW);
    d.joints = uploadVec("scene.joints", j);
    d.jointNormals = uploadVec("scene.jointNormals", n);
  }
  d.drawTriStart = uploadVec("scene.drawTriStart", triStart);
  d.drawVertStart = uploadVec("scene.drawVertStart", vertStart);
  if (drawTables(draws.size())) {
    std::vector<DrawIndex> triDraw(d.numTris), vertDraw(d.numVerts);
    for (size_t k = 0; k < draws.size(); ++k) {
      std::fill_n(triDraw.begin() + draws[k].dstTri, draws[k].triCount, DrawIndex(k));
      std::fill_n(vertDraw.begin() + draws[k].dstVertex, draws[k].vertexCount, DrawIndex(k));
    }
    d.triDraw = uploadVec("scene.triDraw", triDraw);
    d.vertDraw = uploadVec("scene.vertDraw", vertDraw);
  }
  d.uploadLinesAndPoints(s);
  d.uploadAlphaDraws(s);

  std::vector<MaterialGPU> mats;
  for (const Material& m : s.materials) {
    MaterialGPU g{};
    g.baseColor = m.baseColorFactor;
    g.texture = m.texture;
    g.mrTexture = m.metallicRoughnessTexture;
    g.normalTexture = m.normalTexture;
    g.occlusionTexture = m.occlusionTexture;
    g.emissiveTexture = m.emissiveTexture;
    g.metallic = m.metallic;
    g.roughness = m.roughness;
    g.normalScale = m.normalScale;
    g.occlusionStrength = m.occlusionStrength;
    g.emissive = m.emissive;
    g.flags = (m.unlit ? kMaterialUnlit : 0) | (m.doubleSided ? kMaterialDoubleSided : 0) |
              (m.alphaMode != AlphaMode::Blend ? kMaterialOpaque : 0) |  // MASK: opaque where the alpha test keeps it
              (m.hasClearcoat() ? kMaterialClearcoat : 0) | int32_t(m.uv1Slots << kMaterialUv1Shift);
    mats.push_back(g);
    d.hasClearcoat = d.hasClearcoat || m.hasClearcoat();
  }
  d.materials = uploadVec("scene.materials", mats);
  if (d.hasClearcoat) {
    std::vector<ClearcoatGPU> coats;
    for (const Material& m : s.materials)
      coats.push_back(ClearcoatGPU{m.clearcoat, m.clearcoatRoughness, m.clearcoatNormalScale, m.clearcoatTexture,
                                   m.clearcoatRoughnessTexture, m.clearcoatNormalTexture});
    d.clearcoats = uploadVec("scene.clearcoats", coats);
  }
  std::vector<PunctualGPU> lights;
  for (const PunctualLight& l : s.lights) {
    PunctualGPU g{};
    g.color = l.color * l.intensity;
    g.type = int32_t(l.type);
    g.position = l.position;
    g.range = l.range;
    g.direction = l.direction;
    // KHR_lights_punctual's spot smoothing: a linear ramp of cos(angle)
    // between the outer and inner cones (squared by the shader).
    const float cosOuter = std::cos(l.outerConeAngle), cosInner = std::cos(l.innerConeAngle);
    g.lightAngleScale = 1.0f / std::max(0.001f, cosInner - cosOuter);
    g.lightAngleOffset = -cosOuter * g.lightAngleScale;
    lights.push_back(g);
  }
  if (!lights.empty()) d.lights = uploadVec("scene.lights", lights);

  if (usesTexture) d.uploadTextures(s.textures, false);
  d.srgbToLinear = uploadVec("scene.srgbToLinear", srgbDecodeTable());
  std::vector<float> unorm(256);
  for (int i = 0; i < 256; ++i) unorm[i] = float(i) / 255.0f;
  d.unormToFloat = uploadVec("scene.unormToFloat", unorm);
  d.srgbEncodePacked = uploadVec("scene.srgbEncodePacked", rast::srgbEncodePacked());
  return d;
}

namespace {

// The next level: each texel the average of its (up to) 2x2 parents, colour in
// linear light, alpha as stored; a data texture's channels all as stored.
std::vector<uint32_t> halve(const std::vector<uint32_t>& src, int w, int h, int& nw, int& nh, bool data) {
  nw = w > 1 ? w / 2 : 1;
  nh = h > 1 ? h / 2 : 1;
  std::vector<uint32_t> out(size_t(nw) * nh);
  for (int y = 0; y < nh; ++y)
    for (int x = 0; x < nw; ++x) {
      double acc[4] = {0, 0, 0, 0};
      int n = 0;
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
          const int sx = std::min(2 * x + dx, w - 1), sy = std::min(2 * y + dy, h - 1);
          const uint32_t c = src[size_t(sy) * w + sx];
          for (int k = 0; k < 3; ++k) {
            const double v = ((c >> (8 * k)) & 0xff) / 255.0;
            acc[k] += data ? v : srgbDecode(v);
          }
          acc[3] += (c >> 24) / 255.0;
          ++n;
        }
      auto byte = [&](int k) { return data ? uint32_t(acc[k] / n * 255.0 + 0.5) : srgbEncodeByte(acc[k] / n); };
      out[size_t(y) * nw + x] = byte(0) | byte(1) << 8 | byte(2) << 16 | uint32_t(acc[3] / n * 255.0 + 0.5) << 24;
    }
  return out;
}

}  // namespace

void DeviceScene::uploadTextures(const std::vector<Texture>& list, bool mipmaps) {
  std::vector<TextureGPU> tex;
  std::vector<uint32_t> texels;
  for (size_t i = 0; i < list.size(); ++i) {
    const Texture& t = list[i];
    const bool data = i < dataTextures_.size() && dataTextures_[i];
    TextureGPU g{uint32_t(texels.size()), t.width, t.height, t.wrapS, t.wrapT, 1, t.magFilter, t.minFilter};
    texels.insert(texels.end(), t.rgba.begin(), t.rgba.end());
    if (mipmaps) {
      std::vector<uint32_t> level = t.rgba;
      int w = t.width, h = t.height;
      while (w > 1 || h > 1) {
        int nw, nh;
        level = halve(level, w, h, nw, nh, data);
        texels.insert(texels.end(), level.begin(), level.end());
        w = nw;
        h = nh;
        ++g.levels;
      }
    }
    tex.push_back(g);
  }
  textures = uploadVec("scene.textures", tex);
  this->texels = uploadVec("scene.texels", texels);
  hasMipmaps = mipmaps;
}

size_t DeviceScene::bytes() const {
  return viewBytes(positions) + viewBytes(normals) + viewBytes(uvs) + viewBytes(uvs1) + viewBytes(colors) + viewBytes(tangents) + viewBytes(indices) +
         viewBytes(draws) + viewBytes(drawTriStart) + viewBytes(drawVertStart) + viewBytes(triDraw) + viewBytes(vertDraw) + viewBytes(materials) + viewBytes(clearcoats) +
         viewBytes(textures) + viewBytes(texels) + viewBytes(srgbToLinear) + viewBytes(unormToFloat) + viewBytes(lights) +
         viewBytes(srgbEncodePacked) + viewBytes(lines) + viewBytes(points) + viewBytes(skinJoints) + viewBytes(skinWeights) +
         viewBytes(joints) + viewBytes(jointNormals) + viewBytes(alphaDraws);
}

}  // namespace rast
