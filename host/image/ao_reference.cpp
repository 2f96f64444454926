#include "host/image/ao_reference.h"

#include <glm/gtc/matrix_inverse.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

namespace rast {
namespace {

struct Tri {
  glm::dvec3 a, e1, e2;
};

struct Node {
  glm::dvec3 lo, hi;
  int left = -1, right = -1;  // children, or -1 for a leaf
  int first = 0, count = 0;   // leaf: triangles [first, first + count) of the ordered list
};

// Median-split BVH over triangle centroids (the longest axis), leaves of <= 4.
class Bvh {
 public:
  explicit Bvh(std::vector<Tri> tris) : tris_(std::move(tris)) {
    order_.resize(tris_.size());
    std::iota(order_.begin(), order_.end(), 0);
    if (!tris_.empty()) build(0, int(tris_.size()));
  }

  // Any hit with t in (tmin, tmax)?
  bool occluded(const glm::dvec3& o, const glm::dvec3& d, double tmin, double tmax) const {
    if (nodes_.empty()) return false;
    const glm::dvec3 inv(1.0 / d.x, 1.0 / d.y, 1.0 / d.z);
    int stack[64], sp = 0;
    stack[sp++] = 0;
    while (sp) {
      const Node& n = nodes_[size_t(stack[--sp])];
      if (!boxHit(n, o, inv, tmax)) continue;
      if (n.left < 0) {
        for (int k = n.first; k < n.first + n.count; ++k)
          if (triHit(tris_[size_t(order_[size_t(k)])], o, d, tmin, tmax)) return true;
      } else if (sp + 2 <= 64) {
        stack[sp++] = n.left;
        stack[sp++] = n.right;
      }
    }
    return false;
  }

 private:
  static glm::dvec3 centroid(const Tri& t) { return t.a + (t.e1 + t.e2) / 3.0; }

  int build(int first, int count) {
    const int idx = int(nodes_.size());
    nodes_.emplace_back();
    Node n;
    n.lo = glm::dvec3(1e300);
    n.hi = glm::dvec3(-1e300);
    for (int k = first; k < first + count; ++k) {
      const Tri& t = tris_[size_t(order_[size_t(k)])];
      for (const glm::dvec3& p : {t.a, t.a + t.e1, t.a + t.e2}) {
        n.lo = glm::min(n.lo, p);
        n.hi = glm::max(n.hi, p);
      }
    }
    if (count <= 4) {
      n.first = first;
      n.count = count;
      nodes_[size_t(idx)] = n;
      return idx;
    }
    const glm::dvec3 ext = n.hi - n.lo;
    const int axis = ext.x > ext.y ? (ext.x > ext.z ? 0 : 2) : (ext.y > ext.z ? 1 : 2);
    const int mid = first + count / 2;
    std::nth_element(order_.begin() + first, order_.begin() + mid, order_.begin() + first + count, [&](int a, int b) {
      return centroid(tris_[size_t(a)])[axis] < centroid(tris_[size_t(b)])[axis];
    });
    n.left = build(first, mid - first);
    n.right = build(mid, first + count - mid);
    nodes_[size_t(idx)] = n;
    return idx;
  }

  static bool boxHit(const Node& n, const glm::dvec3& o, const glm::dvec3& inv, double tmax) {
    double t0 = 0.0, t1 = tmax;
    for (int a = 0; a < 3; ++a) {
      double ta = (n.lo[a] - o[a]) * inv[a], tb = (n.hi[a] - o[a]) * inv[a];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
      if (t0 > t1) return false;
    }
    return true;
  }

  // Moeller-Trumbore, both faces.
  static bool triHit(const Tri& t, const glm::dvec3& o, const glm::dvec3& d, double tmin, double tmax) {
    const glm::dvec3 p = glm::cross(d, t.e2);
    const double det = glm::dot(t.e1, p);
    if (std::abs(det) < 1e-300) return false;
    const double inv = 1.0 / det;
    const glm::dvec3 s = o - t.a;
    const double u = glm::dot(s, p) * inv;
    if (u < 0.0 || u > 1.0) return false;
    const glm::dvec3 q = glm::cross(s, t.e1);
    const double v = glm::dot(d, q) * inv;
    if (v < 0.0 || u + v > 1.0) return false;
    const double tt = glm::dot(t.e2, q) * inv;
    return tt > tmin && tt < tmax;
  }

