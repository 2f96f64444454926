// glTF 2.0 loading through tinygltf, with every index and range checked so that
// a malformed file ends in one clear Error, never in a crash or a partial scene.
#include "gltf_loader.h"

#include <tiny_gltf.h>

#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>

namespace rast {
namespace {

std::string oneLine(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

// Reads accessor `index` as `count` rows of `comps` floats (normalized integers
// mapped to [0,1] or [-1,1] as the spec says), honouring byteStride and sparse
// substitution.
class AccessorReader {
 public:
  explicit AccessorReader(const tinygltf::Model& m) : m_(m) {}

  std::vector<float> floats(int index, int comps, const char* what) const {
    const tinygltf::Accessor& a = accessor(index, what);
    if (tinygltf::GetNumComponentsInType(a.type) != comps)
      throw Error(std::string(what) + ": accessor " + std::to_string(index) + " has the wrong type");
    std::vector<float> out(a.count * comps, 0.0f);
    if (a.bufferView >= 0) {
      Span sp = span(a, comps, what);
      for (size_t i = 0; i < a.count; ++i)
        for (int c = 0; c < comps; ++c)
          out[i * comps + c] = component(sp.data + i * sp.stride + c * sp.compSize, a.componentType, a.normalized, what);
    }
    applySparse(a, comps, what, [&](size_t row, const unsigned char* p, size_t compSize) {
      for (int c = 0; c < comps; ++c)
        out[row * comps + c] = component(p + c * compSize, a.componentType, a.normalized, what);
    });
    return out;
  }

  std::vector<uint32_t> indices(int index) const {
    const char* what = "indices";
    const tinygltf::Accessor& a = accessor(index, what);
    if (a.type != TINYGLTF_TYPE_SCALAR) throw Error("indices accessor is not SCALAR");
    if (a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
        a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
      throw Error("indices accessor has a component type other than u8/u16/u32");
    std::vector<uint32_t> out(a.count, 0);
    if (a.bufferView >= 0) {
      Span sp = span(a, 1, what);
      for (size_t i = 0; i < a.count; ++i) out[i] = uintAt(sp.data + i * sp.stride, a.componentType);
    }
    applySparse(a, 1, what, [&](size_t row, const unsigned char* p, size_t) { out[row] = uintAt(p, a.componentType); });
    return out;
  }

  size_t count(int index, const char* what) const { return accessor(index, what).count; }

 private:
  struct Span {
    const unsigned char* data;
    size_t stride, compSize;
  };

  const tinygltf::Accessor& accessor(int index, const char* what) const {
    if (index < 0 || size_t(index) >= m_.accessors.size())
      throw Error(std::string(what) + ": accessor index " + std::to_string(index) + " out of range");
    return m_.accessors[index];
  }

  static size_t compSizeOf(int componentType, const char* what) {
    const int s = tinygltf::GetComponentSizeInBytes(componentType);
    if (s <= 0) throw Error(std::string(what) + ": unknown component type " + std::to_string(componentType));
    return size_t(s);
  }

  // Bytes [offset, offset+len) of buffer view `bv`, checked against the buffer.
  const unsigned char* viewBytes(int bv, size_t offset, size_t len, const char* what, size_t* strideOut) const {
    if (bv < 0 || size_t(bv) >= m_.bufferViews.size())
      throw Error(std::string(what) + ": bufferView index " + std::to_string(bv) + " out of range");
    const tinygltf::BufferView& v = m_.bufferViews[bv];
    if (v.buffer < 0 || size_t(v.buffer) >= m_.buffers.size())
      throw Error(std::string(what) + ": buffer index out of range");
    const tinygltf::Buffer& b = m_.buffers[v.buffer];
    if (v.byteOffset + v.byteLength > b.data.size() || v.byteOffset + v.byteLength < v.byteOffset)
      throw Error(std::string(what) + ": bufferView " + std::to_string(bv) + " reaches past the end of its buffer");
    if (offset + len > v.byteLength || offset + len < offset)
      throw Error(std::string(what) + ": accessor reaches past the end of bufferView " + std::to_string(bv));
    if (strideOut) *strideOut = v.byteStride;
    return b.data.data() + v.byteOffset + offset;
  }

  Span span(const tinygltf::Accessor& a, int comps, const char* what) const {
    const size_t cs = compSizeOf(a.componentType, what);
    const size_t elem = cs * size_t(comps);
    const tinygltf::BufferView* bv =
        (a.bufferView >= 0 && size_t(a.bufferView) < m_.bufferViews.size()) ? &m_.bufferViews[a.bufferView] : nullptr;
    const size_t stride = (bv && bv->byteStride) ? bv->byteStride : elem;
    if (stride < elem) throw Error(std::string(what) + ": byteStride smaller than the element");
    const size_t len = a.count ? stride * (a.count - 1) + elem : 0;
    const unsigned char* p = viewBytes(a.bufferView, a.byteOffset, len, what, nullptr);
    return {p, stride, cs};
  }

  template <class F>
  void applySparse(const tinygltf::Accessor& a, int comps, const char* what, F&& put) const {
    if (!a.sparse.isSparse) return;
    const size_t n = size_t(std::max(a.sparse.count, 0));
    const int it = a.sparse.indices.componentType;
    const size_t is = compSizeOf(it, what);
    const unsigned char* ip = viewBytes(a.sparse.indices.bufferView, a.sparse.indices.byteOffset, n * is, what, nullptr);
    const size_t cs = compSizeOf(a.componentType, what);
    const unsigned char* vp =
        viewBytes(a.sparse.values.bufferView, a.sparse.values.byteOffset, n * cs * comps, what, nullptr);
    for (size_t k = 0; k < n; ++k) {
      const uint32_t row = uintAt(ip + k * is, it);
      if (row >= a.count) throw Error(std::string(what) + ": sparse index out of range");
      put(row, vp + k * cs * comps, cs);
    }
  }

  static uint32_t uintAt(const unsigned char* p, int type) {
    switch (type) {
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return *p;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t v; memcpy(&v, p, 2); return v; }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { uint32_t v; memcpy(&v, p, 4); return v; }
      default: throw Error("index component type is not unsigned");
    }
  }

  static float component(const unsigned char* p, int type, bool normalized, const char* what) {
    switch (type) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT: { float v; memcpy(&v, p, 4); return v; }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? *p / 255.0f : float(*p);
      case TINYGLTF_COMPONENT_TYPE_BYTE: { int8_t v; memcpy(&v, p, 1); return normalized ? std::max(v / 127.0f, -1.0f) : float(v); }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t v; memcpy(&v, p, 2); return normalized ? v / 65535.0f : float(v); }
      case TINYGLTF_COMPONENT_TYPE_SHORT: { int16_t v; memcpy(&v, p, 2); return normalized ? std::max(v / 32767.0f, -1.0f) : float(v); }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { uint32_t v; memcpy(&v, p, 4); return float(v); }
      default: throw Error(std::string(what) + ": unsupported component type " + std::to_string(type));
    }
  }

