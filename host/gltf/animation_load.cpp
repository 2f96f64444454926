// The glTF loader's reading of what moves (host/scene/animation.h): the node
// hierarchy with rest transforms, skins, animations and each deformed draw's
// joints, weights and morph targets. Kept out of model_walk.cpp, which builds
// the static scene; the walk hands over, per draw, the node that placed it and
// the primitives it loaded. Every index, count, key time and value is checked
// here, so that a bad file ends in one clear Error, never in a crash at
// posing time: posing (host/scene/animation.cpp) trusts what this built.
#include "host/gltf/gltf_internal.h"

#include "host/scene/animation.h"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <type_traits>

namespace rast::gltf_detail {
namespace {

bool finiteAll(const std::vector<float>& v) {
  return std::all_of(v.begin(), v.end(), [](float x) { return std::isfinite(x); });
}

class RigBuilder {
 public:
  RigBuilder(const tinygltf::Model& m, LoadContext& ctx, Scene& s, const WalkRecord& w)
      : m_(m), ctx_(ctx), acc_(m, ctx), s_(s), w_(w) {}

  std::shared_ptr<SceneRig> build() {
    bool moves = !m_.animations.empty();
    for (const tinygltf::Mesh& mesh : m_.meshes)
      for (const tinygltf::Primitive& p : mesh.primitives) moves |= !p.targets.empty();
    for (const tinygltf::Node& n : m_.nodes) moves |= n.skin >= 0;
    if (!moves) return nullptr;
    rig_ = std::make_shared<SceneRig>();
    nodes();
    skins();
    animations();
    rig_->drawNode = w_.drawNode;
    for (const glm::dmat4& m : w_.drawInstance)
      if (m != glm::dmat4(1.0)) {
        rig_->drawInstance = w_.drawInstance;
        break;
      }
    deformedDraws();
    return rig_;
  }

 private:
  std::string nodeAt(size_t i) const { return "nodes[" + std::to_string(i) + "]"; }

  // Rest transforms and parents; every node reached once from a root, so a
  // cycle anywhere among the nodes (joints may lie outside the scene) is an Error.
  void nodes() {
    const size_t n = m_.nodes.size();
    rig_->nodes.resize(n);
    for (size_t i = 0; i < n; ++i) {
      const tinygltf::Node& gn = m_.nodes[i];
      RigNode& r = rig_->nodes[i];
      if (gn.matrix.size() == 16) {
        r.hasMatrix = true;
        r.matrix = glm::make_mat4(gn.matrix.data());
      }
      if (gn.translation.size() == 3) r.translation = glm::make_vec3(gn.translation.data());
      if (gn.rotation.size() == 4)
        r.rotation = glm::normalize(glm::dquat(gn.rotation[3], gn.rotation[0], gn.rotation[1], gn.rotation[2]));
      if (gn.scale.size() == 3) r.scale = glm::make_vec3(gn.scale.data());
      for (int c : gn.children) {
        if (c < 0 || size_t(c) >= n) throw Error(nodeAt(i) + ": child index " + std::to_string(c) + " out of range");
        if (rig_->nodes[size_t(c)].parent >= 0 || size_t(c) == i)
          throw Error("node " + std::to_string(c) + " has two parents or is its own child (joint hierarchy must be a tree)");
        rig_->nodes[size_t(c)].parent = int32_t(i);
      }
      // Morph weights: the node's, else its mesh's (checked against the target count below).
      if (gn.mesh >= 0 && size_t(gn.mesh) < m_.meshes.size()) {
        const std::vector<double>& w = gn.weights.empty() ? m_.meshes[size_t(gn.mesh)].weights : gn.weights;
        r.weights = w;
        size_t targets = 0;
        for (const tinygltf::Primitive& p : m_.meshes[size_t(gn.mesh)].primitives) targets = std::max(targets, p.targets.size());
        if (!w.empty() && w.size() != targets)
          throw Error(nodeAt(i) + ": " + std::to_string(w.size()) + " morph weights for " + std::to_string(targets) + " targets");
        for (double x : w)
          if (!std::isfinite(x)) throw Error(nodeAt(i) + ": morph weights must be finite");
        if (w.empty()) r.weights.assign(targets, 0.0);
      }
    }
    // Parents before children, without recursion.
    std::vector<int32_t> stack;
    for (size_t i = 0; i < n; ++i)
      if (rig_->nodes[i].parent < 0) stack.push_back(int32_t(i));
    while (!stack.empty()) {
      const int32_t i = stack.back();
      stack.pop_back();
      rig_->order.push_back(i);
      for (int c : m_.nodes[size_t(i)].children) stack.push_back(c);
    }
    if (rig_->order.size() != n) throw Error("node hierarchy has a cycle (a joint is its own ancestor)");
  }

