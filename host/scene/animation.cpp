// Animation evaluation on the host: samplers at a time (STEP, LINEAR with
// quaternion slerp, CUBICSPLINE with tangents scaled by the key interval),
// node transforms down the hierarchy, then the pose written into the Scene:
// morph targets, then skinning (glTF 2.0, 3.7.3 and 3.11). Double precision
// throughout, each node sampled by one thread, so a time gives the same pose
// on every backend and with any number of threads.
#include "host/scene/animation.h"

#include "host/scene/host_workers.h"

#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <unordered_map>

#ifdef _OPENMP
#include <omp.h>
#endif

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

// Where a time falls in a sampler's keys; a function of the key times alone,
// so samplers sharing their times share it.
struct KeyAt {
  uint8_t where = 0;  // 0: no keys, 1: the first key's value, 2: the last's, 3: between keys k and k1
  uint32_t k = 0, k1 = 0;
  double dt = 0.0, u = 0.0;
};

KeyAt keyAt(const SamplerView& s, double t) {
  KeyAt a;
  const uint32_t n = s.n;
  if (n == 0) return a;
  if (!(t > s.first) || n == 1) {
    a.where = 1;
  } else if (t >= s.last) {
    a.where = 2;
  } else {
    a.where = 3;
    a.k = keyBefore(s, t);
    a.k1 = std::min(a.k + 1, n - 1);
    const double t0 = s.times[a.k], t1 = s.times[a.k1];
    a.dt = t1 - t0;
    a.u = a.dt > 0.0 ? std::clamp((t - t0) / a.dt, 0.0, 1.0) : 0.0;
  }
  return a;
}