  const tinygltf::Model& m_;
};

glm::dmat4 nodeMatrix(const tinygltf::Node& n) {
  if (n.matrix.size() == 16) return glm::make_mat4(n.matrix.data());
  glm::dmat4 t(1.0), r(1.0), s(1.0);
  if (n.translation.size() == 3) t = glm::translate(glm::dmat4(1.0), glm::make_vec3(n.translation.data()));
  if (n.rotation.size() == 4) r = glm::mat4_cast(glm::dquat(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]));
  if (n.scale.size() == 3) s = glm::scale(glm::dmat4(1.0), glm::make_vec3(n.scale.data()));
  return t * r * s;
}

Texture decodeTexture(const tinygltf::Model& m, int texIndex) {
  if (texIndex < 0 || size_t(texIndex) >= m.textures.size()) throw Error("texture index out of range");
  const tinygltf::Texture& t = m.textures[texIndex];
  if (t.source < 0 || size_t(t.source) >= m.images.size()) throw Error("texture has no valid image source");
  const tinygltf::Image& im = m.images[t.source];
  if (im.width <= 0 || im.height <= 0 || im.image.empty())
    throw Error("texture image " + std::to_string(t.source) + " ('" + im.uri + "') could not be decoded");
  const int comps = im.component, bytes = im.bits / 8;
  if (comps < 1 || comps > 4 || (bytes != 1 && bytes != 2) ||
      im.image.size() < size_t(im.width) * im.height * comps * bytes)
    throw Error("texture image " + std::to_string(t.source) + " has an unsupported layout");
  Texture out;
  out.width = im.width;
  out.height = im.height;
  out.rgba.resize(size_t(im.width) * im.height);
  for (size_t i = 0; i < out.rgba.size(); ++i) {
    uint8_t c[4] = {0, 0, 0, 255};
    for (int k = 0; k < comps; ++k) {
      const unsigned char* p = &im.image[(i * comps + k) * bytes];
      c[k] = bytes == 1 ? p[0] : p[1];  // 16-bit little endian: keep the high byte
    }
    if (comps == 1 || comps == 2) {  // grey (+alpha)
      c[3] = comps == 2 ? c[1] : 255;
      c[1] = c[2] = c[0];
    }
    out.rgba[i] = uint32_t(c[0]) | uint32_t(c[1]) << 8 | uint32_t(c[2]) << 16 | uint32_t(c[3]) << 24;
  }
  if (t.sampler >= 0) {
    if (size_t(t.sampler) >= m.samplers.size()) throw Error("texture sampler index out of range");
    out.wrapS = m.samplers[t.sampler].wrapS;
    out.wrapT = m.samplers[t.sampler].wrapT;
  }
  for (int32_t w : {out.wrapS, out.wrapT})
    if (w != WrapRepeat && w != WrapClamp && w != WrapMirror) throw Error("sampler has an invalid wrap mode");
  return out;
}