  void skins() {
    for (size_t k = 0; k < m_.skins.size(); ++k) {
      const tinygltf::Skin& gs = m_.skins[k];
      const std::string at = "skins[" + std::to_string(k) + "]";
      Skin sk;
      if (gs.joints.empty()) throw Error(at + " has no joints");
      for (int j : gs.joints) {
        if (j < 0 || size_t(j) >= m_.nodes.size()) throw Error(at + ": joint node index " + std::to_string(j) + " out of range");
        sk.joints.push_back(j);
      }
      sk.inverseBind.assign(sk.joints.size(), glm::dmat4(1.0));
      if (gs.inverseBindMatrices >= 0) {
        const std::vector<float> f = acc_.floats(gs.inverseBindMatrices, 16, "inverseBindMatrices");
        if (f.size() / 16 < sk.joints.size())
          throw Error(at + ": " + std::to_string(f.size() / 16) + " inverse bind matrices for " + std::to_string(sk.joints.size()) + " joints");
        if (!finiteAll(f)) throw Error(at + ": inverse bind matrices must be finite");
        for (size_t j = 0; j < sk.joints.size(); ++j) sk.inverseBind[j] = glm::dmat4(glm::make_mat4(f.data() + 16 * j));
      }
      rig_->skins.push_back(std::move(sk));
    }
  }

  void animations() {
    for (size_t a = 0; a < m_.animations.size(); ++a) {
      const tinygltf::Animation& ga = m_.animations[a];
      const std::string at = "animations[" + std::to_string(a) + "]";
      Animation an;
      an.name = ga.name;
      an.samplers.resize(ga.samplers.size());
      std::vector<int> comps(ga.samplers.size(), -1);
      bool first = true;
      for (size_t c = 0; c < ga.channels.size(); ++c) {
        const tinygltf::AnimationChannel& gc = ga.channels[c];
        const std::string cat = at + ".channels[" + std::to_string(c) + "]";
        if (gc.target_node < 0) continue;  // no target: ignored, as the spec allows (extensions may set one)
        if (size_t(gc.target_node) >= m_.nodes.size())
          throw Error(cat + ": target node " + std::to_string(gc.target_node) + " out of range");
        if (gc.sampler < 0 || size_t(gc.sampler) >= ga.samplers.size())
          throw Error(cat + ": sampler " + std::to_string(gc.sampler) + " out of range");
        AnimChannel ch;
        ch.node = gc.target_node;
        ch.sampler = gc.sampler;
        int n = 0;
        if (gc.target_path == "translation") { ch.path = AnimPath::Translation; n = 3; }
        else if (gc.target_path == "rotation") { ch.path = AnimPath::Rotation; n = 4; }
        else if (gc.target_path == "scale") { ch.path = AnimPath::Scale; n = 3; }
        else if (gc.target_path == "weights") {
          ch.path = AnimPath::Weights;
          n = int(rig_->nodes[size_t(ch.node)].weights.size());
          if (n == 0) throw Error(cat + ": animates the weights of node " + std::to_string(ch.node) + ", which has no morph targets");
        } else continue;  // "pointer" and other extension paths: not animated
        if (ch.path != AnimPath::Weights && rig_->nodes[size_t(ch.node)].hasMatrix)
          throw Error(cat + ": node " + std::to_string(ch.node) + " has a matrix and cannot be animated");
        if (comps[size_t(ch.sampler)] >= 0 && comps[size_t(ch.sampler)] != n)
          throw Error(cat + ": sampler " + std::to_string(ch.sampler) + " is shared by targets of different sizes");
        if (comps[size_t(ch.sampler)] < 0) {
          comps[size_t(ch.sampler)] = n;
          an.samplers[size_t(ch.sampler)] = sampler(ga.samplers[size_t(ch.sampler)], n, at + ".samplers[" + std::to_string(ch.sampler) + "]");
          const AnimSampler& s = an.samplers[size_t(ch.sampler)];
          an.start = first ? s.times.front() : std::min(an.start, double(s.times.front()));
          an.end = first ? s.times.back() : std::max(an.end, double(s.times.back()));
          first = false;
        }
        an.channels.push_back(ch);
      }
      rig_->animations.push_back(std::move(an));
    }
  }