  std::vector<Tri> tris_;
  std::vector<int> order_;
  std::vector<Node> nodes_;
};

std::vector<Tri> worldTriangles(const Scene& s) {
  std::vector<Tri> out;
  for (const Draw& d : s.draws) {
    const MeshPrim& p = s.prims[d.prim];
    for (uint32_t t = 0; t < p.triCount; ++t) {
      glm::dvec3 v[3];
      for (int k = 0; k < 3; ++k) {
        const float3 q = s.positions[p.firstVertex + s.indices[3 * size_t(p.firstTri + t) + k]];
        v[k] = glm::dvec3(d.model * glm::dvec4(q.x, q.y, q.z, 1.0));
      }
      out.push_back({v[0], v[1] - v[0], v[2] - v[0]});
    }
  }
  return out;
}

}  // namespace

std::vector<float> rayTracedAo(const Scene& scene, const Camera& cam, int w, int h, const std::vector<float4>& geom,
                               float radius, int rays, uint32_t seed) {
  const Bvh bvh(worldTriangles(scene));
  const glm::dmat4 view = cam.view(), invView = glm::inverse(view);
  const glm::dmat4 proj = cam.projection(w, h);
  const double tanX = 1.0 / proj[0][0], tanY = 1.0 / proj[1][1];
  std::vector<float> ao(size_t(w) * h, 1.0f);
  // Stratified directions per pixel (sqrt(rays) x sqrt(rays) cells, rounded
  // up), jittered by a per-pixel hash: independent of thread scheduling.
  const int side = std::max(1, int(std::ceil(std::sqrt(double(rays)))));
  // Host threads, one row at a time (rows write disjoint pixels).
  using HostRange = Kokkos::RangePolicy<Kokkos::DefaultHostExecutionSpace, Kokkos::Schedule<Kokkos::Dynamic>>;
  Kokkos::parallel_for("rast::aoref", HostRange(0, h), [&](const int y) {
    for (int x = 0; x < w; ++x) {
      const float4 g = geom[size_t(y) * w + x];
      if (!(g.w > 0.0f)) continue;
      const double d = g.w;
      const glm::dvec3 pv((2.0 * (x + 0.5) / w - 1.0) * tanX * d, (2.0 * (y + 0.5) / h - 1.0) * tanY * d, -d);
      const glm::dvec3 P = glm::dvec3(invView * glm::dvec4(pv, 1.0));
      const glm::dvec3 N = glm::normalize(glm::dvec3(invView * glm::dvec4(g.x, g.y, g.z, 0.0)));
      const glm::dvec3 a = std::abs(N.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
      const glm::dvec3 T = glm::normalize(glm::cross(a, N)), B = glm::cross(N, T);
      uint64_t rng = (uint64_t(seed) << 40) ^ (uint64_t(y) * 0x9e3779b97f4a7c15ull + uint64_t(x) * 0xbf58476d1ce4e5b9ull);
      auto uniform = [&rng]() {  // splitmix64
        uint64_t z = (rng += 0x9e3779b97f4a7c15ull);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return double((z ^ (z >> 31)) >> 11) / double(1ull << 53);
      };
      // Offset off the surface against self-intersection, relative to the scale.
      const double eps = 1e-2 * radius + 1e-6 * d;
      int hits = 0, n = 0;
      for (int k = 0; k < side * side && n < rays; ++k, ++n) {
        const double u1 = ((k % side) + uniform()) / side, u2 = ((k / side) + uniform()) / side;
        const double r = std::sqrt(u1), phi = 2.0 * 3.14159265358979 * u2;
        const glm::dvec3 dir = T * (r * std::cos(phi)) + B * (r * std::sin(phi)) + N * std::sqrt(std::max(0.0, 1.0 - u1));
        hits += bvh.occluded(P + N * eps, dir, 0.0, double(radius)) ? 1 : 0;
      }
      ao[size_t(y) * w + x] = float(1.0 - double(hits) / n);
    }
  });
  Kokkos::DefaultHostExecutionSpace().fence();
  return ao;
}

}  // namespace rast