class Loader {
 public:
  Loader(const tinygltf::Model& m, Scene& s) : m_(m), s_(s), acc_(m) {}

  void run() {
    std::vector<int> roots;
    if (!m_.scenes.empty()) {
      const int si = m_.defaultScene >= 0 ? m_.defaultScene : 0;
      if (size_t(si) >= m_.scenes.size()) throw Error("default scene index out of range");
      roots = m_.scenes[si].nodes;
    } else {
      // No scene: draw every root node (a node nobody lists as a child).
      std::vector<char> isChild(m_.nodes.size(), 0);
      for (const auto& n : m_.nodes)
        for (int c : n.children)
          if (c >= 0 && size_t(c) < m_.nodes.size()) isChild[c] = 1;
      for (size_t i = 0; i < m_.nodes.size(); ++i)
        if (!isChild[i]) roots.push_back(int(i));
    }
    onPath_.assign(m_.nodes.size(), 0);
    for (int r : roots) visit(r, glm::dmat4(1.0));
    if (s_.draws.empty()) {
      std::string why = "the scene has no triangles to draw";
      if (skipped_) why += " (" + std::to_string(skipped_) + " point/line primitives skipped: not supported yet)";
      throw Error(why);
    }
  }

 private:
  void visit(int ni, const glm::dmat4& parent) {
    if (ni < 0 || size_t(ni) >= m_.nodes.size()) throw Error("node index " + std::to_string(ni) + " out of range");
    if (onPath_[ni]) throw Error("node hierarchy has a cycle through node " + std::to_string(ni));
    onPath_[ni] = 1;
    const tinygltf::Node& n = m_.nodes[ni];
    const glm::dmat4 world = parent * nodeMatrix(n);
    for (int k = 0; k < 16; ++k)
      if (!std::isfinite(glm::value_ptr(world)[k])) throw Error("node " + std::to_string(ni) + " has a non-finite transform");
    if (n.mesh >= 0) {
      if (size_t(n.mesh) >= m_.meshes.size()) throw Error("mesh index " + std::to_string(n.mesh) + " out of range");
      for (uint32_t p : meshPrims(n.mesh)) s_.draws.push_back(Draw{p, world});
    } else if (n.mesh < -1) {
      throw Error("mesh index " + std::to_string(n.mesh) + " out of range");
    }
    for (int c : n.children) visit(c, world);
    onPath_[ni] = 0;
  }

