// Per-vertex tangents for normal mapping where a file gives none (glTF 2.0,
// 3.7.2.1: "client implementations SHOULD calculate tangents"): each
// triangle's dP/du made orthogonal to the vertex normal and summed at its
// vertices, the handedness from its dP/dv (glTF's bitangent points up the
// image: -dP/dv).
// docs/gltf-support.md says how this differs from MikkTSpace and by how much.
#pragma once

#include "base/vec.h"

#include <cstdint>
#include <vector>

namespace rast {

// Tangents (xyz unit, w = +1 or -1: bitangent = w * cross(N, T)) of the
// vertices of an indexed triangle list, one per vertex: the tangents of the
// vertex's triangles in its tangent plane, unit length, weighted by the
// triangle's angle at the vertex (as MikkTSpace weighs them), summed per
// handedness. A vertex whose triangles give no usable direction (degenerate
// positions or texture coordinates) gets (0, 0, 0, 0): the shader then builds
// that triangle's frame from its own dP/du.
// A vertex whose triangles disagree in handedness (a mirrored seam within one
// vertex) keeps the side with the larger angle; with `split`, the other
// side's corners move to a copy of the vertex (listed in `copies`, its index
// vertices + k, idx rewritten), as MikkTSpace splits such vertices.
struct GeneratedTangents {
  std::vector<float4> tangents;  // per vertex, then per copy
  std::vector<uint32_t> copies;  // the vertex each copy repeats
};
GeneratedTangents generateTangents(const std::vector<float3>& pos, const std::vector<float3>& nrm,
                                   const std::vector<float2>& uv, std::vector<uint32_t>& idx, bool split);

}  // namespace rast
