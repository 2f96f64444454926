#include "host/distributed/scene_share.h"

#include <algorithm>
#include <limits>

namespace rast {
namespace {

uint64_t cut(uint64_t n, int i, int parts) {
  // floor(n * i / parts) without overflow for n < 2^63 / parts.
  return n / uint64_t(parts) * uint64_t(i) + n % uint64_t(parts) * uint64_t(i) / uint64_t(parts);
}

// Copies prim `p` of `from` into `to`, keeping triangles [ta, tb), segments
// [la, lb) and points [pa, pb) of it (relative to the primitive), with only the
// vertices they use (every vertex with `allVertices`), kept in source order.
uint32_t copyPart(const Scene& from, const MeshPrim& p, Scene& to, uint32_t ta, uint32_t tb, uint32_t la, uint32_t lb,
                  uint32_t pa, uint32_t pb, bool allVertices = false) {
  constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();
  std::vector<uint32_t> remap(p.vertexCount, allVertices ? 0 : kNone);
  const auto mark = [&](uint32_t v) {
    if (v < p.vertexCount) remap[v] = 0;
  };
  for (uint64_t i = 3 * uint64_t(p.firstTri + ta); i < 3 * uint64_t(p.firstTri + tb); ++i) mark(from.indices[i]);
  for (uint64_t i = 2 * uint64_t(p.firstLine + la); i < 2 * uint64_t(p.firstLine + lb); ++i) mark(from.lineIndices[i]);
  for (uint64_t i = p.firstPoint + pa; i < uint64_t(p.firstPoint) + pb; ++i) mark(from.pointIndices[i]);
  MeshPrim q;
  q.material = p.material;
  q.firstVertex = uint32_t(to.positions.size());
  q.firstTri = uint32_t(to.indices.size() / 3);
  q.firstLine = uint32_t(to.lineIndices.size() / 2);
  q.firstPoint = uint32_t(to.pointIndices.size());
  uint32_t n = 0;
  for (uint32_t v = 0; v < p.vertexCount; ++v) {
    if (remap[v] == kNone) continue;
    remap[v] = n++;
    const size_t src = size_t(p.firstVertex) + v;
    to.positions.push_back(from.positions[src]);
    to.normals.push_back(from.normals[src]);
    if (!from.uvs.empty()) to.uvs.push_back(from.uvs[src]);
    if (!from.uvs1.empty()) to.uvs1.push_back(from.uvs1[src]);
    if (!from.colors.empty()) to.colors.push_back(from.colors[src]);
    if (!from.tangents.empty()) to.tangents.push_back(from.tangents[src]);
  }
  const auto idx = [&](uint32_t v) { return v < p.vertexCount ? remap[v] : v; };  // out of range: validate() says so
  for (uint64_t i = 3 * uint64_t(p.firstTri + ta); i < 3 * uint64_t(p.firstTri + tb); ++i)
    to.indices.push_back(idx(from.indices[i]));
  for (uint64_t i = 2 * uint64_t(p.firstLine + la); i < 2 * uint64_t(p.firstLine + lb); ++i)
    to.lineIndices.push_back(idx(from.lineIndices[i]));
  for (uint64_t i = p.firstPoint + pa; i < uint64_t(p.firstPoint) + pb; ++i) to.pointIndices.push_back(idx(from.pointIndices[i]));
  q.vertexCount = n;
  q.triCount = tb - ta;
  q.lineCount = lb - la;
  q.pointCount = pb - pa;
  to.prims.push_back(q);
  return uint32_t(to.prims.size() - 1);
}

// [a, b) of a draw's local range [0, n) that falls in the global [lo, hi), the
// draw starting at `at`.
void overlap(uint64_t at, uint64_t n, uint64_t lo, uint64_t hi, uint32_t& a, uint32_t& b) {
  const uint64_t s = std::max(at, lo), e = std::min(at + n, hi);
  a = b = 0;
  if (s < e) {
    a = uint32_t(s - at);
    b = uint32_t(e - at);
  }
}

}  // namespace

bool isBlendDraw(const Scene& s, const Draw& d) {
  if (d.prim >= s.prims.size()) return false;
  const MeshPrim& p = s.prims[d.prim];
  return p.triCount > 0 && p.material >= 0 && size_t(p.material) < s.materials.size() &&
         s.materials[size_t(p.material)].alphaMode == AlphaMode::Blend;
}

bool drawsBlend(const Scene& s) {
  for (const Draw& d : s.draws)
    if (isBlendDraw(s, d)) return true;
  return false;
}

std::vector<ShareRange> planShares(uint64_t triangles, uint64_t lines, uint64_t points, int ranks) {
  std::vector<ShareRange> out(size_t(std::max(ranks, 1)));
  for (int r = 0; r < int(out.size()); ++r) {
    ShareRange& s = out[size_t(r)];
    s.t0 = cut(triangles, r, int(out.size()));
    s.t1 = cut(triangles, r + 1, int(out.size()));
    s.l0 = cut(lines, r, int(out.size()));
    s.l1 = cut(lines, r + 1, int(out.size()));
    s.p0 = cut(points, r, int(out.size()));
    s.p1 = cut(points, r + 1, int(out.size()));
  }
  return out;
}

Scene takeShare(const Scene& full, const ShareRange& r, std::vector<TriRun>* blendWhole) {
  if (blendWhole && r.t0 != 0) throw Error("internal: only the first share keeps the BLEND draws whole");
  Scene s;
  s.name = full.name;
  s.camera = full.camera;
  s.look = full.look;
  s.materials = full.materials;
  s.textures = full.textures;
  s.cameras = full.cameras;
  s.facts = full.facts;
  s.sourceFiles = full.sourceFiles;
  std::vector<int64_t> whole(full.prims.size(), -1);  // full prim -> its copy in s, when drawn whole
  uint64_t T = 0, L = 0, P = 0;
  uint64_t local = 0;  // s's drawn triangles so far
  for (const Draw& d : full.draws) {
    const MeshPrim& p = full.prims[d.prim];
    uint32_t ta, tb, la, lb, pa, pb;
    overlap(T, p.triCount, r.t0, r.t1, ta, tb);
    overlap(L, p.lineCount, r.l0, r.l1, la, lb);
    overlap(P, p.pointCount, r.p0, r.p1, pa, pb);
    const bool keepWhole = blendWhole && isBlendDraw(full, d);  // triangles only: one kind a primitive
    if (keepWhole) {
      // r.t0 is 0: the draw's triangles past r.t1 (all of them, or the tail of
      // the draw cut by r's end) are numbered after r's, in this order.
      const uint64_t past = std::max(T, r.t1);
      if (past < T + p.triCount) blendWhole->push_back(TriRun{local + (past - T), past, T + p.triCount - past});
      ta = 0;
      tb = p.triCount;
    }
    T += p.triCount;
    L += p.lineCount;
    P += p.pointCount;
    if (ta == tb && la == lb && pa == pb) continue;
    uint32_t prim;
    if (tb - ta == p.triCount && lb - la == p.lineCount && pb - pa == p.pointCount) {
      if (whole[d.prim] < 0)
        whole[d.prim] = copyPart(full, p, s, 0, p.triCount, 0, p.lineCount, 0, p.pointCount, keepWhole);
      prim = uint32_t(whole[d.prim]);
    } else {
      prim = copyPart(full, p, s, ta, tb, la, lb, pa, pb);
    }
    local += tb - ta;
    s.draws.push_back(Draw{prim, d.model});
  }
  return s;
}

}  // namespace rast
