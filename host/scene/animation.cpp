// Animation evaluation on the host: samplers at a time (STEP, LINEAR with
// quaternion slerp, CUBICSPLINE with tangents scaled by the key interval),
// node transforms down the hierarchy, then the pose written into the Scene:
// morph targets, then skinning (glTF 2.0, 3.7.3 and 3.11). Double precision
// throughout, each node sampled by one thread, so a time gives the same pose
// on every backend and with any number of threads.
#include "host/scene/animation.h"

#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>

namespace rast {

int findAnimation(const SceneRig& rig, const std::string& which) {
  const int n = int(rig.animations.size());
  if (n == 0) throw Error("--animation: the scene has no animations");
  char* end = nullptr;
  const long idx = std::strtol(which.c_str(), &end, 10);
  if (!which.empty() && end && *end == '\0') {
    if (idx < 0 || idx >= n) throw Error("--animation " + which + ": the scene has animations 0.." + std::to_string(n - 1));
    return int(idx);
  }
  std::string names;
  for (int i = 0; i < n; ++i) {
    if (rig.animations[i].name == which) return i;
    names += (i ? ", " : "") + std::to_string(i) + (rig.animations[i].name.empty() ? "" : " '" + rig.animations[i].name + "'");
  }
  throw Error("--animation: no animation named '" + which + "' (the scene has " + names + ")");
}

namespace {

// Spherical interpolation along the shorter arc; nearly equal quaternions are
// interpolated linearly (then normalised), where slerp's division is unstable.
void slerp(const double* a, const double* b0, double u, double* out) {
  double b[4] = {b0[0], b0[1], b0[2], b0[3]};
  double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
  if (d < 0.0) {
    for (double& x : b) x = -x;
    d = -d;
  }
  double wa = 1.0 - u, wb = u;
  if (d < 0.9995) {
    const double theta = std::acos(std::min(d, 1.0)), s = std::sin(theta);
    wa = std::sin((1.0 - u) * theta) / s;
    wb = std::sin(u * theta) / s;
  }
  double len = 0.0;
  for (int k = 0; k < 4; ++k) {
    out[k] = wa * a[k] + wb * b[k];
    len += out[k] * out[k];
  }
  len = std::sqrt(len);
  if (len > 0.0)
    for (int k = 0; k < 4; ++k) out[k] /= len;
}

// The key interval [k, k+1) holding t, for times[0] < t < times[n-1]: first
// guessed as if the keys were evenly spaced (exported animations mostly are),
// then its neighbours, then a binary search. The same k whichever finds it.
uint32_t guessKey(const SamplerView& s, double t) {
  return uint32_t(std::clamp((t - s.first) * s.keysPerSecond, 0.0, double(s.n - 2)));
}

uint32_t keyBefore(const SamplerView& s, double t) {
  const float* times = s.times;
  const uint32_t n = s.n;
  const uint32_t g = guessKey(s, t);
  auto holds = [&](uint32_t k) { return double(times[k]) <= t && t < double(times[k + 1]); };
  if (holds(g)) return g;
  if (g + 2 < n && holds(g + 1)) return g + 1;
  if (g > 0 && holds(g - 1)) return g - 1;
  return uint32_t(std::upper_bound(times, times + n, t, [](double a, float b) { return a < double(b); }) - times) - 1;
}

void normalise4(double* q) {
  const double len = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (len > 0.0)
    for (int k = 0; k < 4; ++k) q[k] /= len;
}

}  // namespace

namespace {

// sampleView's arithmetic with the component count known when C != 0 (3 for
// translations and scales, 4 for rotations), so that its loops unroll.
template <uint32_t C>
void sampleComps(const SamplerView& s, double t, bool rotation, double* out) {
  const uint32_t c = C ? C : s.comps, n = s.n;
  const bool cubic = s.interp == Interpolation::CubicSpline;
  const uint32_t stride = cubic ? 3 * c : c, valueAt = cubic ? c : 0;  // a key's value after its in-tangent
  auto value = [&](uint32_t k, uint32_t j) { return double(s.values[size_t(k) * stride + valueAt + j]); };
  if (n == 0) return;
  if (!(t > s.first) || n == 1) {
    for (uint32_t j = 0; j < c; ++j) out[j] = value(0, j);
  } else if (t >= s.last) {
    for (uint32_t j = 0; j < c; ++j) out[j] = value(n - 1, j);
  } else {
    const uint32_t k = keyBefore(s, t);
    const uint32_t k1 = std::min(k + 1, n - 1);
    const double t0 = s.times[k], t1 = s.times[k1], dt = t1 - t0;
    const double u = dt > 0.0 ? std::clamp((t - t0) / dt, 0.0, 1.0) : 0.0;
    if (s.interp == Interpolation::Step) {
      for (uint32_t j = 0; j < c; ++j) out[j] = value(k, j);
    } else if (!cubic) {
      if (rotation && c == 4) {
        double a[4], b[4];
        for (uint32_t j = 0; j < 4; ++j) {
          a[j] = value(k, j);
          b[j] = value(k1, j);
        }
        slerp(a, b, u, out);
        return;
      }
      for (uint32_t j = 0; j < c; ++j) out[j] = value(k, j) * (1.0 - u) + value(k1, j) * u;
    } else {
      // Hermite: p = h00 v_k + h10 dt b_k + h01 v_k+1 + h11 dt a_k+1 (b: out-tangent, a: in-tangent).
      const double u2 = u * u, u3 = u2 * u;
      const double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2, h11 = u3 - u2;
      for (uint32_t j = 0; j < c; ++j) {
        const double vk = value(k, j), vk1 = value(k1, j);
        const double bk = s.values[size_t(k) * stride + 2 * c + j], ak1 = s.values[size_t(k1) * stride + j];
        out[j] = h00 * vk + h10 * dt * bk + h01 * vk1 + h11 * dt * ak1;
      }
    }
  }
  if (rotation && c == 4) normalise4(out);
}

}  // namespace

void sampleView(const SamplerView& s, double t, bool rotation, double* out) {
  if (s.comps == 3) sampleComps<3>(s, t, rotation, out);
  else if (s.comps == 4) sampleComps<4>(s, t, rotation, out);
  else sampleComps<0>(s, t, rotation, out);
}

SamplerView viewOf(const AnimSampler& s) {
  SamplerView v;
  v.times = s.times.data();
  v.values = s.values.data();
  v.n = uint32_t(s.times.size());
  v.comps = s.comps;
  v.interp = s.interp;
  if (v.n) {
    v.first = s.times.front();
    v.last = s.times.back();
    v.keysPerSecond = double(v.n - 1) / (double(v.last) - double(v.first));
  }
  return v;
}

void sampleAt(const AnimSampler& s, double t, bool rotation, double* out) { sampleView(viewOf(s), t, rotation, out); }

namespace {

// A node's local matrix from its T R S (built directly: columns of R scaled,
// T in the last), or its own matrix.
glm::dmat4 localMatrix(const RigNode& nd, const glm::dvec3& tr, const glm::dquat& rot, const glm::dvec3& sc) {
  if (nd.hasMatrix) return nd.matrix;
  const glm::dmat3 r = glm::mat3_cast(glm::normalize(rot));
  return glm::dmat4(glm::dvec4(r[0] * sc.x, 0.0), glm::dvec4(r[1] * sc.y, 0.0), glm::dvec4(r[2] * sc.z, 0.0), glm::dvec4(tr, 1.0));
}

// parent * local, glm's operator* with two rows at a time (GCC/Clang vector
// extensions, SSE2 on x86-64): the same products and sums in the same order,
// so the same bits, in about half the instructions.
glm::dmat4 compose(const glm::dmat4& a, const glm::dmat4& b) {
  typedef double Pair __attribute__((vector_size(16)));
  Pair lo[4], hi[4];
  for (int c = 0; c < 4; ++c) {
    std::memcpy(&lo[c], &a[c][0], sizeof(Pair));
    std::memcpy(&hi[c], &a[c][2], sizeof(Pair));
  }
  glm::dmat4 r;
  for (int c = 0; c < 4; ++c) {
    const Pair rl = lo[0] * b[c][0] + lo[1] * b[c][1] + lo[2] * b[c][2] + lo[3] * b[c][3];
    const Pair rh = hi[0] * b[c][0] + hi[1] * b[c][1] + hi[2] * b[c][2] + hi[3] * b[c][3];
    std::memcpy(&r[c][0], &rl, sizeof(Pair));
    std::memcpy(&r[c][2], &rh, sizeof(Pair));
  }
  return r;
}

void makePlan(const SceneRig& rig, AnimPlan& plan) {
  const size_t n = rig.nodes.size();
  std::vector<uint8_t> ordered(n, 0);
  for (int32_t i : rig.order) ordered[size_t(i)] = 1;
  std::vector<int32_t> slot(n, -1);  // a node's entry in the selection being resolved
  auto resolve = [&](size_t from, size_t to) {
    std::vector<NodeDrivers> out;
    for (size_t a = from; a < to; ++a)
      for (const AnimChannel& ch : rig.animations[a].channels) {
        if (ch.node < 0 || size_t(ch.node) >= n || !ordered[size_t(ch.node)]) continue;  // outside the scene: never drawn
        int32_t& k = slot[size_t(ch.node)];
        if (k < 0) {
          k = int32_t(out.size());
          out.emplace_back().node = ch.node;
        }
        out[size_t(k)].driven |= 1u << int(ch.path);
        out[size_t(k)].sampler[int(ch.path)] = viewOf(rig.animations[a].samplers[size_t(ch.sampler)]);
      }
    for (const NodeDrivers& d : out) slot[size_t(d.node)] = -1;
    return out;
  };
  plan.selections.push_back(resolve(0, rig.animations.size()));
  for (size_t a = 0; a < rig.animations.size(); ++a) plan.selections.push_back(resolve(a, a + 1));
  for (int32_t i : rig.order) plan.orderParent.push_back(rig.nodes[size_t(i)].parent);
  plan.restWorld.assign(n, glm::dmat4(1.0));
  for (int32_t i : rig.order) {
    const RigNode& nd = rig.nodes[size_t(i)];
    const glm::dmat4 local = localMatrix(nd, nd.translation, nd.rotation, nd.scale);
    plan.restWorld[size_t(i)] = nd.parent >= 0 ? plan.restWorld[size_t(nd.parent)] * local : local;
  }
  plan.owner = &rig;
}

}  // namespace

AnimPlan& AnimPlan::operator=(AnimPlan&&) noexcept {
  owner = nullptr;
  selections.clear();
  restWorld.clear();
  orderParent.clear();
  return *this;
}

void planAnimations(SceneRig& rig) {
  rig.plan = AnimPlan();
  makePlan(rig, rig.plan);
}

void evaluateNodes(const SceneRig& rig, const PoseRequest& r, std::vector<glm::dmat4>& world,
                   std::vector<std::vector<double>>* weights) {
  AnimPlan made;
  const AnimPlan* plan = &rig.plan;
  if (plan->owner != &rig) {
    makePlan(rig, made);
    plan = &made;
  }
  const size_t n = rig.nodes.size();
  if (rig.order.size() != n) world.assign(n, glm::dmat4(1.0));  // nodes outside the scene: identity
  else world.resize(n);
  if (weights) {
    weights->resize(n);
    for (size_t i = 0; i < n; ++i) (*weights)[i] = rig.nodes[i].weights;
  }
  static const std::vector<NodeDrivers> kNone;
  const size_t sel = r.animation == kAllAnimations ? 0 : size_t(r.animation) + 1;
  const std::vector<NodeDrivers>& drv = r.animation >= kAllAnimations && sel < plan->selections.size() ? plan->selections[sel] : kNone;
  // Sampling: each driven node's channels by one thread, its local matrix
  // left in world[node] for the pass below.
  const long m = long(drv.size());
  // Threads only for thousands of nodes: a parallel region costs a few
  // microseconds, and on a busy machine a thread may wait for its core.
#pragma omp parallel for schedule(static) if (m >= 2048)
  for (long k = 0; k < m; ++k) {
    const NodeDrivers& d = drv[size_t(k)];
    const RigNode& nd = rig.nodes[size_t(d.node)];
    auto drives = [&](AnimPath p) { return (d.driven >> int(p)) & 1u; };
    auto samplerOf = [&](AnimPath p) -> const SamplerView& { return d.sampler[int(p)]; };
    glm::dvec3 tr = nd.translation, sc = nd.scale;
    glm::dquat rot = nd.rotation;
    double v[4] = {0, 0, 0, 0};
    if (drives(AnimPath::Translation)) {
      sampleView(samplerOf(AnimPath::Translation), r.time, false, v);
      tr = {v[0], v[1], v[2]};
    }
    if (drives(AnimPath::Rotation)) {
      sampleView(samplerOf(AnimPath::Rotation), r.time, true, v);
      rot = glm::dquat(v[3], v[0], v[1], v[2]);
    }
    if (drives(AnimPath::Scale)) {
      sampleView(samplerOf(AnimPath::Scale), r.time, false, v);
      sc = {v[0], v[1], v[2]};
    }
    if (weights && drives(AnimPath::Weights)) {
      const SamplerView& s = samplerOf(AnimPath::Weights);
      std::vector<double>& w = (*weights)[size_t(d.node)];
      w.assign(s.comps, 0.0);
      sampleView(s, r.time, false, w.data());
    }
    world[size_t(d.node)] = localMatrix(nd, tr, rot, sc);
  }
  // Down the hierarchy: driven nodes and those under them composed, the
  // others at rest.
  std::vector<uint8_t> moved(n, 0);
  for (const NodeDrivers& d : drv) moved[size_t(d.node)] = 1;
  for (size_t j = 0; j < rig.order.size(); ++j) {
    const size_t i = size_t(rig.order[j]);
    const int32_t p = plan->orderParent[j];
    if (moved[i]) {
      if (p >= 0) world[i] = compose(world[size_t(p)], world[i]);
    } else if (p >= 0 && moved[size_t(p)]) {
      moved[i] = 1;
      const RigNode& nd = rig.nodes[i];
      world[i] = compose(world[size_t(p)], localMatrix(nd, nd.translation, nd.rotation, nd.scale));
    } else {
      world[i] = plan->restWorld[i];
    }
  }
}

std::vector<glm::dmat4> evaluateNodes(const SceneRig& rig, const PoseRequest& r, std::vector<std::vector<double>>* weights) {
  std::vector<glm::dmat4> world;
  evaluateNodes(rig, r, world, weights);
  return world;
}

namespace {

// A deformed draw's vertices with its morph targets applied (object space).
void morph(const DeformedDraw& dd, const std::vector<double>& w, float3* pos, float3* nrm, uint32_t nv) {
  std::vector<double> tw(dd.targets, 0.0);
  for (uint32_t t = 0; t < dd.targets && t < w.size(); ++t) tw[t] = w[t];
  for (uint32_t v = 0; v < nv; ++v) {
    glm::dvec3 q(dd.basePositions[v].x, dd.basePositions[v].y, dd.basePositions[v].z);
    glm::dvec3 m(dd.baseNormals[v].x, dd.baseNormals[v].y, dd.baseNormals[v].z);
    for (uint32_t t = 0; t < dd.targets; ++t) {
      if (tw[t] == 0.0) continue;
      const float3 dp = dd.targetPositions[size_t(t) * nv + v];
      q += tw[t] * glm::dvec3(dp.x, dp.y, dp.z);
      if (!dd.targetNormals.empty()) {
        const float3 dn = dd.targetNormals[size_t(t) * nv + v];
        m += tw[t] * glm::dvec3(dn.x, dn.y, dn.z);
      }
    }
    pos[v] = {float(q.x), float(q.y), float(q.z)};
    nrm[v] = {float(m.x), float(m.y), float(m.z)};
  }
}

// Flat-shaded primitives own a vertex per triangle corner (addPrim): each
// triangle's face normal again; else the normals normalised.
void finishNormals(const Scene& s, const MeshPrim& p, const DeformedDraw& dd, const float3* pos, float3* nrm) {
  if (dd.flatNormals) {
    for (uint32_t t = 0; t < p.triCount; ++t) {
      const uint32_t* ix = s.indices.data() + 3 * size_t(p.firstTri + t);
      const float3 a = pos[ix[0]], b = pos[ix[1]], c = pos[ix[2]];
      const float3 n = normalize(cross(b - a, c - a));
      for (int k = 0; k < 3; ++k) nrm[ix[k]] = n;
    }
  } else {
    for (uint32_t v = 0; v < p.vertexCount; ++v) nrm[v] = normalize(nrm[v]);
  }
}

std::vector<glm::dmat4> jointMatrices(const Skin& sk, const std::vector<glm::dmat4>& world) {
  std::vector<glm::dmat4> j(sk.joints.size());
  for (size_t k = 0; k < sk.joints.size(); ++k) j[k] = world[size_t(sk.joints[k])] * sk.inverseBind[k];
  return j;
}

}  // namespace

bool hasSkins(const Scene& s) {
  if (!s.rig) return false;
  for (const DeformedDraw& dd : s.rig->deformed)
    if (dd.skin >= 0) return true;
  return false;
}

void poseScene(Scene& s, const PoseRequest& r, bool skinOnHost) {
  if (!s.rig) return;
  const SceneRig& rig = *s.rig;
  s.poseTime = r.time;
  s.poseAnimation = r.animation;
  s.skinnedOnHost = skinOnHost;
  std::vector<std::vector<double>> weights;
  const std::vector<glm::dmat4> world = evaluateNodes(rig, r, &weights);
  for (size_t d = 0; d < s.draws.size() && d < rig.drawNode.size(); ++d)
    s.draws[d].model = rig.drawInstance.empty() ? world[size_t(rig.drawNode[d])] : world[size_t(rig.drawNode[d])] * rig.drawInstance[d];
  for (const DeformedDraw& dd : rig.deformed) {
    Draw& draw = s.draws[dd.draw];
    const MeshPrim& p = s.prims[draw.prim];
    const uint32_t nv = p.vertexCount;
    float3* pos = s.positions.data() + p.firstVertex;
    float3* nrm = s.normals.data() + p.firstVertex;
    morph(dd, weights[size_t(rig.drawNode[dd.draw])], pos, nrm, nv);  // morph targets first, then the skin
    if (dd.skin >= 0) {
      // The skinned mesh's own node transform is ignored (glTF 2.0, 3.7.3.3):
      // the joints place it in the world.
      draw.model = glm::dmat4(1.0);
      if (!skinOnHost) {
        finishNormals(s, p, dd, pos, nrm);
        continue;
      }
      const std::vector<glm::dmat4> jointMat = jointMatrices(rig.skins[size_t(dd.skin)], world);
      for (uint32_t v = 0; v < nv; ++v) {
        glm::dmat4 m(0.0);
        for (uint32_t k = 0; k < 4 * dd.sets; ++k) {
          const float wk = dd.weights[size_t(v) * 4 * dd.sets + k];
          if (wk != 0.0f) m += double(wk) * jointMat[dd.joints[size_t(v) * 4 * dd.sets + k]];
        }
        const glm::dvec4 q = m * glm::dvec4(pos[v].x, pos[v].y, pos[v].z, 1.0);
        pos[v] = {float(q.x), float(q.y), float(q.z)};
        if (!dd.flatNormals) {
          const glm::dmat3 m3(m);
          const glm::dvec3 n = (glm::determinant(m3) != 0.0 ? glm::inverseTranspose(m3) : m3) * glm::dvec3(nrm[v].x, nrm[v].y, nrm[v].z);
          nrm[v] = {float(n.x), float(n.y), float(n.z)};
        }
      }
    }
    finishNormals(s, p, dd, pos, nrm);
  }
}

SkinPalette skinPalette(const Scene& s, std::vector<float3>* positions, std::vector<float3>* normals) {
  SkinPalette pal;
  pal.start.assign(s.draws.size(), -1);
  if (!hasSkins(s)) return pal;
  const SceneRig& rig = *s.rig;
  std::vector<std::vector<double>> weights;
  const std::vector<glm::dmat4> world = evaluateNodes(rig, PoseRequest{s.poseTime, s.poseAnimation}, &weights);
  for (const DeformedDraw& dd : rig.deformed) {
    if (dd.skin < 0) continue;
    pal.start[dd.draw] = int32_t(pal.joints.size());
    for (const glm::dmat4& j : jointMatrices(rig.skins[size_t(dd.skin)], world)) {
      pal.joints.push_back(j);
      const glm::dmat3 m3(j);
      pal.normals.push_back(glm::determinant(m3) != 0.0 ? glm::inverseTranspose(m3) : m3);
    }
    if (s.skinnedOnHost && positions && normals) {
      const MeshPrim& p = s.prims[s.draws[dd.draw].prim];
      float3* pos = positions->data() + p.firstVertex;
      float3* nrm = normals->data() + p.firstVertex;
      morph(dd, weights[size_t(rig.drawNode[dd.draw])], pos, nrm, p.vertexCount);
      finishNormals(s, p, dd, pos, nrm);
    }
  }
  return pal;
}

}  // namespace rast
