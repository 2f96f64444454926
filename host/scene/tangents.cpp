// Generated tangents (tangents.h): the sums are in double precision, so a
// vertex's tangent does not depend on the order its triangles come in beyond
// rounding of the final float.
#include "host/scene/tangents.h"

#include <cmath>
#include <cstdint>

namespace rast {
namespace {

struct V3 {
  double x, y, z;
};
V3 sub(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 scale(V3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
V3 of(const float3& v) { return {v.x, v.y, v.z}; }

// Per vertex and handedness (0: w = +1, 1: w = -1): the weighted sum of the
// tangents of the vertex's triangles of that handedness, and their weight.
struct Sum {
  V3 t[2] = {{0, 0, 0}, {0, 0, 0}};
  double weight[2] = {0, 0};
};

}  // namespace

GeneratedTangents generateTangents(const std::vector<float3>& pos, const std::vector<float3>& nrm,
                                   const std::vector<float2>& uv, std::vector<uint32_t>& idx, bool split) {
  const size_t nv = pos.size();
  std::vector<Sum> sums(nv);
  std::vector<V3> normal(nv, V3{0, 0, 0});
  for (size_t v = 0; v < nv; ++v) {
    const V3 n = of(nrm[v]);
    const double l = std::sqrt(dot(n, n));
    if (l > 0.0 && std::isfinite(l)) normal[v] = scale(n, 1.0 / l);
  }
  std::vector<int8_t> cornerSide(idx.size(), -1);  // -1: the corner adds nothing
  for (size_t t = 0; t + 2 < idx.size(); t += 3) {
    const uint32_t c[3] = {idx[t], idx[t + 1], idx[t + 2]};
    if (c[0] >= nv || c[1] >= nv || c[2] >= nv) continue;  // the loader has refused such indices already
    const V3 e1 = sub(of(pos[c[1]]), of(pos[c[0]])), e2 = sub(of(pos[c[2]]), of(pos[c[0]]));
    const double du1 = double(uv[c[1]].x) - uv[c[0]].x, dv1 = double(uv[c[1]].y) - uv[c[0]].y;
    const double du2 = double(uv[c[2]].x) - uv[c[0]].x, dv2 = double(uv[c[2]].y) - uv[c[0]].y;
    const double det = du1 * dv2 - du2 * dv1;
    if (!(std::abs(det) > 0.0) || !std::isfinite(1.0 / det)) continue;  // no texture direction on this triangle
    // dP/du and dP/dv of the triangle (positions and coordinates are both linear over it).
    const V3 T = scale(sub(scale(e1, dv2), scale(e2, dv1)), 1.0 / det);
    const V3 B = scale(sub(scale(e2, du1), scale(e1, du2)), 1.0 / det);
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = c[k];
      const V3 n = normal[v];
      // The triangle's tangent in the vertex's tangent plane, unit length.
      V3 tt = sub(T, scale(n, dot(n, T)));
      const double l = std::sqrt(dot(tt, tt));
      if (!(l > 0.0) || !std::isfinite(l)) continue;
      tt = scale(tt, 1.0 / l);
      // Handedness: glTF's normal textures have +Y up the image, towards
      // decreasing v (texture coordinates start at the image's top left), so
      // the bitangent is -dP/dv: w = +1 when -dP/dv lies on the side of N x T.
      const int side = dot(cross(n, tt), B) > 0.0 ? 1 : 0;
      // Weighted by the triangle's angle at the vertex.
      const V3 a = sub(of(pos[c[(k + 1) % 3]]), of(pos[v])), b = sub(of(pos[c[(k + 2) % 3]]), of(pos[v]));
      const double angle = std::atan2(std::sqrt(dot(cross(a, b), cross(a, b))), dot(a, b));
      Sum& s = sums[v];
      s.t[side] = {s.t[side].x + tt.x * angle, s.t[side].y + tt.y * angle, s.t[side].z + tt.z * angle};
      s.weight[side] += angle;
      cornerSide[t + k] = int8_t(side);
    }
  }
  auto tangent = [&](size_t v, int side) {
    const Sum& s = sums[v];
    if (!(s.weight[side] > 0.0)) return float4{0.0f, 0.0f, 0.0f, 0.0f};
    const V3 n = normal[v];
    V3 t = sub(s.t[side], scale(n, dot(n, s.t[side])));
    const double l = std::sqrt(dot(t, t));
    if (!(l > 1e-6 * s.weight[side])) return float4{0.0f, 0.0f, 0.0f, 0.0f};
    t = scale(t, 1.0 / l);
    return float4{float(t.x), float(t.y), float(t.z), side ? -1.0f : 1.0f};
  };
  GeneratedTangents g;
  g.tangents.assign(nv, float4{0.0f, 0.0f, 0.0f, 0.0f});
  std::vector<int8_t> chosen(nv, 0);
  for (size_t v = 0; v < nv; ++v) {
    // A vertex shared by triangles of both handednesses (a mirrored seam
    // within one vertex) keeps the side of the larger angle ...
    chosen[v] = sums[v].weight[1] > sums[v].weight[0] ? 1 : 0;
    g.tangents[v] = tangent(v, chosen[v]);
  }
  if (!split) return g;
  // ... and, when splitting, the other side's corners move to a copy of it
  // with that side's tangent (one copy per vertex).
  std::vector<uint32_t> copyOf(nv, UINT32_MAX);
  for (size_t i = 0; i < idx.size(); ++i) {
    const uint32_t v = idx[i];
    if (cornerSide[i] < 0 || cornerSide[i] == chosen[v]) continue;
    if (copyOf[v] == UINT32_MAX) {
      copyOf[v] = uint32_t(nv + g.copies.size());
      g.copies.push_back(v);
      g.tangents.push_back(tangent(v, cornerSide[i]));
    }
    idx[i] = copyOf[v];
  }
  return g;
}

}  // namespace rast
