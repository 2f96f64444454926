// EXT_mesh_gpu_instancing: a node drawing its mesh many times, each instance
// placed by per-instance TRANSLATION, ROTATION and SCALE accessors under the
// node's own transform. rast makes each instance a Draw (the pipeline already
// draws one mesh from many nodes with one stored copy), so instances cost a
// draw entry each and no vertices. Kept beside the model walk, which calls it
// for every node with a mesh.
#include "host/gltf/gltf_internal.h"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include <cmath>

namespace rast::gltf_detail {

std::vector<glm::dmat4> instanceMatrices(const tinygltf::Model& m, LoadContext& ctx, int nodeIndex, size_t primsPerInstance) {
  const tinygltf::Node& n = m.nodes[size_t(nodeIndex)];
  const auto ext = n.extensions.find("EXT_mesh_gpu_instancing");
  if (ext == n.extensions.end()) return {};
  const std::string at = "nodes[" + std::to_string(nodeIndex) + "] EXT_mesh_gpu_instancing: ";
  const tinygltf::Value& x = ext->second;
  if (!x.IsObject() || !x.Has("attributes") || !x.Get("attributes").IsObject())
    throw Error(at + "needs an attributes object");
  const tinygltf::Value& attrs = x.Get("attributes");
  AccessorReader acc(m, ctx);
  struct Attr {
    const char* name;
    int comps;
    std::vector<float> v;
  } list[3] = {{"TRANSLATION", 3, {}}, {"ROTATION", 4, {}}, {"SCALE", 3, {}}};
  size_t count = 0;
  bool any = false;
  for (Attr& a : list) {
    if (!attrs.Has(a.name)) continue;
    const tinygltf::Value& i = attrs.Get(a.name);
    if (!i.IsInt() || i.GetNumberAsInt() < 0) throw Error(at + a.name + " must be an accessor index");
    const int index = i.GetNumberAsInt();
    if (size_t(index) < m.accessors.size()) {
      // The draws first: a few bytes of accessor can claim millions of instances.
      const uint64_t draws = mulSat(m.accessors[size_t(index)].count, primsPerInstance);
      ctx.ledger.check(at + std::to_string(m.accessors[size_t(index)].count) + " instances", mulSat(draws, sizeof(Draw) + 64));
    }
    a.v = acc.floats(index, a.comps, (std::string("instance ") + a.name).c_str());
    const size_t c = a.v.size() / size_t(a.comps);
    if (any && c != count) throw Error(at + "TRANSLATION, ROTATION and SCALE must have the same count");
    count = c;
    any = true;
    for (float f : a.v)
      if (!std::isfinite(f)) throw Error(at + a.name + " has non-finite values");
  }
  if (!any) throw Error(at + "has no TRANSLATION, ROTATION or SCALE");
  ctx.ledger.charge(at + std::to_string(count) + " instances", mulSat(mulSat(count, primsPerInstance), sizeof(Draw) + 64));
  std::vector<glm::dmat4> out(count, glm::dmat4(1.0));
  for (size_t k = 0; k < count; ++k) {
    glm::dmat4 t(1.0), r(1.0), s(1.0);
    if (!list[0].v.empty()) t = glm::translate(glm::dmat4(1.0), glm::dvec3(list[0].v[3 * k], list[0].v[3 * k + 1], list[0].v[3 * k + 2]));
    if (!list[1].v.empty()) {
      const float* q = list[1].v.data() + 4 * k;
      if (q[0] == 0.0f && q[1] == 0.0f && q[2] == 0.0f && q[3] == 0.0f) throw Error(at + "ROTATION " + std::to_string(k) + " is zero");
      r = glm::mat4_cast(glm::normalize(glm::dquat(q[3], q[0], q[1], q[2])));
    }
    if (!list[2].v.empty()) s = glm::scale(glm::dmat4(1.0), glm::dvec3(list[2].v[3 * k], list[2].v[3 * k + 1], list[2].v[3 * k + 2]));
    out[k] = t * r * s;
  }
  return out;
}

}  // namespace rast::gltf_detail