  AnimSampler sampler(const tinygltf::AnimationSampler& gs, int comps, const std::string& at) {
    AnimSampler s;
    s.comps = uint32_t(comps);
    if (gs.interpolation.empty() || gs.interpolation == "LINEAR") s.interp = Interpolation::Linear;
    else if (gs.interpolation == "STEP") s.interp = Interpolation::Step;
    else if (gs.interpolation == "CUBICSPLINE") s.interp = Interpolation::CubicSpline;
    else throw Error(at + ": unknown interpolation '" + oneLine(gs.interpolation) + "'");
    s.times = acc_.floats(gs.input, 1, "animation sampler input");
    if (s.times.empty()) throw Error(at + ": no keyframes");
    for (size_t k = 0; k < s.times.size(); ++k) {
      if (!std::isfinite(s.times[k])) throw Error(at + ": keyframe time " + std::to_string(k) + " is not finite");
      if (k > 0 && !(s.times[k] > s.times[k - 1]))
        throw Error(at + ": keyframe times must increase (time " + std::to_string(k) + " is not after time " + std::to_string(k - 1) + ")");
    }
    const int per = s.interp == Interpolation::CubicSpline ? 3 : 1;
    // Weights outputs are scalars, one per target per key; the rest VEC3/VEC4.
    const bool scalar = acc_.components(gs.output, "animation sampler output") == 1;
    std::vector<float> v = acc_.floats(gs.output, scalar ? 1 : comps, "animation sampler output");
    const uint64_t want = uint64_t(s.times.size()) * uint64_t(per) * uint64_t(comps);
    if (v.size() != want)
      throw Error(at + ": output has " + std::to_string(v.size() / (scalar ? 1 : comps)) + " elements, " + std::to_string(s.times.size()) +
                  " keyframes need " + std::to_string(want / (scalar ? 1 : comps)));
    if (!finiteAll(v)) throw Error(at + ": output values must be finite (NaN or infinite key)");
    s.values = std::move(v);
    return s;
  }

  // The deformed draws: a skinned node's primitives with JOINTS_0, and
  // primitives with morph targets. A primitive drawn by a second deformed
  // draw is copied, so that each deformed draw owns the vertices it poses.
  void deformedDraws() {
    std::vector<char> owned(s_.prims.size(), 0);
    for (size_t d = 0; d < s_.draws.size(); ++d) {
      const int32_t ni = w_.drawNode[d];
      const tinygltf::Node& gn = m_.nodes[size_t(ni)];
      const auto it = w_.meshPrims.find(gn.mesh);
      if (it == w_.meshPrims.end()) continue;
      const auto k = std::find(it->second.begin(), it->second.end(), s_.draws[d].prim);
      if (k == it->second.end()) continue;
      const tinygltf::Primitive& gp = m_.meshes[size_t(gn.mesh)].primitives[size_t(k - it->second.begin())];
      const bool skinned = gn.skin >= 0 && gp.attributes.count("JOINTS_0");
      if (gn.skin >= 0 && size_t(gn.skin) >= m_.skins.size())
        throw Error(nodeAt(size_t(ni)) + ": skin index " + std::to_string(gn.skin) + " out of range");
      if (!skinned && gp.targets.empty()) continue;
      const uint32_t src = s_.draws[d].prim;
      if (owned[src]) s_.draws[d].prim = copyPrim(src);
      owned[src] = 1;
      DeformedDraw dd;
      dd.draw = uint32_t(d);
      dd.skin = skinned ? gn.skin : -1;
      const MeshPrim& p = s_.prims[s_.draws[d].prim];
      dd.basePositions.assign(s_.positions.begin() + p.firstVertex, s_.positions.begin() + p.firstVertex + p.vertexCount);
      dd.baseNormals.assign(s_.normals.begin() + p.firstVertex, s_.normals.begin() + p.firstVertex + p.vertexCount);
      const auto corners = w_.flatCorners.find(src);
      const std::vector<uint32_t>* corner = corners == w_.flatCorners.end() ? nullptr : &corners->second;
      dd.flatNormals = corner != nullptr;
      const size_t srcCount = m_.accessors[size_t(gp.attributes.at("POSITION"))].count;
      // Bind pose, joints and weights (4 of each a set), deltas: charged before they are read.
      const uint64_t sets = skinned ? (gp.attributes.count("JOINTS_1") ? 2 : 1) : 0;
      ctx_.ledger.charge("posed vertices of draw " + std::to_string(d),
                         mulSat(p.vertexCount, 24 + sets * 24 + mulSat(gp.targets.size(), 24)));
      if (skinned) joints(gp, srcCount, corner, p.vertexCount, dd);
      targets(gp, srcCount, corner, p.vertexCount, dd);
      rig_->deformed.push_back(std::move(dd));
    }
  }

