// The glTF loader's entry (loadGltf) and its walk of the parsed model into a
// Scene. loadGltf runs the jobs in order: the file gate (file_gate.cpp), the
// JSON checks (schema_check.cpp), tinygltf's parse with rast's file and image
// callbacks, then the walk here: the default scene's node trees (without
// recursion, since a file may chain millions of nodes; a cycle or a node with
// two parents is an Error, not a hang or an exponential walk), each mesh's
// primitives read through the AccessorReader (accessors.cpp) with every index
// checked against the vertex count, strips, fans and loops turned into lists,
// materials and textures (image_decode.cpp) loaded once however often used, and
// what each primitive will hold charged to the memory budget before it is
// built. Every failure, wherever it is met, leaves as one one-line Error that
// names the file, never as a crash or a partial scene.
#include "host/gltf/gltf_internal.h"
#include "host/scene/tangents.h"

#include <glm/gtc/constants.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>

namespace rast {
namespace gltf_detail {
namespace {

// ---------------------------------------------------------------- model walk

bool allFinite(const std::vector<float>& v) {
  return std::all_of(v.begin(), v.end(), [](float x) { return std::isfinite(x); });
}

glm::dmat4 nodeMatrix(const tinygltf::Node& n) {
  if (n.matrix.size() == 16) return glm::make_mat4(n.matrix.data());
  glm::dmat4 t(1.0), r(1.0), s(1.0);
  if (n.translation.size() == 3) t = glm::translate(glm::dmat4(1.0), glm::make_vec3(n.translation.data()));
  // glTF rotations are unit quaternions; files store them rounded, so normalise
  // (as glref and OpenGL viewers do) rather than scale the mesh slightly.
  if (n.rotation.size() == 4)
    r = glm::mat4_cast(glm::normalize(glm::dquat(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2])));
  if (n.scale.size() == 3) s = glm::scale(glm::dmat4(1.0), glm::make_vec3(n.scale.data()));
  return t * r * s;
}

class Loader {
 public:
  Loader(const tinygltf::Model& m, Scene& s, LoadContext& ctx) : m_(m), s_(s), ctx_(ctx), acc_(m, ctx) {}

