// Animation evaluation on the host: samplers at a time (STEP, LINEAR with
// quaternion slerp, CUBICSPLINE with tangents scaled by the key interval),
// node transforms down the hierarchy, then the pose written into the Scene:
// morph targets, then skinning (glTF 2.0, 3.7.3 and 3.11). Double precision
// throughout and no threads, so a time gives the same pose on every backend.
#include "host/scene/animation.h"

#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>

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

void normalise4(double* q) {
  const double len = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (len > 0.0)
    for (int k = 0; k < 4; ++k) q[k] /= len;
}

}  // namespace

void sampleAt(const AnimSampler& s, double t, bool rotation, double* out) {
  const uint32_t c = s.comps, n = uint32_t(s.times.size());
  const bool cubic = s.interp == Interpolation::CubicSpline;
  const uint32_t stride = cubic ? 3 * c : c, valueAt = cubic ? c : 0;  // a key's value after its in-tangent
  auto value = [&](uint32_t k, uint32_t j) { return double(s.values[size_t(k) * stride + valueAt + j]); };
  if (n == 0) return;
  if (!(t > s.times[0]) || n == 1) {
    for (uint32_t j = 0; j < c; ++j) out[j] = value(0, j);
  } else if (t >= s.times[n - 1]) {
    for (uint32_t j = 0; j < c; ++j) out[j] = value(n - 1, j);
  } else {
    // The key interval [k, k+1) holding t.
    const uint32_t k = uint32_t(std::upper_bound(s.times.begin(), s.times.end(), t, [](double a, float b) { return a < double(b); }) - s.times.begin()) - 1;
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

std::vector<glm::dmat4> evaluateNodes(const SceneRig& rig, const PoseRequest& r, std::vector<std::vector<double>>* weights) {
  const size_t n = rig.nodes.size();
  std::vector<glm::dvec3> tr(n), sc(n);
  std::vector<glm::dquat> rot(n);
  std::vector<std::vector<double>> w(weights ? n : 0);
  for (size_t i = 0; i < n; ++i) {
    tr[i] = rig.nodes[i].translation;
    rot[i] = rig.nodes[i].rotation;
    sc[i] = rig.nodes[i].scale;
    if (weights) w[i] = rig.nodes[i].weights;
  }
  for (size_t a = 0; a < rig.animations.size(); ++a) {
    if (r.animation != kAllAnimations && size_t(r.animation) != a) continue;
    const Animation& anim = rig.animations[a];
    for (const AnimChannel& ch : anim.channels) {
      const AnimSampler& s = anim.samplers[size_t(ch.sampler)];
      double v[4] = {0, 0, 0, 0};
      const size_t i = size_t(ch.node);
      switch (ch.path) {
        case AnimPath::Translation: sampleAt(s, r.time, false, v); tr[i] = {v[0], v[1], v[2]}; break;
        case AnimPath::Scale: sampleAt(s, r.time, false, v); sc[i] = {v[0], v[1], v[2]}; break;
        case AnimPath::Rotation: sampleAt(s, r.time, true, v); rot[i] = glm::dquat(v[3], v[0], v[1], v[2]); break;
        case AnimPath::Weights:
          if (!weights) break;
          w[i].assign(s.comps, 0.0);
          sampleAt(s, r.time, false, w[i].data());
          break;
      }
    }
  }
  std::vector<glm::dmat4> world(n, glm::dmat4(1.0));
  for (int32_t i : rig.order) {
    const RigNode& nd = rig.nodes[size_t(i)];
    glm::dmat4 local = nd.matrix;
    if (!nd.hasMatrix) {  // T R S, built directly: columns of R scaled, T in the last
      const glm::dmat3 r = glm::mat3_cast(glm::normalize(rot[i]));
      local = glm::dmat4(glm::dvec4(r[0] * sc[i].x, 0.0), glm::dvec4(r[1] * sc[i].y, 0.0), glm::dvec4(r[2] * sc[i].z, 0.0),
                         glm::dvec4(tr[i], 1.0));
    }
    world[i] = nd.parent >= 0 ? world[size_t(nd.parent)] * local : local;
  }
  if (weights) *weights = std::move(w);
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