  uint32_t copyPrim(uint32_t src) {
    MeshPrim p = s_.prims[src];
    ctx_.ledger.charge("a copy of a deformed primitive", mulSat(p.vertexCount, 48));
    const uint32_t fv = uint32_t(s_.positions.size()), ft = uint32_t(s_.indices.size() / 3);
    // Through a copy: inserting a vector's own range into it is undefined.
    auto copyRange = [](auto& v, size_t from, size_t count) {
      const std::vector<typename std::decay_t<decltype(v)>::value_type> part(v.begin() + from, v.begin() + from + count);
      v.insert(v.end(), part.begin(), part.end());
    };
    auto dup = [&](auto& v) {
      if (!v.empty()) copyRange(v, p.firstVertex, p.vertexCount);
    };
    dup(s_.positions);
    dup(s_.normals);
    dup(s_.uvs);
    dup(s_.uvs1);
    dup(s_.tangents);
    dup(s_.colors);
    copyRange(s_.indices, 3 * size_t(p.firstTri), 3 * size_t(p.triCount));
    const uint32_t fl = uint32_t(s_.lineIndices.size() / 2), fp = uint32_t(s_.pointIndices.size());
    copyRange(s_.lineIndices, 2 * size_t(p.firstLine), 2 * size_t(p.lineCount));
    copyRange(s_.pointIndices, p.firstPoint, p.pointCount);
    p.firstVertex = fv;
    p.firstTri = ft;
    p.firstLine = fl;
    p.firstPoint = fp;
    s_.prims.push_back(p);
    return uint32_t(s_.prims.size() - 1);
  }

  // An attribute of the source vertices, one row per scene vertex (flat-shaded
  // primitives give each triangle corner its own vertex: `corner` maps them).
  std::vector<float> perVertex(const std::vector<float>& f, int comps, size_t srcCount, const std::vector<uint32_t>* corner,
                               uint32_t nv, const char* what) {
    if (f.size() != srcCount * size_t(comps)) throw Error(std::string(what) + " count differs from POSITION count");
    if (!corner) return f;
    if (corner->size() != nv) throw Error(std::string("internal: ") + what + " corner map");
    std::vector<float> out(size_t(nv) * comps);
    for (uint32_t v = 0; v < nv; ++v)
      for (int c = 0; c < comps; ++c) out[size_t(v) * comps + c] = f[size_t((*corner)[v]) * comps + c];
    return out;
  }

  void joints(const tinygltf::Primitive& gp, size_t srcCount, const std::vector<uint32_t>* corner, uint32_t nv, DeformedDraw& dd) {
    const size_t jointCount = m_.skins[size_t(dd.skin)].joints.size();
    dd.sets = gp.attributes.count("JOINTS_1") && gp.attributes.count("WEIGHTS_1") ? 2 : 1;
    dd.joints.resize(size_t(nv) * 4 * dd.sets);
    dd.weights.resize(size_t(nv) * 4 * dd.sets);
    for (uint32_t set = 0; set < dd.sets; ++set) {
      const std::string jn = "JOINTS_" + std::to_string(set), wn = "WEIGHTS_" + std::to_string(set);
      const auto wa = gp.attributes.find(wn);
      if (wa == gp.attributes.end()) throw Error("mesh primitive has " + jn + " but no " + wn);
      const int ja = gp.attributes.at(jn);
      if (ja < 0 || size_t(ja) >= m_.accessors.size()) throw Error(jn + " accessor out of range");
      const int ct = m_.accessors[size_t(ja)].componentType;
      if (ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT)
        throw Error(jn + " must be unsigned byte or unsigned short");
      const std::vector<float> j = perVertex(acc_.floats(ja, 4, jn.c_str()), 4, srcCount, corner, nv, jn.c_str());
      const std::vector<float> w = perVertex(acc_.floats(wa->second, 4, wn.c_str()), 4, srcCount, corner, nv, wn.c_str());
      if (!finiteAll(w)) throw Error(wn + " has non-finite weights");
      for (uint32_t v = 0; v < nv; ++v)
        for (int c = 0; c < 4; ++c) {
          const size_t o = size_t(v) * 4 * dd.sets + set * 4 + c;
          const float jf = j[size_t(v) * 4 + c], wf = w[size_t(v) * 4 + c];
          if (wf < 0.0f) throw Error(wn + " has a negative weight (vertex " + std::to_string(v) + ")");
          if (wf > 0.0f && jf >= float(jointCount))
            throw Error(jn + ": joint " + std::to_string(uint32_t(jf)) + " out of range (the skin has " + std::to_string(jointCount) + " joints)");
          dd.joints[o] = uint16_t(wf > 0.0f ? jf : 0.0f);
          dd.weights[o] = wf;
        }
    }
    // Weights that do not sum to 1 are scaled to (glTF 2.0, 3.7.3.3: their
    // sum should be 1); a vertex without any follows its first joint.
    for (uint32_t v = 0; v < nv; ++v) {
      float* wv = dd.weights.data() + size_t(v) * 4 * dd.sets;
      double sum = 0.0;
      for (uint32_t c = 0; c < 4 * dd.sets; ++c) sum += wv[c];
      if (sum > 0.0 && sum != 1.0)
        for (uint32_t c = 0; c < 4 * dd.sets; ++c) wv[c] = float(wv[c] / sum);
      if (sum == 0.0) wv[0] = 1.0f;
    }
  }

