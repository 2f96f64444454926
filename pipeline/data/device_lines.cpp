// Uploads the scene's drawn points and line segments as flat lists: one entry
// per drawn point or segment, in scene traversal order, so that a point or
// line primitive id is its position in the list plus an offset (see
// docs/points-lines.md) and a kernel needs no draw lookup.
#include "pipeline/data/device_scene.h"

#include <limits>

namespace rast {

void DeviceScene::uploadLinesAndPoints(const Scene& s) {
  std::vector<LineGPU> segs, pts;
  uint64_t vert = 0;
  for (const Draw& dr : s.draws) {
    const MeshPrim& p = s.prims[dr.prim];
    for (uint32_t k = 0; k < p.lineCount; ++k) {
      const uint32_t a = s.lineIndices[2 * size_t(p.firstLine + k)], b = s.lineIndices[2 * size_t(p.firstLine + k) + 1];
      segs.push_back(LineGPU{uint32_t(vert + a), uint32_t(vert + b), p.firstVertex + a, p.material});
    }
    for (uint32_t k = 0; k < p.pointCount; ++k) {
      const uint32_t a = s.pointIndices[p.firstPoint + k];
      pts.push_back(LineGPU{uint32_t(vert + a), uint32_t(vert + a), p.firstVertex + a, p.material});
    }
    vert += p.vertexCount;
  }
  // Ids of points and lines follow the triangles' and must fit the 31 bits the
  // visibility key leaves them (raster_lines.h).
  if (uint64_t(numTris) + segs.size() + pts.size() >= (1ull << 31))
    throw Error("scene too large: more than 2^31 drawn triangles, lines and points");
  numLines = uint32_t(segs.size());
  numPoints = uint32_t(pts.size());
  auto up = [](const char* label, const std::vector<LineGPU>& v) {
    DView<LineGPU> d = allocUninit<LineGPU>(label, v.size());
    if (!v.empty()) {
      Kokkos::View<const LineGPU*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>> h(v.data(), v.size());
      Kokkos::deep_copy(d, h);
    }
    return d;
  };
  lines = up("scene.lines", segs);
  points = up("scene.points", pts);
}

}  // namespace rast