// A sampler's value where keyAt put the time, with the component count known
// when C != 0 (3 for translations and scales, 4 for rotations), so that its
// loops unroll.
template <uint32_t C>
inline void sampleKeyed(const SamplerView& s, const KeyAt& at, bool rotation, double* out) {
  const uint32_t c = C ? C : s.comps, n = s.n;
  const bool cubic = s.interp == Interpolation::CubicSpline;
  const uint32_t stride = cubic ? 3 * c : c, valueAt = cubic ? c : 0;  // a key's value after its in-tangent
  auto value = [&](uint32_t k, uint32_t j) { return double(s.values[size_t(k) * stride + valueAt + j]); };
  if (at.where == 0) return;
  if (at.where == 1) {
    for (uint32_t j = 0; j < c; ++j) out[j] = value(0, j);
  } else if (at.where == 2) {
    for (uint32_t j = 0; j < c; ++j) out[j] = value(n - 1, j);
  } else {
    const uint32_t k = at.k, k1 = at.k1;
    const double dt = at.dt, u = at.u;
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

template <uint32_t C>
void sampleComps(const SamplerView& s, double t, bool rotation, double* out) {
  sampleKeyed<C>(s, keyAt(s, t), rotation, out);
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
inline glm::dmat4 localMatrix(const RigNode& nd, const glm::dvec3& tr, const glm::dquat& rot, const glm::dvec3& sc) {
  if (nd.hasMatrix) return nd.matrix;
  const glm::dmat3 r = glm::mat3_cast(glm::normalize(rot));
  return glm::dmat4(glm::dvec4(r[0] * sc.x, 0.0), glm::dvec4(r[1] * sc.y, 0.0), glm::dvec4(r[2] * sc.z, 0.0), glm::dvec4(tr, 1.0));
}

// parent * local, glm's operator* a column of four at a time (GCC/Clang
// vector extensions: two SSE2 registers, or one AVX register in the AVX2
// clone of composeMoved): the same products and sums in the same order, so
// the same bits (no contraction: -ffp-contract=off), in a fraction of the
// instructions.
inline __attribute__((always_inline)) glm::dmat4 compose(const glm::dmat4& a, const glm::dmat4& b) {
  typedef double Quad __attribute__((vector_size(32)));
  Quad col[4];
  for (int c = 0; c < 4; ++c) std::memcpy(&col[c], &a[c][0], sizeof(Quad));
  glm::dmat4 r;
  for (int c = 0; c < 4; ++c) {
    const Quad rc = col[0] * b[c][0] + col[1] * b[c][1] + col[2] * b[c][2] + col[3] * b[c][3];
    std::memcpy(&r[c][0], &rc, sizeof(Quad));
  }
  return r;
}

// The pass down the hierarchy over the planned nodes, also compiled for AVX2
// on GCC/x86-64 (picked at load time; the same bits, see compose).
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define RAST_HOST_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define RAST_HOST_CLONES
#endif
RAST_HOST_CLONES void composeMoved(const MovedNode* mv, size_t m, const glm::dmat4* restLocal, glm::dmat4* world) {
  for (size_t j = 0; j < m; ++j) {
    const MovedNode& e = mv[j];
    if (e.parent < 0) continue;  // a driven root: its sampled local matrix is its world matrix
    world[e.node] = compose(world[e.parent], e.driven ? world[e.node] : restLocal[e.node]);
  }
}

uint64_t hashTimes(const float* t, uint32_t n) {
  uint64_t h = 1469598103934665603ull ^ n;
  for (uint32_t i = 0; i < n; ++i) {
    uint32_t b;
    std::memcpy(&b, &t[i], sizeof b);
    h = (h ^ b) * 1099511628211ull;
  }
  return h;
}

void makePlan(const SceneRig& rig, AnimPlan& plan) {
  const size_t n = rig.nodes.size();
  std::vector<uint8_t> ordered(n, 0);
  for (int32_t i : rig.order) ordered[size_t(i)] = 1;
  plan.restLocal.assign(n, glm::dmat4(1.0));
  plan.restWorld.assign(n, glm::dmat4(1.0));
  for (int32_t i : rig.order) {
    const RigNode& nd = rig.nodes[size_t(i)];
    plan.restLocal[size_t(i)] = localMatrix(nd, nd.translation, nd.rotation, nd.scale);
    plan.restWorld[size_t(i)] = nd.parent >= 0 ? plan.restWorld[size_t(nd.parent)] * plan.restLocal[size_t(i)] : plan.restLocal[size_t(i)];
  }
  std::vector<int32_t> slot(n, -1);  // a node's entry in the selection being resolved
  auto resolve = [&](size_t from, size_t to) {
    PlanSelection sel;
    std::vector<NodeDrivers>& out = sel.drivers;
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
    std::vector<uint8_t> moved(n, 0);
    for (const NodeDrivers& d : out) {
      slot[size_t(d.node)] = -1;
      moved[size_t(d.node)] = 1;
    }
    // Timelines: samplers whose key times are the same bits share one.
    std::unordered_map<uint64_t, std::vector<uint32_t>> byHash;
    for (NodeDrivers& d : out)
      for (int p = 0; p < 4; ++p) {
        if (!((d.driven >> p) & 1u)) continue;
        const SamplerView& v = d.sampler[p];
        std::vector<uint32_t>& same = byHash[hashTimes(v.times, v.n)];
        uint32_t found = uint32_t(sel.timelines.size());
        for (uint32_t t : same) {
          const SamplerView& o = sel.timelines[t];
          if (o.n == v.n && (o.times == v.times || std::memcmp(o.times, v.times, sizeof(float) * v.n) == 0)) found = t;
        }
        if (found == sel.timelines.size()) {
          same.push_back(found);
          sel.timelines.push_back(v);
        }
        d.timeline[p] = found;
      }
    for (int32_t i : rig.order) {
      const int32_t p = rig.nodes[size_t(i)].parent;
      const bool driven = moved[size_t(i)] != 0;
      if (!driven && p >= 0 && moved[size_t(p)]) moved[size_t(i)] = 1;
      if (moved[size_t(i)]) sel.moved.push_back(MovedNode{i, p, driven});
      else sel.resting.push_back(i);
    }
    return sel;
  };
  plan.selections.push_back(resolve(0, rig.animations.size()));
  for (size_t a = 0; a < rig.animations.size(); ++a) plan.selections.push_back(resolve(a, a + 1));
  plan.owner = &rig;
}

// One pose's sampling, shared by chunks of driven nodes (shareChunks).
struct SampleJob {
  const SceneRig* rig = nullptr;
  const PlanSelection* sel = nullptr;
  const KeyAt* keys = nullptr;  // per timeline
  glm::dmat4* world = nullptr;
  std::vector<std::vector<double>>* weights = nullptr;
};
constexpr uint32_t kNodesPerChunk = 256;

// A driven node's channels into its local matrix, left in world[node] for
// the pass down the hierarchy.
inline void sampleNode(const SampleJob& j, const NodeDrivers& d) {
  const RigNode& nd = j.rig->nodes[size_t(d.node)];
  auto drives = [&](AnimPath p) { return (d.driven >> int(p)) & 1u; };
  auto at = [&](AnimPath p) -> const KeyAt& { return j.keys[d.timeline[int(p)]]; };
  glm::dvec3 tr = nd.translation, sc = nd.scale;
  glm::dquat rot = nd.rotation;
  double v[4] = {0, 0, 0, 0};
  auto three = [&](AnimPath p) {
    const SamplerView& s = d.sampler[int(p)];
    if (s.comps == 3) sampleKeyed<3>(s, at(p), false, v);
    else sampleKeyed<0>(s, at(p), false, v);
  };
  if (drives(AnimPath::Translation)) {
    three(AnimPath::Translation);
    tr = {v[0], v[1], v[2]};
  }
  if (drives(AnimPath::Rotation)) {
    const SamplerView& s = d.sampler[int(AnimPath::Rotation)];
    if (s.comps == 4) sampleKeyed<4>(s, at(AnimPath::Rotation), true, v);
    else sampleKeyed<0>(s, at(AnimPath::Rotation), true, v);
    rot = glm::dquat(v[3], v[0], v[1], v[2]);
  }
  if (drives(AnimPath::Scale)) {
    three(AnimPath::Scale);
    sc = {v[0], v[1], v[2]};
  }
  if (j.weights && drives(AnimPath::Weights)) {
    const SamplerView& s = d.sampler[int(AnimPath::Weights)];
    std::vector<double>& w = (*j.weights)[size_t(d.node)];
    w.assign(s.comps, 0.0);
    sampleKeyed<0>(s, at(AnimPath::Weights), false, w.data());
  }
  j.world[size_t(d.node)] = localMatrix(nd, tr, rot, sc);
}

void sampleChunk(void* ctx, uint32_t chunk) {
  const SampleJob& j = *static_cast<const SampleJob*>(ctx);
  const size_t m = j.sel->drivers.size(), from = size_t(chunk) * kNodesPerChunk, to = std::min(m, from + kNodesPerChunk);
  for (size_t k = from; k < to; ++k) sampleNode(j, j.sel->drivers[k]);
}

}  // namespace

AnimPlan& AnimPlan::operator=(AnimPlan&&) noexcept {
  owner = nullptr;
  selections.clear();
  restWorld.clear();
  restLocal.clear();
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
  const size_t which = r.animation == kAllAnimations ? 0 : size_t(r.animation) + 1;
  if (r.animation < kAllAnimations || which >= plan->selections.size()) {  // the rest pose
    for (int32_t i : rig.order) world[size_t(i)] = plan->restWorld[size_t(i)];
    return;
  }
  const PlanSelection& sel = plan->selections[which];
  // Each timeline's key interval once; then the driven nodes sampled, each
  // by one thread (threads only for thousands of nodes: waking one costs
  // microseconds).
  thread_local std::vector<KeyAt> keys;
  keys.resize(sel.timelines.size());
  for (size_t t = 0; t < sel.timelines.size(); ++t) keys[t] = keyAt(sel.timelines[t], r.time);
  SampleJob job;
  job.rig = &rig;
  job.sel = &sel;
  job.keys = keys.data();
  job.world = world.data();
  job.weights = weights;
  const size_t m = sel.drivers.size();
  int threads = 1;
#ifdef _OPENMP
  if (m >= 2048) threads = omp_get_max_threads();
#endif
  shareChunks(uint32_t((m + kNodesPerChunk - 1) / kNodesPerChunk), threads, sampleChunk, &job);
  // Down the hierarchy: driven nodes and those under them composed, the
  // others at rest.
  for (int32_t i : sel.resting) world[size_t(i)] = plan->restWorld[size_t(i)];
  composeMoved(sel.moved.data(), sel.moved.size(), plan->restLocal.data(), world.data());
}

std::vector<glm::dmat4> evaluateNodes(const SceneRig& rig, const PoseRequest& r, std::vector<std::vector<double>>* weights) {
  std::vector<glm::dmat4> world;
  evaluateNodes(rig, r, world, weights);
  return world;
}

namespace {

// A deformed draw's vertices with its morph targets applied (object space);
// its tangents too when it has tangent deltas and `tan` is given (the shader
// makes them orthogonal to the normal and normalises them).
void morph(const DeformedDraw& dd, const std::vector<double>& w, float3* pos, float3* nrm, uint32_t nv,
           float4* tan = nullptr) {
  std::vector<double> tw(dd.targets, 0.0);
  for (uint32_t t = 0; t < dd.targets && t < w.size(); ++t) tw[t] = w[t];
  const bool tangents = tan && !dd.targetTangents.empty();
  for (uint32_t v = 0; v < nv; ++v) {
    glm::dvec3 q(dd.basePositions[v].x, dd.basePositions[v].y, dd.basePositions[v].z);
    glm::dvec3 m(dd.baseNormals[v].x, dd.baseNormals[v].y, dd.baseNormals[v].z);
    glm::dvec3 g(0.0);
    if (tangents) g = glm::dvec3(dd.baseTangents[v].x, dd.baseTangents[v].y, dd.baseTangents[v].z);
    for (uint32_t t = 0; t < dd.targets; ++t) {
      if (tw[t] == 0.0) continue;
      const float3 dp = dd.targetPositions[size_t(t) * nv + v];
      q += tw[t] * glm::dvec3(dp.x, dp.y, dp.z);
      if (!dd.targetNormals.empty()) {
        const float3 dn = dd.targetNormals[size_t(t) * nv + v];
        m += tw[t] * glm::dvec3(dn.x, dn.y, dn.z);
      }
      if (tangents) {
        const float3 dt = dd.targetTangents[size_t(t) * nv + v];
        g += tw[t] * glm::dvec3(dt.x, dt.y, dt.z);
      }
    }
    pos[v] = {float(q.x), float(q.y), float(q.z)};
    nrm[v] = {float(m.x), float(m.y), float(m.z)};
    if (tangents) tan[v] = {float(g.x), float(g.y), float(g.z), dd.baseTangents[v].w};
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
    float4* tan = s.tangents.size() >= size_t(p.firstVertex) + nv ? s.tangents.data() + p.firstVertex : nullptr;
    morph(dd, weights[size_t(rig.drawNode[dd.draw])], pos, nrm, nv, tan);  // morph targets first, then the skin
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
