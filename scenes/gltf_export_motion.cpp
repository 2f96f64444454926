// writeMotion (gltf_export_motion.h): the rig of a Scene into the tinygltf
// model exportGlb builds. Node i of the rig is node i of the file, so that
// skins and channels keep their node indices; each node's children and the
// scene's roots are ordered by the first draw under them, so that reading the
// file back (a depth-first walk, a node's own meshes first) gives the draws,
// and so the primitive ids, in the scene's order.
#include "scenes/gltf_export_motion.h"

#include "host/scene/animation.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cstring>
#include <limits>

namespace rast {
namespace {

static_assert(sizeof(float3) == 3 * sizeof(float), "float3 is written as three floats");

// Appends arrays to buffer 0, each as a buffer view and an accessor.
struct Appender {
  tinygltf::Model& m;

  int accessor(const void* data, size_t count, int componentType, int type, size_t elementBytes, int target = 0) {
    std::vector<unsigned char>& bin = m.buffers[0].data;
    while (bin.size() % 4) bin.push_back(0);
    tinygltf::BufferView v;
    v.buffer = 0;
    v.byteOffset = bin.size();
    v.byteLength = count * elementBytes;
    v.target = target;
    const auto* p = static_cast<const unsigned char*>(data);
    bin.insert(bin.end(), p, p + count * elementBytes);
    m.bufferViews.push_back(v);
    tinygltf::Accessor a;
    a.bufferView = int(m.bufferViews.size() - 1);
    a.componentType = componentType;
    a.count = count;
    a.type = type;
    m.accessors.push_back(a);
    return int(m.accessors.size() - 1);
  }

  int vec3(const float3* f, size_t count, bool bounds = false) {
    const int a = accessor(f, count, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, sizeof(float3), TINYGLTF_TARGET_ARRAY_BUFFER);
    if (bounds && count) {  // POSITION carries its bounds
      tinygltf::Accessor& acc = m.accessors[size_t(a)];
      acc.minValues.assign(3, std::numeric_limits<double>::infinity());
      acc.maxValues.assign(3, -std::numeric_limits<double>::infinity());
      for (size_t i = 0; i < count; ++i) {
        const float c[3] = {f[i].x, f[i].y, f[i].z};
        for (int k = 0; k < 3; ++k) {
          acc.minValues[k] = std::min(acc.minValues[k], double(c[k]));
          acc.maxValues[k] = std::max(acc.maxValues[k], double(c[k]));
        }
      }
    }
    return a;
  }

