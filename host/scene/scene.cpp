#include "host/scene/scene.h"

#include <cmath>
#include <limits>

namespace rast {

uint32_t Scene::triangleCount() const {
  uint64_t n = 0;
  for (const Draw& d : draws) n += prims[d.prim].triCount;
  if (n > std::numeric_limits<uint32_t>::max() - 1)
    throw Error("scene has more than 2^32-2 triangles; primitive ids would overflow");
  return static_cast<uint32_t>(n);
}

uint64_t Scene::lineCount() const {
  uint64_t n = 0;
  for (const Draw& d : draws) n += prims[d.prim].lineCount;
  return n;
}

uint64_t Scene::pointCount() const {
  uint64_t n = 0;
  for (const Draw& d : draws) n += prims[d.prim].pointCount;
  return n;
}

void Scene::worldBounds(glm::dvec3& lo, glm::dvec3& hi) const {
  lo = glm::dvec3(std::numeric_limits<double>::infinity());
  hi = -lo;
  for (const Draw& d : draws) {
    const MeshPrim& p = prims[d.prim];
    for (uint32_t i = 0; i < p.vertexCount; ++i) {
      const float3 v = positions[p.firstVertex + i];
      const glm::dvec3 w = glm::dvec3(d.model * glm::dvec4(v.x, v.y, v.z, 1.0));
      lo = glm::min(lo, w);
      hi = glm::max(hi, w);
    }
  }
}

void Scene::validate() const {
  const size_t nv = positions.size();
  if (normals.size() != nv) throw Error("internal: normal stream size mismatch");
  if (!uvs.empty() && uvs.size() != nv) throw Error("internal: uv stream size mismatch");
  if (!colors.empty() && colors.size() != nv) throw Error("internal: colour stream size mismatch");
  if (!uvs1.empty() && uvs1.size() != nv) throw Error("internal: second uv stream size mismatch");
  if (!tangents.empty() && tangents.size() != nv) throw Error("internal: tangent stream size mismatch");
  for (const MeshPrim& p : prims) {
    if (uint64_t(p.firstVertex) + p.vertexCount > nv) throw Error("internal: primitive vertex range");
    if ((uint64_t(p.firstTri) + p.triCount) * 3 > indices.size())
      throw Error("internal: primitive triangle range");
    for (uint64_t i = uint64_t(p.firstTri) * 3; i < (uint64_t(p.firstTri) + p.triCount) * 3; ++i)
      if (indices[i] >= p.vertexCount) throw Error("index out of range");
    if ((uint64_t(p.firstLine) + p.lineCount) * 2 > lineIndices.size()) throw Error("internal: primitive line range");
    if (uint64_t(p.firstPoint) + p.pointCount > pointIndices.size()) throw Error("internal: primitive point range");
    for (uint64_t i = uint64_t(p.firstLine) * 2; i < (uint64_t(p.firstLine) + p.lineCount) * 2; ++i)
      if (lineIndices[i] >= p.vertexCount) throw Error("index out of range");
    for (uint64_t i = p.firstPoint; i < uint64_t(p.firstPoint) + p.pointCount; ++i)
      if (pointIndices[i] >= p.vertexCount) throw Error("index out of range");
    if (p.material >= int32_t(materials.size())) throw Error("internal: material index");
  }
  for (const Material& m : materials)
    if (m.texture >= int32_t(textures.size())) throw Error("internal: texture index");
  for (const Draw& d : draws)
    if (d.prim >= prims.size()) throw Error("internal: draw primitive index");
}

uint32_t addPrim(Scene& s, const std::vector<float3>& pos, const std::vector<float3>* nrm,
                 const std::vector<float2>* uv, const std::vector<float4>* col,
                 const std::vector<uint32_t>& idx, int32_t material) {
  if (idx.size() % 3 != 0) throw Error("internal: index count not a multiple of 3");
  const size_t n = pos.size();
  if ((nrm && nrm->size() != n) || (uv && uv->size() != n) || (col && col->size() != n))
    throw Error("vertex attribute counts differ from the POSITION count");
  for (uint32_t i : idx)
    if (i >= n) throw Error("index " + std::to_string(i) + " out of range (" + std::to_string(n) + " vertices)");
  MeshPrim p;
  p.firstVertex = static_cast<uint32_t>(s.positions.size());
  p.firstTri = static_cast<uint32_t>(s.indices.size() / 3);
  p.material = material;
  const size_t oldVerts = s.positions.size();

  // Streams that appear for the first time are back-filled for earlier
  // primitives; streams this primitive lacks get defaults.
  // (A stream exists once any primitive has it, even the very first one, when
  // the stream is still empty: hence the flags rather than !empty().)
  const bool withUV = uv || !s.uvs.empty(), withColor = col || !s.colors.empty();
  if (uv && s.uvs.empty()) s.uvs.assign(oldVerts, float2{0.0f, 0.0f});
  if (col && s.colors.empty()) s.colors.assign(oldVerts, float4{1.0f, 1.0f, 1.0f, 1.0f});

  auto pushVertex = [&](uint32_t v, const float3& n) {
    s.positions.push_back(pos[v]);
    s.normals.push_back(n);
    if (withUV) s.uvs.push_back(uv ? (*uv)[v] : float2{0.0f, 0.0f});
    if (withColor) s.colors.push_back(col ? (*col)[v] : float4{1.0f, 1.0f, 1.0f, 1.0f});
  };

  if (nrm) {
    for (size_t v = 0; v < pos.size(); ++v) pushVertex(uint32_t(v), (*nrm)[v]);
    for (uint32_t i : idx) s.indices.push_back(i);
  } else {
    // No normals: every triangle gets its own three corners carrying the face
    // normal normalize(cross(b-a, c-a)), as glTF prescribes (flat shading).
    for (size_t t = 0; t < idx.size(); t += 3) {
      const float3 a = pos[idx[t]], b = pos[idx[t + 1]], c = pos[idx[t + 2]];
      const float3 n = normalize(cross(b - a, c - a));
      const uint32_t base = static_cast<uint32_t>(s.positions.size()) - p.firstVertex;
      for (int k = 0; k < 3; ++k) pushVertex(idx[t + k], n);
      s.indices.push_back(base);
      s.indices.push_back(base + 1);
      s.indices.push_back(base + 2);
    }
  }
  p.vertexCount = static_cast<uint32_t>(s.positions.size()) - p.firstVertex;
  p.triCount = static_cast<uint32_t>(s.indices.size() / 3) - p.firstTri;
  s.prims.push_back(p);
  return static_cast<uint32_t>(s.prims.size() - 1);
}

uint32_t addLinePrim(Scene& s, const std::vector<float3>& pos, const std::vector<float4>* col,
                     const std::vector<uint32_t>& segments, const std::vector<uint32_t>& points, int32_t material) {
  if (segments.size() % 2 != 0) throw Error("internal: line index count not a multiple of 2");
  const size_t n = pos.size();
  if (col && col->size() != n) throw Error("vertex attribute counts differ from the POSITION count");
  for (uint32_t i : segments)
    if (i >= n) throw Error("index " + std::to_string(i) + " out of range (" + std::to_string(n) + " vertices)");
  for (uint32_t i : points)
    if (i >= n) throw Error("index " + std::to_string(i) + " out of range (" + std::to_string(n) + " vertices)");
  MeshPrim p;
  p.firstVertex = static_cast<uint32_t>(s.positions.size());
  p.firstTri = static_cast<uint32_t>(s.indices.size() / 3);
  p.firstLine = static_cast<uint32_t>(s.lineIndices.size() / 2);
  p.firstPoint = static_cast<uint32_t>(s.pointIndices.size());
  p.material = material;
  const size_t oldVerts = s.positions.size();
  const bool withUV = !s.uvs.empty(), withColor = col || !s.colors.empty();
  if (col && s.colors.empty()) s.colors.assign(oldVerts, float4{1.0f, 1.0f, 1.0f, 1.0f});
  for (size_t v = 0; v < n; ++v) {
    s.positions.push_back(pos[v]);
    s.normals.push_back(float3{0.0f, 0.0f, 1.0f});
    if (withUV) s.uvs.push_back(float2{0.0f, 0.0f});
    if (withColor) s.colors.push_back(col ? (*col)[v] : float4{1.0f, 1.0f, 1.0f, 1.0f});
  }
  s.lineIndices.insert(s.lineIndices.end(), segments.begin(), segments.end());
  s.pointIndices.insert(s.pointIndices.end(), points.begin(), points.end());
  p.vertexCount = static_cast<uint32_t>(n);
  p.lineCount = static_cast<uint32_t>(segments.size() / 2);
  p.pointCount = static_cast<uint32_t>(points.size());
  s.prims.push_back(p);
  return static_cast<uint32_t>(s.prims.size() - 1);
}

}  // namespace rast