  void targets(const tinygltf::Primitive& gp, size_t srcCount, const std::vector<uint32_t>* corner, uint32_t nv, DeformedDraw& dd) {
    dd.targets = uint32_t(gp.targets.size());
    if (!dd.targets) return;
    bool anyNormal = false, anyTangent = false;
    for (const auto& t : gp.targets) anyNormal |= t.count("NORMAL") > 0, anyTangent |= t.count("TANGENT") > 0;
    dd.targetPositions.assign(size_t(nv) * dd.targets, float3{0, 0, 0});
    if (anyNormal && !dd.flatNormals) dd.targetNormals.assign(size_t(nv) * dd.targets, float3{0, 0, 0});
    // Tangents move only where the primitive keeps some (a normal-mapped
    // material's; Scene::tangents), from the bind pose's.
    const MeshPrim& p = s_.prims[s_.draws[dd.draw].prim];
    if (anyTangent && s_.tangents.size() >= size_t(p.firstVertex) + nv) {
      ctx_.ledger.charge("morphed tangents of draw " + std::to_string(dd.draw), mulSat(nv, 16 + 12 * uint64_t(dd.targets)));
      dd.baseTangents.assign(s_.tangents.begin() + p.firstVertex, s_.tangents.begin() + p.firstVertex + nv);
      dd.targetTangents.assign(size_t(nv) * dd.targets, float3{0, 0, 0});
    }
    for (uint32_t t = 0; t < dd.targets; ++t) {
      for (const auto& [name, a] : gp.targets[t]) {
        std::vector<float3>* out = name == "POSITION" ? &dd.targetPositions
                                   : name == "NORMAL" ? &dd.targetNormals
                                   : name == "TANGENT" ? &dd.targetTangents
                                                       : nullptr;
        if (!out || out->empty()) continue;
        const std::string what = "morph target " + name;
        const std::vector<float> f = perVertex(acc_.floats(a, 3, what.c_str()), 3, srcCount, corner, nv, what.c_str());
        if (!finiteAll(f)) throw Error(what + " has non-finite values");
        for (uint32_t v = 0; v < nv; ++v) (*out)[size_t(t) * nv + v] = {f[3 * size_t(v)], f[3 * size_t(v) + 1], f[3 * size_t(v) + 2]};
      }
    }
  }

  const tinygltf::Model& m_;
  LoadContext& ctx_;
  AccessorReader acc_;
  Scene& s_;
  const WalkRecord& w_;
  std::shared_ptr<SceneRig> rig_;
};

}  // namespace

void buildRig(const tinygltf::Model& m, LoadContext& ctx, Scene& s, const WalkRecord& w) {
  std::shared_ptr<SceneRig> rig = RigBuilder(m, ctx, s, w).build();
  if (rig) planAnimations(*rig);  // channels resolved once, for every pose
  s.rig = rig;
  if (s.rig) poseScene(s, PoseRequest{0.0, kNoAnimation});  // the rest pose: skins and default morph weights applied
}

}  // namespace rast::gltf_detail