  // Floats of `comps` components each (a sampler's keys; min/max for inputs).
  int floats(const std::vector<float>& f, int type, size_t comps, bool bounds = false) {
    const int a = accessor(f.data(), f.size() / comps, TINYGLTF_COMPONENT_TYPE_FLOAT, type, comps * sizeof(float));
    if (bounds && !f.empty()) {
      m.accessors[size_t(a)].minValues = {double(*std::min_element(f.begin(), f.end()))};
      m.accessors[size_t(a)].maxValues = {double(*std::max_element(f.begin(), f.end()))};
    }
    return a;
  }
};

const char* interpolationName(Interpolation i) {
  return i == Interpolation::Step ? "STEP" : i == Interpolation::CubicSpline ? "CUBICSPLINE" : "LINEAR";
}

const char* pathName(AnimPath p) {
  return p == AnimPath::Translation ? "translation" : p == AnimPath::Rotation ? "rotation" : p == AnimPath::Scale ? "scale" : "weights";
}

// A deformed draw's primitive: its bind pose in place of the posed vertices,
// its joints and weights (one JOINTS_n/WEIGHTS_n pair per set of four; the
// weights of a vertex scaled to sum 1, as glTF 2.0 3.7.3.3 asks), its morph
// targets.
void deformPrimitive(const DeformedDraw& dd, Appender& w, tinygltf::Primitive& gp) {
  const size_t nv = dd.basePositions.size();
  gp.attributes["POSITION"] = w.vec3(dd.basePositions.data(), nv, true);
  if (dd.flatNormals) gp.attributes.erase("NORMAL");  // generated per face: the reader generates them again
  else gp.attributes["NORMAL"] = w.vec3(dd.baseNormals.data(), nv);
  if (dd.skin >= 0) {
    const uint32_t per = 4 * dd.sets;
    std::vector<float> weights(dd.weights);
    for (size_t v = 0; v < nv; ++v) {
      float* wv = weights.data() + v * per;
      double sum = 0.0;
      for (uint32_t c = 0; c < per; ++c) sum += wv[c];
      if (sum > 0.0 && sum != 1.0)
        for (uint32_t c = 0; c < per; ++c) wv[c] = float(wv[c] / sum);
      if (sum == 0.0) wv[0] = 1.0f;
    }
    for (uint32_t set = 0; set < dd.sets; ++set) {
      std::vector<uint16_t> j(4 * nv);
      std::vector<float> wt(4 * nv);
      for (size_t v = 0; v < nv; ++v)
        for (uint32_t c = 0; c < 4; ++c) {
          j[4 * v + c] = dd.joints[v * per + 4 * set + c];
          wt[4 * v + c] = weights[v * per + 4 * set + c];
        }
      const std::string n = std::to_string(set);
      gp.attributes["JOINTS_" + n] = w.accessor(j.data(), nv, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_VEC4,
                                                4 * sizeof(uint16_t), TINYGLTF_TARGET_ARRAY_BUFFER);
      gp.attributes["WEIGHTS_" + n] = w.accessor(wt.data(), nv, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4,
                                                 4 * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER);
    }
  }
  gp.targets.clear();
  for (uint32_t t = 0; t < dd.targets; ++t) {
    std::map<std::string, int> target;
    target["POSITION"] = w.vec3(dd.targetPositions.data() + size_t(t) * nv, nv, true);
    if (!dd.targetNormals.empty()) target["NORMAL"] = w.vec3(dd.targetNormals.data() + size_t(t) * nv, nv);
    gp.targets.push_back(target);
  }
}

}  // namespace

bool writeMotion(const Scene& s, tinygltf::Model& m, tinygltf::Scene& scene) {
  if (!s.rig) return false;
  const SceneRig& rig = *s.rig;
  if (!rig.drawInstance.empty())
    throw Error("rast export: instanced draws (EXT_mesh_gpu_instancing) of a scene that moves are not written");
  if (rig.drawNode.size() != s.draws.size() || rig.order.size() != rig.nodes.size() || m.meshes.size() < s.prims.size())
    throw Error("rast export: the scene's rig does not match its draws");
  const size_t n = rig.nodes.size();
  const int base = int(m.nodes.size());
  Appender w{m};

  std::vector<const DeformedDraw*> deformedOf(s.draws.size(), nullptr);
  for (const DeformedDraw& dd : rig.deformed) deformedOf[dd.draw] = &dd;
  std::vector<std::vector<uint32_t>> drawsOf(n);
  for (size_t d = 0; d < s.draws.size(); ++d) drawsOf[size_t(rig.drawNode[d])].push_back(uint32_t(d));

  // The nodes, with their rest transforms and meshes.
  std::vector<tinygltf::Node> nodes(n);
  for (size_t i = 0; i < n; ++i) {
    const RigNode& rn = rig.nodes[i];
    tinygltf::Node& gn = nodes[i];
    gn.name = "node " + std::to_string(i);  // the rig keeps no names; and tinygltf writes a node with no property as null
    if (rn.hasMatrix) {
      gn.matrix.assign(&rn.matrix[0][0], &rn.matrix[0][0] + 16);
    } else {
      if (rn.translation != glm::dvec3(0.0)) gn.translation = {rn.translation.x, rn.translation.y, rn.translation.z};
      if (rn.rotation != glm::dquat(1.0, 0.0, 0.0, 0.0)) gn.rotation = {rn.rotation.x, rn.rotation.y, rn.rotation.z, rn.rotation.w};
      if (rn.scale != glm::dvec3(1.0)) gn.scale = {rn.scale.x, rn.scale.y, rn.scale.z};
    }
    if (drawsOf[i].empty()) continue;
    tinygltf::Mesh mesh;
    for (uint32_t d : drawsOf[i]) {
      tinygltf::Primitive gp = m.meshes[s.draws[d].prim].primitives.at(0);
      if (const DeformedDraw* dd = deformedOf[d]) {
        deformPrimitive(*dd, w, gp);
        if (dd->skin >= 0) gn.skin = dd->skin;
      }
      mesh.primitives.push_back(gp);
    }
    mesh.weights = rn.weights;  // the default morph weights
    gn.weights = rn.weights;
    m.meshes.push_back(mesh);
    gn.mesh = int(m.meshes.size() - 1);
  }
  // Children and roots ordered by the first draw under them (the scene's draw order back).
  std::vector<uint32_t> firstDraw(n, std::numeric_limits<uint32_t>::max());
  for (size_t d = 0; d < s.draws.size(); ++d) firstDraw[size_t(rig.drawNode[d])] = std::min(firstDraw[size_t(rig.drawNode[d])], uint32_t(d));
  for (auto it = rig.order.rbegin(); it != rig.order.rend(); ++it) {
    const int32_t p = rig.nodes[size_t(*it)].parent;
    if (p >= 0) firstDraw[size_t(p)] = std::min(firstDraw[size_t(p)], firstDraw[size_t(*it)]);
  }
  auto byFirstDraw = [&](int a, int b) { return firstDraw[size_t(a)] < firstDraw[size_t(b)]; };
  std::vector<int> roots;
  for (size_t i = 0; i < n; ++i) {
    const int32_t p = rig.nodes[i].parent;
    if (p >= 0) nodes[size_t(p)].children.push_back(int(i));
    else roots.push_back(int(i));
  }
  for (tinygltf::Node& gn : nodes) {
    std::stable_sort(gn.children.begin(), gn.children.end(), byFirstDraw);
    for (int& c : gn.children) c += base;
  }
  std::stable_sort(roots.begin(), roots.end(), byFirstDraw);
  for (int r : roots) scene.nodes.push_back(r + base);
  m.nodes.insert(m.nodes.end(), nodes.begin(), nodes.end());

  for (const Skin& sk : rig.skins) {
    tinygltf::Skin gs;
    for (int32_t j : sk.joints) gs.joints.push_back(j + base);
    std::vector<float> ibm;
    for (const glm::dmat4& b : sk.inverseBind)
      for (int k = 0; k < 16; ++k) ibm.push_back(float((&b[0][0])[k]));
    gs.inverseBindMatrices = w.floats(ibm, TINYGLTF_TYPE_MAT4, 16);
    m.skins.push_back(gs);
  }
  for (const Animation& an : rig.animations) {
    tinygltf::Animation ga;
    ga.name = an.name;
    std::vector<int> samplerIndex(an.samplers.size(), -1);  // samplers no channel reads are left out
    for (const AnimChannel& ch : an.channels) {
      int& k = samplerIndex[size_t(ch.sampler)];
      if (k < 0) {
        const AnimSampler& sm = an.samplers[size_t(ch.sampler)];
        tinygltf::AnimationSampler gsm;
        gsm.input = w.floats(sm.times, TINYGLTF_TYPE_SCALAR, 1, true);
        const bool vec = ch.path != AnimPath::Weights;
        gsm.output = w.floats(sm.values, !vec ? TINYGLTF_TYPE_SCALAR : sm.comps == 4 ? TINYGLTF_TYPE_VEC4 : TINYGLTF_TYPE_VEC3, vec ? sm.comps : 1);
        gsm.interpolation = interpolationName(sm.interp);
        ga.samplers.push_back(gsm);
        k = int(ga.samplers.size() - 1);
      }
      tinygltf::AnimationChannel gc;
      gc.sampler = k;
      gc.target_node = ch.node + base;
      gc.target_path = pathName(ch.path);
      ga.channels.push_back(gc);
    }
    m.animations.push_back(ga);
  }
  return true;
}

}  // namespace rast