  void run() {
    std::vector<int> roots;
    if (!m_.scenes.empty()) {
      const int si = m_.defaultScene >= 0 ? m_.defaultScene : 0;
      if (size_t(si) >= m_.scenes.size()) throw Error("default scene index " + std::to_string(si) + " out of range");
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
    state_.assign(m_.nodes.size(), 0);
    for (int r : roots) traverse(r);
    gatherFacts();
    if (!s_.tangents.empty() && s_.tangents.size() < s_.positions.size()) {  // later primitives without tangents
      ctx_.ledger.charge("tangents", mulSat(s_.positions.size() - s_.tangents.size(), sizeof(float4)));
      s_.tangents.resize(s_.positions.size(), float4{0.0f, 0.0f, 0.0f, 0.0f});
    }
    if (!s_.uvs1.empty() && s_.uvs1.size() < s_.positions.size()) {  // later primitives with one set
      ctx_.ledger.charge("second texture coordinates", mulSat(s_.positions.size() - s_.uvs1.size(), sizeof(float2)));
      s_.uvs1.resize(s_.positions.size(), float2{0.0f, 0.0f});
    }
    if (s_.draws.empty()) throw Error("the scene has no triangles, lines or points to draw");
    buildRig(m_, ctx_, s_, walk_);  // animation_load.cpp
  }

 private:
  // Depth-first walk without recursion (a file may chain millions of nodes).
  // glTF nodes form disjoint trees: a node met twice is a cycle (still on the
  // path) or a second parent; both are errors (the latter could otherwise
  // blow up exponentially).
  void traverse(int root) {
    struct Frame {
      int node;
      glm::dmat4 world;
      size_t nextChild;
    };
    std::vector<Frame> stack;
    auto enter = [&](int ni, const glm::dmat4& parent) {
      if (ni < 0 || size_t(ni) >= m_.nodes.size()) throw Error("node index " + std::to_string(ni) + " out of range");
      if (state_[ni] == 1) throw Error("node hierarchy has a cycle through node " + std::to_string(ni));
      if (state_[ni] == 2)
        throw Error("node " + std::to_string(ni) + " appears twice in the scene hierarchy (glTF nodes form disjoint trees)");
      state_[ni] = 1;
      const tinygltf::Node& n = m_.nodes[ni];
      const glm::dmat4 world = parent * nodeMatrix(n);
      for (int k = 0; k < 16; ++k)
        if (!std::isfinite(glm::value_ptr(world)[k]))
          throw Error("node " + std::to_string(ni) + " has a non-finite transform");
      if (n.camera >= 0) {
        s_.cameras.push_back(fileCamera(n.camera, n.name, world));
      } else if (n.camera < -1) {
        throw Error("camera index " + std::to_string(n.camera) + " out of range");
      }
      const auto light = n.extensions.find("KHR_lights_punctual");
      if (light != n.extensions.end()) {
        ++s_.facts.lightNodes;
        const tinygltf::Value& x = light->second;
        if (!x.IsObject() || !x.Has("light") || !x.Get("light").IsInt())
          throw Error("node " + std::to_string(ni) + " KHR_lights_punctual: light must be an integer index");
        s_.lights.push_back(readLight(m_, x.Get("light").GetNumberAsInt(), n.name, world));
      }
      if (n.mesh >= 0) {
        if (size_t(n.mesh) >= m_.meshes.size()) throw Error("mesh index " + std::to_string(n.mesh) + " out of range");
        const std::vector<uint32_t>& prims = meshPrims(n.mesh);
        const std::vector<glm::dmat4> inst = instanceMatrices(m_, ctx_, ni, prims.size());  // instancing.cpp
        for (size_t i = 0; i < std::max<size_t>(inst.size(), 1); ++i)
          for (uint32_t p : prims) {
            s_.draws.push_back(Draw{p, inst.empty() ? world : world * inst[i]});
            walk_.drawNode.push_back(ni);
            walk_.drawInstance.push_back(inst.empty() ? glm::dmat4(1.0) : inst[i]);
          }
      } else if (n.mesh < -1) {
        throw Error("mesh index " + std::to_string(n.mesh) + " out of range");
      }
      stack.push_back(Frame{ni, world, 0});
    };
    enter(root, glm::dmat4(1.0));
    while (!stack.empty()) {
      Frame& f = stack.back();
      const std::vector<int>& children = m_.nodes[f.node].children;
      if (f.nextChild < children.size()) {
        const int c = children[f.nextChild++];
        const glm::dmat4 world = f.world;  // enter() may reallocate the stack
        enter(c, world);
      } else {
        state_[f.node] = 2;
        stack.pop_back();
      }
    }
  }

  // Camera ci of the file as node `nodeName` places it, its values checked
  // against glTF 2.0's rules (5.12-5.14): a camera that cannot make a view is
  // an Error when the file is loaded, not when --camera picks it.
  FileCamera fileCamera(int ci, const std::string& nodeName, const glm::dmat4& world) const {
    if (size_t(ci) >= m_.cameras.size()) throw Error("camera index " + std::to_string(ci) + " out of range");
    const tinygltf::Camera& gc = m_.cameras[ci];
    const std::string at = "cameras[" + std::to_string(ci) + "]";
    auto finitePositive = [](double v) { return std::isfinite(v) && v > 0.0; };
    FileCamera c;
    c.name = !gc.name.empty() ? gc.name : nodeName;
    c.world = world;
    if (gc.type == "perspective") {
      const tinygltf::PerspectiveCamera& p = gc.perspective;
      if (!finitePositive(p.yfov) || p.yfov >= glm::pi<double>()) throw Error(at + ": perspective yfov must be in (0, pi) radians");
      if (!finitePositive(p.znear)) throw Error(at + ": perspective znear must be positive");
      if (p.zfar != 0.0 && !(std::isfinite(p.zfar) && p.zfar > p.znear))
        throw Error(at + ": perspective zfar must be greater than znear");
      if (p.aspectRatio != 0.0 && !finitePositive(p.aspectRatio))
        throw Error(at + ": perspective aspectRatio must be positive");
      c.yfovRad = p.yfov;
      c.aspectRatio = p.aspectRatio;
      c.znear = p.znear;
      c.zfar = p.zfar;
    } else if (gc.type == "orthographic") {
      const tinygltf::OrthographicCamera& o = gc.orthographic;
      if (!std::isfinite(o.xmag) || o.xmag == 0.0 || !std::isfinite(o.ymag) || o.ymag == 0.0)
        throw Error(at + ": orthographic xmag and ymag must be finite and not zero");
      if (!(std::isfinite(o.znear) && o.znear >= 0.0)) throw Error(at + ": orthographic znear must not be negative");
      if (!(std::isfinite(o.zfar) && o.zfar > o.znear)) throw Error(at + ": orthographic zfar must be greater than znear");
      c.orthographic = true;
      c.xmag = std::abs(o.xmag);
      c.ymag = std::abs(o.ymag);
      c.znear = o.znear;
      c.zfar = o.zfar;
    } else {
      throw Error(at + ": type must be perspective or orthographic");
    }
    return c;
  }

  // What the file declares that `rast info SCENE` reports (FileFacts).
  void gatherFacts() {
    FileFacts& f = s_.facts;
    f.extensionsUsed = m_.extensionsUsed;
    f.extensionsRequired = m_.extensionsRequired;
    for (const tinygltf::Light& l : m_.lights)
      ++f.lightsDeclared[l.type == "directional" ? 0 : l.type == "point" ? 1 : 2];
    f.materials = uint32_t(m_.materials.size());
    for (const tinygltf::Material& gm : m_.materials) {
      const auto& pbr = gm.pbrMetallicRoughness;
      bool emissive = gm.emissiveTexture.index >= 0;
      for (double e : gm.emissiveFactor) emissive = emissive || e != 0.0;
      const bool transform = pbr.baseColorTexture.extensions.count("KHR_texture_transform") ||
                             pbr.metallicRoughnessTexture.extensions.count("KHR_texture_transform") ||
                             gm.normalTexture.extensions.count("KHR_texture_transform") ||
                             gm.occlusionTexture.extensions.count("KHR_texture_transform") ||
                             gm.emissiveTexture.extensions.count("KHR_texture_transform");
      const bool uses[11] = {pbr.baseColorTexture.index >= 0, pbr.metallicRoughnessTexture.index >= 0,
                             gm.normalTexture.index >= 0, gm.occlusionTexture.index >= 0, emissive,
                             gm.alphaMode == "MASK", gm.alphaMode == "BLEND", gm.doubleSided,
                             gm.extensions.count("KHR_materials_unlit") > 0, transform,
                             gm.extensions.count("KHR_materials_clearcoat") > 0};
      for (int k = 0; k < 11; ++k) f.materialUses[k] += uses[k] ? 1 : 0;
    }
  }

  // Loads the primitives of a mesh once, however many nodes use it.
  const std::vector<uint32_t>& meshPrims(int mi) {
    auto it = walk_.meshPrims.find(mi);
    if (it != walk_.meshPrims.end()) return it->second;
    std::vector<uint32_t>& out = walk_.meshPrims[mi];
    const tinygltf::Mesh& mesh = m_.meshes[mi];
    for (const tinygltf::Primitive& p : mesh.primitives) {
      const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
      if (mode < 0 || mode > 6) throw Error("primitive mode " + std::to_string(mode) + " is invalid");
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
    chargePrim(p, mode, posA, attr("NORMAL") >= 0, attr("COLOR_0") >= 0);
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
      if (!allFinite(nf)) throw Error("NORMAL accessor " + std::to_string(nA) + " has non-finite values");
      nrm.resize(nv);
      for (size_t i = 0; i < nv; ++i) nrm[i] = {nf[3 * i], nf[3 * i + 1], nf[3 * i + 2]};
    }

    int32_t matIndex = -1;
    LoadedMaterial lm{-1, -1, UvTransform{}};
    if (p.material >= 0) {
      if (size_t(p.material) >= m_.materials.size()) throw Error("material index " + std::to_string(p.material) + " out of range");
      lm = material(p.material);
      matIndex = lm.index;
    } else if (p.material < -1) {
      throw Error("material index out of range");
    }

    // The material's coordinates (points and lines are not textured): its
    // first set, and the second where its textures sample two (Scene::uvs1).
    auto readUv = [&](int set, const UvTransform& xf) {
      std::vector<float2> out;
      if (set < 0 || mode < TINYGLTF_MODE_TRIANGLES) return out;
      const int uvA = attr(("TEXCOORD_" + std::to_string(set)).c_str());
      if (uvA < 0) throw Error("material samples TEXCOORD_" + std::to_string(set) + " which the primitive lacks");
      const std::vector<float> uf = acc_.floats(uvA, 2, "TEXCOORD");
      if (uf.size() / 2 != nv) throw Error("TEXCOORD count differs from POSITION count");
      if (!allFinite(uf)) throw Error("TEXCOORD accessor " + std::to_string(uvA) + " has non-finite values");
      out.resize(nv);
      for (size_t i = 0; i < nv; ++i) out[i] = {uf[2 * i], uf[2 * i + 1]};
      applyUvTransform(xf, out);
      return out;
    };
    const int texCoordSet = lm.texCoordSet;
    std::vector<float2> uv = readUv(texCoordSet, lm.uv);
    std::vector<float2> uv1 = readUv(lm.texCoordSet1, lm.uv1);
    if (!uv1.empty()) ctx_.ledger.charge("second texture coordinates", mulSat(nv, sizeof(float2)));

    std::vector<float4> col;
    const int cA = attr("COLOR_0");
    if (cA >= 0) {
      const int comps = acc_.components(cA, "COLOR_0");
      if (comps != 3 && comps != 4) throw Error("COLOR_0 must be VEC3 or VEC4");
      const std::vector<float> cf = acc_.floats(cA, comps, "COLOR_0");
      if (cf.size() / comps != nv) throw Error("COLOR_0 count differs from POSITION count");
      if (!allFinite(cf)) throw Error("COLOR_0 accessor " + std::to_string(cA) + " has non-finite values");
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

    if (mode <= TINYGLTF_MODE_LINE_STRIP) {
      // Points and lines (docs/points-lines.md): loops and strips become
      // segment lists here (glTF 2.0 section 3.7.2.1), so the pipeline sees
      // only points and independent segments. A loop closes with the segment
      // from its last vertex back to its first; a LINES list of odd length
      // loses its incomplete last segment; a strip or loop of one vertex draws
      // nothing.
      std::vector<uint32_t> seg, pts;
      if (mode == TINYGLTF_MODE_POINTS) {
        pts = seq;
      } else if (mode == TINYGLTF_MODE_LINE) {
        seg.assign(seq.begin(), seq.end() - seq.size() % 2);
      } else {
        for (size_t i = 0; i + 1 < seq.size(); ++i) {
          seg.push_back(seq[i]);
          seg.push_back(seq[i + 1]);
        }
        if (mode == TINYGLTF_MODE_LINE_LOOP && seq.size() >= 2) {
          seg.push_back(seq.back());
          seg.push_back(seq.front());
        }
      }
      return addLinePrim(s_, pos, cA >= 0 ? &col : nullptr, seg, pts, matIndex);
    }

    // Strips and fans become lists (glTF 2.0 section 3.7.2.1). A list whose
    // length is not a multiple of 3 loses its incomplete last triangle.
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
    const std::vector<float4> tan = tangents(p, matIndex, nA >= 0, pos, nrm, uv, uv1, col, idx);
    const uint32_t added = addPrim(s_, pos, nA >= 0 ? &nrm : nullptr, texCoordSet >= 0 ? &uv : nullptr,
                                   cA >= 0 ? &col : nullptr, idx, matIndex);
    if (!uv1.empty()) {  // vertex for vertex as addPrim stored them (a vertex per corner with flat normals)
      s_.uvs1.resize(s_.prims[added].firstVertex, float2{0.0f, 0.0f});
      if (nA >= 0) s_.uvs1.insert(s_.uvs1.end(), uv1.begin(), uv1.end());
      else for (uint32_t i : idx) s_.uvs1.push_back(uv1[i]);
    }
    if (!tan.empty()) {  // earlier primitives without tangents get none (Scene::tangents)
      s_.tangents.resize(s_.prims[added].firstVertex, float4{0.0f, 0.0f, 0.0f, 0.0f});
      s_.tangents.insert(s_.tangents.end(), tan.begin(), tan.end());
    }
    if (nA < 0 && (attr("JOINTS_0") >= 0 || !p.targets.empty())) walk_.flatCorners[added] = idx;  // a vertex per corner
    return added;
  }

  // Normal mapping's tangents of a primitive (Scene::tangents), only where
  // its material has a normal texture: the file's TANGENT (its w taken as
  // the sign it carries), else generated per vertex (host/scene/tangents.h).
  // Without NORMAL there are none: flat normals are generated and a file's
  // tangents MUST then be ignored (glTF 2.0 3.7.2.1); the shader's frame of
  // each triangle is exactly what generation would give there.
  std::vector<float4> tangents(const tinygltf::Primitive& p, int32_t matIndex, bool hasNormals,
                               std::vector<float3>& pos, std::vector<float3>& nrm, std::vector<float2>& uv,
                               std::vector<float2>& uv1, std::vector<float4>& col, std::vector<uint32_t>& idx) {
    if (matIndex < 0 || !s_.materials[matIndex].anyNormalMap() || !hasNormals || uv.empty()) return {};
    // The frame of the base's normal map, else of the clearcoat's (one frame a vertex serves both).
    const Material& mt = s_.materials[matIndex];
    const TextureSlot mapSlot = mt.normalTexture >= 0 ? SlotNormal : SlotClearcoatNormal;
    const std::vector<float2>& normalUv = mt.uv1Slots >> mapSlot & 1u ? uv1 : uv;
    const size_t nv = pos.size();
    const std::string what = "tangents (" + std::to_string(nv) + " vertices)";
    ctx_.ledger.check(what, mulSat(nv, 2 * sizeof(float4)));
    ctx_.ledger.charge(what, mulSat(nv, sizeof(float4)));
    const auto it = p.attributes.find("TANGENT");
    if (it == p.attributes.end()) {
      ++s_.facts.generatedTangentPrims;
      // Vertices split at mirrored seams, as MikkTSpace splits them, except
      // where per-vertex skin or morph data would have to follow.
      const bool split = !p.attributes.count("JOINTS_0") && p.targets.empty();
      GeneratedTangents g = generateTangents(pos, nrm, normalUv, idx, split);
      if (!g.copies.empty()) {
        const std::string more = "vertices split for tangents (" + std::to_string(g.copies.size()) + ")";
        ctx_.ledger.charge(more, mulSat(g.copies.size(), 12 + 12 + 8 + 16 + (uv1.empty() ? 0 : 8) + (col.empty() ? 0 : 16)));
        for (uint32_t v : g.copies) {
          pos.push_back(pos[v]);
          nrm.push_back(nrm[v]);
          uv.push_back(uv[v]);
          if (!uv1.empty()) uv1.push_back(uv1[v]);
          if (!col.empty()) col.push_back(col[v]);
        }
      }
      return std::move(g.tangents);
    }
    ++s_.facts.tangentPrims;
    const std::vector<float> tf = acc_.floats(it->second, 4, "TANGENT");
    if (tf.size() / 4 != nv) throw Error("TANGENT count differs from POSITION count");
    if (!allFinite(tf)) throw Error("TANGENT accessor " + std::to_string(it->second) + " has non-finite values");
    std::vector<float4> out(nv);
    for (size_t i = 0; i < nv; ++i)
      out[i] = {tf[4 * i], tf[4 * i + 1], tf[4 * i + 2], tf[4 * i + 3] < 0.0f ? -1.0f : 1.0f};
    return out;
  }

  // What the primitive will hold in the scene (positions, normals, texture
  // coordinates, colours, 3 indices per triangle) is charged once its
  // positions are read and checked, before the indices and the triangles
  // (strips, flat normals multiply them); converting needs as much again.
  void chargePrim(const tinygltf::Primitive& p, int mode, int posA, bool hasNormal, bool hasColor) {
    if (size_t(posA) >= m_.accessors.size()) return;  // reported by the reader
    const uint64_t nv = m_.accessors[posA].count;
    uint64_t n = nv;
    if (p.indices >= 0 && size_t(p.indices) < m_.accessors.size()) n = m_.accessors[p.indices].count;
    const uint64_t tris = mode == TINYGLTF_MODE_TRIANGLES ? n / 3 : n > 2 ? n - 2 : 0;
    // Without normals, flat shading gives every triangle its own 3 vertices.
    const uint64_t stored = hasNormal ? nv : addSat(nv, mulSat(tris, 3));
    const uint64_t perVertex = 12 + 12 + 8 + (hasColor ? 16 : 0);
    const uint64_t bytes = addSat(mulSat(stored, perVertex), mulSat(tris, 12));
    const std::string what = "mesh primitive (" + std::to_string(nv) + " vertices, " + std::to_string(tris) + " triangles)";
    ctx_.ledger.check(what, mulSat(bytes, 2));
    ctx_.ledger.charge(what, bytes);
  }

  // A texture's transform (KHR_texture_transform): an affine map of its
  // texture coordinates, uv' = T(offset) R(rotation) S(scale) uv. It is baked
  // into the primitive's coordinates at load (applyUvTransform; the second
  // coordinates hold the other transform when a material has two): a
  // primitive has one material, and an affine map commutes with the
  // barycentric interpolation of the coordinates, so the texels sampled (and
  // the derivatives that pick mip levels) are the spec's, at no cost a frame.
  struct UvTransform {
    bool on = false;
    double m[6] = {1, 0, 0, 0, 1, 0};  // u' = m0 u + m1 v + m2, v' = m3 u + m4 v + m5
  };

  static UvTransform uvTransform(const tinygltf::TextureInfo& ti, const std::string& slot, int* set) {
    UvTransform t;
    const auto it = ti.extensions.find("KHR_texture_transform");
    if (it == ti.extensions.end()) return t;
    const tinygltf::Value& x = it->second;
    const std::string at = slot + " KHR_texture_transform: ";
    if (!x.IsObject()) throw Error(at + "must be an object");
    auto pair = [&](const char* key, double d0, double d1, double out[2]) {
      out[0] = d0;
      out[1] = d1;
      if (!x.Has(key)) return;
      const tinygltf::Value& v = x.Get(key);
      if (!v.IsArray() || v.ArrayLen() != 2 || !v.Get(0).IsNumber() || !v.Get(1).IsNumber())
        throw Error(at + key + " must be an array of 2 numbers");
      out[0] = v.Get(0).GetNumberAsDouble();
      out[1] = v.Get(1).GetNumberAsDouble();
      if (!std::isfinite(out[0]) || !std::isfinite(out[1])) throw Error(at + key + " must be finite");
    };
    double offset[2], scale[2], rotation = 0.0;
    pair("offset", 0.0, 0.0, offset);
    pair("scale", 1.0, 1.0, scale);
    if (x.Has("rotation")) {
      const tinygltf::Value& r = x.Get("rotation");
      if (!r.IsNumber() || !std::isfinite(r.GetNumberAsDouble())) throw Error(at + "rotation must be a finite number");
      rotation = r.GetNumberAsDouble();
    }
    if (x.Has("texCoord")) {  // overrides the textureInfo's set
      const tinygltf::Value& c = x.Get("texCoord");
      if (!c.IsInt() || c.GetNumberAsInt() < 0) throw Error(at + "texCoord must be a non-negative integer");
      *set = c.GetNumberAsInt();
    }
    const double cs = std::cos(rotation), sn = std::sin(rotation);
    t.on = true;
    const double m[6] = {cs * scale[0], sn * scale[1], offset[0], -sn * scale[0], cs * scale[1], offset[1]};
    std::copy(m, m + 6, t.m);
    return t;
  }

  static void applyUvTransform(const UvTransform& t, std::vector<float2>& uv) {
    if (!t.on) return;
    for (float2& p : uv) {
      const double u = p.x, v = p.y;
      p = {float(t.m[0] * u + t.m[1] * v + t.m[2]), float(t.m[3] * u + t.m[4] * v + t.m[5])};
    }
  }

  struct LoadedMaterial {
    int32_t index;
    int texCoordSet;  // -1: untextured
    UvTransform uv;
    int texCoordSet1 = -1;  // the second coordinates (Material::uv1Slots), -1: none
    UvTransform uv1;
  };

  static bool sameUse(int setA, const UvTransform& a, int setB, const UvTransform& b) {
    return setA == setB && std::equal(a.m, a.m + 6, b.m);
  }

  const LoadedMaterial& material(int mi) {
    auto it = matCache_.find(mi);
    if (it == matCache_.end()) {
      const tinygltf::Material& gm = m_.materials[mi];
      Material mat = readMaterial(m_, mi, [&](int ti, const char*) { return texture(ti); });
      // Each texture samples its own set (texCoord, or its transform's
      // texCoord override) through its own transform. The first textured
      // slot (the base colour's when it has one) defines the primitive's
      // first coordinates, the first slot that differs in set or transform
      // the second (Material::uv1Slots); a third is refused.
      struct Slot {
        const char* name;
        TextureSlot slot;
        tinygltf::TextureInfo info;
      };
      auto info = [](int index, int texCoord, const tinygltf::ExtensionMap& ext) {
        tinygltf::TextureInfo t;
        t.index = index;
        t.texCoord = texCoord;
        t.extensions = ext;
        return t;
      };
      const auto& pbr = gm.pbrMetallicRoughness;
      // KHR_materials_clearcoat's textures, where the material has a coat (readMaterial loaded them).
      const std::string ccAt = "materials[" + std::to_string(mi) + "] KHR_materials_clearcoat: ";
      const tinygltf::Value* cc = mat.hasClearcoat() ? clearcoatOf(gm, ccAt) : nullptr;
      auto ccInfo = [&](const char* key) {
        if (!cc) return info(-1, 0, {});
        const ExtTexture t = extTexture(m_, *cc, key, ccAt);
        return info(t.index, t.texCoord, t.extensions);
      };
      const Slot slots[8] = {
          {"baseColorTexture", SlotBaseColor, pbr.baseColorTexture},
          {"metallicRoughnessTexture", SlotMetalRough, pbr.metallicRoughnessTexture},
          {"emissiveTexture", SlotEmissive, gm.emissiveTexture},
          {"normalTexture", SlotNormal, info(gm.normalTexture.index, gm.normalTexture.texCoord, gm.normalTexture.extensions)},
          {"occlusionTexture", SlotOcclusion,
           info(gm.occlusionTexture.index, gm.occlusionTexture.texCoord, gm.occlusionTexture.extensions)},
          {"clearcoatTexture", SlotClearcoat, ccInfo("clearcoatTexture")},
          {"clearcoatRoughnessTexture", SlotClearcoatRoughness, ccInfo("clearcoatRoughnessTexture")},
          {"clearcoatNormalTexture", SlotClearcoatNormal, ccInfo("clearcoatNormalTexture")}};
      LoadedMaterial lm{0, -1, UvTransform{}};
      for (const Slot& sl : slots) {
        if (sl.info.index < 0) continue;
        int set = sl.info.texCoord;
        const std::string at = "materials[" + std::to_string(mi) + "] " + sl.name;
        if (set < 0) throw Error(at + " texCoord must not be negative");
        const UvTransform xf = uvTransform(sl.info, at, &set);
        if (lm.texCoordSet < 0) {
          lm.texCoordSet = set;
          lm.uv = xf;
        } else if (!sameUse(set, xf, lm.texCoordSet, lm.uv)) {
          if (lm.texCoordSet1 < 0) {
            lm.texCoordSet1 = set;
            lm.uv1 = xf;
          } else if (!sameUse(set, xf, lm.texCoordSet1, lm.uv1)) {
            throw Error(at + ": a third set of texture coordinates or transform in one material (rast samples two)");
          }
          mat.uv1Slots |= 1u << sl.slot;
        }
      }
      if (mat.uv1Slots) ++s_.facts.twoUvMaterials;
      s_.materials.push_back(mat);
      lm.index = int32_t(s_.materials.size() - 1);
      it = matCache_.emplace(mi, lm).first;
    }
    return it->second;
  }

  // Decodes a texture once, however many materials use it.
  int32_t texture(int ti) {
    // Textures of the same image and sampler share one decoded Texture (and
    // one charge to the budget), whichever texture index names them.
    std::pair<int, int> key{ti, -1};
    if (ti >= 0 && size_t(ti) < m_.textures.size()) key = {m_.textures[ti].source, m_.textures[ti].sampler};
    auto it = texCache_.find(key);
    if (it != texCache_.end()) return it->second;
    s_.textures.push_back(decodeTexture(m_, ti, ctx_.ledger));
    return texCache_[key] = int32_t(s_.textures.size() - 1);
  }

  const tinygltf::Model& m_;
  Scene& s_;
  LoadContext& ctx_;
  AccessorReader acc_;
  std::vector<char> state_;  // per node: 0 not seen, 1 on the current path, 2 done
  WalkRecord walk_;  // draws' nodes, meshes' primitives (gltf_internal.h), for the rig
  std::map<int, LoadedMaterial> matCache_;
  std::map<std::pair<int, int>, int32_t> texCache_;  // (image, sampler) -> scene texture
};

Scene loadChecked(const std::string& path, const LoadOptions& options) {
  const std::vector<unsigned char> bytes = readWholeFile(path, options.maxMemory ? options.maxMemory : defaultMemoryBudget());
  LoadContext ctx(path, options);
  ctx.ledger.charge("the file", bytes.size());
  ctx.zeroElementsLeft = std::max(kMinZeroElements, mulSat(bytes.size(), kZeroElementsPerFileByte));

  // Sniff the GLB magic instead of trusting the extension.
  const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  GlbLayout glb;
  if (binary) glb = checkGlb(bytes);
  const char* json = reinterpret_cast<const char*>(bytes.data()) + (binary ? glb.jsonOffset : 0);
  size_t jsonLength = binary ? glb.jsonLength : bytes.size();
  nlohmann::json doc = parseJson(json, jsonLength, ctx.ledger);
  checkDocument(doc, ctx);
  std::vector<unsigned char> stubbed;  // what tinygltf refuses, stubbed (compression.cpp)
  if (stubForTinygltf(doc, binary, bytes, glb, stubbed)) {
    if (binary) {
      glb.length = stubbed.size();
    } else {
      json = reinterpret_cast<const char*>(stubbed.data());
      jsonLength = stubbed.size();
    }
  }
  doc = nlohmann::json();

  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(loadImageChecked, &ctx);
  loader.SetFsCallbacks({&fileExistsForTinygltf, &expandPathForTinygltf, &readFileForTinygltf, &writeFileForTinygltf, &ctx});
  tinygltf::Model model;
  std::string err, warn;
  bool ok = false;
  const std::string& baseDir = ctx.resolver.baseDir();
  try {
    const unsigned char* glbBytes = stubbed.empty() ? bytes.data() : stubbed.data();
    ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, glbBytes, unsigned(glb.length), baseDir)
                : loader.LoadASCIIFromString(&model, &err, &warn, json, unsigned(jsonLength), baseDir);
  } catch (const std::exception& e) {
    // nlohmann::json throws on some type mismatches inside tinygltf.
    throw Error("malformed glTF: " + oneLine(e.what()));
  }
  // A refused or over-budget external file or image, even where tinygltf only warns.
  if (!ctx.fatal.empty()) throw Error(ctx.fatal);
  if (!ok || !err.empty()) {
    std::string why = oneLine(err.empty() ? warn : err);
    throw Error(why.empty() ? std::string("not a valid glTF file") : why);
  }
  if (model.asset.version.rfind("2.", 0) != 0)
    throw Error("glTF version '" + model.asset.version + "' is not 2.x");
  Scene s;
  s.name = path;
  s.sourceFiles.push_back(path);
  s.sourceFiles.insert(s.sourceFiles.end(), ctx.filesRead.begin(), ctx.filesRead.end());
  decodeCompressed(model, ctx);  // compression.cpp
  Loader(model, s, ctx).run();
  s.validate();
  return s;
}

}  // namespace
}  // namespace gltf_detail

Scene loadGltf(const std::string& path, const LoadOptions& options) {
  try {
    return gltf_detail::loadChecked(path, options);
  } catch (const Error& e) {
    const std::string what = gltf_detail::oneLine(e.what());
    // Messages about the file as a whole already name it.
    if (what.find("'" + path + "'") != std::string::npos) throw Error(what);
    throw Error("'" + gltf_detail::oneLine(path) + "': " + what);
  }
}

}  // namespace rast