  // Loads the triangle primitives of a mesh once, however many nodes use it.
  const std::vector<uint32_t>& meshPrims(int mi) {
    auto it = meshCache_.find(mi);
    if (it != meshCache_.end()) return it->second;
    std::vector<uint32_t>& out = meshCache_[mi];
    const tinygltf::Mesh& mesh = m_.meshes[mi];
    for (const tinygltf::Primitive& p : mesh.primitives) {
      const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
      if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
        if (mode < 0 || mode > 6) throw Error("primitive mode " + std::to_string(mode) + " is invalid");
        ++skipped_;
        continue;
      }
      out.push_back(loadPrim(p, mode));
    }
    return out;
  }

  uint32_t loadPrim(const tinygltf::Primitive& p, int mode) {
    auto attr = [&](const char* name) {
      auto it = p.attributes.find(name);
      return it == p.attributes.end() ? -1 : it->second;
    };
    const int posA = attr("POSITION");
    if (posA < 0) throw Error("mesh primitive has no POSITION attribute");
    const std::vector<float> pf = acc_.floats(posA, 3, "POSITION");
    const size_t nv = pf.size() / 3;
    std::vector<float3> pos(nv);
    for (size_t i = 0; i < nv; ++i) {
      pos[i] = {pf[3 * i], pf[3 * i + 1], pf[3 * i + 2]};
      if (!std::isfinite(pf[3 * i]) || !std::isfinite(pf[3 * i + 1]) || !std::isfinite(pf[3 * i + 2]))
        throw Error("POSITION accessor " + std::to_string(posA) + " has non-finite values (vertex " + std::to_string(i) + ")");
    }

    std::vector<float3> nrm;
    const int nA = attr("NORMAL");
    if (nA >= 0) {
      const std::vector<float> nf = acc_.floats(nA, 3, "NORMAL");
      if (nf.size() != pf.size()) throw Error("NORMAL count differs from POSITION count");
      nrm.resize(nv);
      for (size_t i = 0; i < nv; ++i) {
        nrm[i] = {nf[3 * i], nf[3 * i + 1], nf[3 * i + 2]};
        if (!isFinite(nrm[i].x) || !isFinite(nrm[i].y) || !isFinite(nrm[i].z))
          throw Error("NORMAL accessor " + std::to_string(nA) + " has non-finite values");
      }
    }

    int32_t matIndex = -1;
    int texCoordSet = -1;
    if (p.material >= 0) {
      if (size_t(p.material) >= m_.materials.size()) throw Error("material index " + std::to_string(p.material) + " out of range");
      matIndex = material(p.material, &texCoordSet);
    } else if (p.material < -1) {
      throw Error("material index out of range");
    }

    std::vector<float2> uv;
    if (texCoordSet >= 0) {
      const int uvA = attr(("TEXCOORD_" + std::to_string(texCoordSet)).c_str());
      if (uvA < 0) throw Error("material samples TEXCOORD_" + std::to_string(texCoordSet) + " which the primitive lacks");
      const std::vector<float> uf = acc_.floats(uvA, 2, "TEXCOORD");
      if (uf.size() / 2 != nv) throw Error("TEXCOORD count differs from POSITION count");
      uv.resize(nv);
      for (size_t i = 0; i < nv; ++i) uv[i] = {uf[2 * i], uf[2 * i + 1]};
    }

    std::vector<float4> col;
    const int cA = attr("COLOR_0");
    if (cA >= 0) {
      const tinygltf::Accessor& a = m_.accessors.at(size_t(cA) < m_.accessors.size() ? cA : 0);
      const int comps = tinygltf::GetNumComponentsInType(a.type);
      if (comps != 3 && comps != 4) throw Error("COLOR_0 must be VEC3 or VEC4");
      const std::vector<float> cf = acc_.floats(cA, comps, "COLOR_0");
      if (cf.size() / comps != nv) throw Error("COLOR_0 count differs from POSITION count");
      col.resize(nv);
      for (size_t i = 0; i < nv; ++i)
        col[i] = {cf[comps * i], cf[comps * i + 1], cf[comps * i + 2], comps == 4 ? cf[comps * i + 3] : 1.0f};
    }

    std::vector<uint32_t> seq;
    if (p.indices >= 0) {
      seq = acc_.indices(p.indices);
    } else if (p.indices < -1) {
      throw Error("indices accessor out of range");
    } else {
      seq.resize(nv);
      for (size_t i = 0; i < nv; ++i) seq[i] = uint32_t(i);
    }
    for (uint32_t i : seq)
      if (i >= nv)
        throw Error("index " + std::to_string(i) + " out of range: the primitive has " + std::to_string(nv) + " vertices");

    // Strips and fans become lists (glTF 2.0 section 3.7.2.1).
    std::vector<uint32_t> idx;
    if (mode == TINYGLTF_MODE_TRIANGLES) {
      idx.assign(seq.begin(), seq.end() - seq.size() % 3);
    } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
      for (size_t i = 0; i + 2 < seq.size(); ++i) {
        idx.push_back(seq[i]);
        idx.push_back(seq[i + 1 + i % 2]);
        idx.push_back(seq[i + 2 - i % 2]);
      }
    } else {
      for (size_t i = 0; i + 2 < seq.size(); ++i) {
        idx.push_back(seq[i + 1]);
        idx.push_back(seq[i + 2]);
        idx.push_back(seq[0]);
      }
    }
    return addPrim(s_, pos, nA >= 0 ? &nrm : nullptr, texCoordSet >= 0 ? &uv : nullptr, cA >= 0 ? &col : nullptr, idx,
                   matIndex);
  }

  int32_t material(int mi, int* texCoordSet) {
    auto it = matCache_.find(mi);
    if (it == matCache_.end()) {
      const tinygltf::Material& gm = m_.materials[mi];
      Material mat;
      const auto& f = gm.pbrMetallicRoughness.baseColorFactor;
      if (f.size() == 4) mat.baseColorFactor = {float(f[0]), float(f[1]), float(f[2]), float(f[3])};
      const auto& bt = gm.pbrMetallicRoughness.baseColorTexture;
      int set = -1;
      if (bt.index >= 0) {
        s_.textures.push_back(decodeTexture(m_, bt.index));
        mat.texture = int32_t(s_.textures.size() - 1);
        set = bt.texCoord;
        if (set < 0) throw Error("material texCoord set is negative");
      }
      s_.materials.push_back(mat);
      it = matCache_.emplace(mi, std::make_pair(int32_t(s_.materials.size() - 1), set)).first;
    }
    *texCoordSet = it->second.second;
    return it->second.first;
  }

  const tinygltf::Model& m_;
  Scene& s_;
  AccessorReader acc_;
  std::vector<char> onPath_;
  std::map<int, std::vector<uint32_t>> meshCache_;
  std::map<int, std::pair<int32_t, int>> matCache_;
  int skipped_ = 0;
};

}  // namespace

Scene loadGltf(const std::string& path) {
  {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw Error("cannot open '" + path + "'");
  }
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string err, warn;
  // Sniff the GLB magic instead of trusting the extension.
  char magic[4] = {0, 0, 0, 0};
  {
    std::ifstream f(path, std::ios::binary);
    f.read(magic, 4);
  }
  const bool binary = std::string(magic, 4) == "glTF";
  bool ok = false;
  try {
    ok = binary ? loader.LoadBinaryFromFile(&model, &err, &warn, path)
                : loader.LoadASCIIFromFile(&model, &err, &warn, path);
  } catch (const std::exception& e) {
    // nlohmann::json throws on some type mismatches inside tinygltf.
    throw Error("'" + path + "': malformed glTF: " + oneLine(e.what()));
  }
  if (!ok || !err.empty())
    throw Error("'" + path + "': " + (err.empty() ? std::string("not a valid glTF file") : oneLine(err)));
  if (model.asset.version.rfind("2.", 0) != 0)
    throw Error("'" + path + "': glTF version '" + model.asset.version + "' is not 2.x");
  Scene s;
  s.name = path;
  try {
    Loader(model, s).run();
    s.validate();
  } catch (const Error& e) {
    throw Error("'" + path + "': " + e.what());
  }
  return s;
}

}  // namespace rast
