// Uploads what the transparency passes need per draw (AlphaDraw: its glTF
// alphaMode as a class, the MASK cutoff, its bounding box centre), and only
// for scenes that draw a MASK or BLEND material: an opaque scene uploads
// nothing and its setup reads nothing more (docs/transparency.md).
#include "pipeline/data/device_scene.h"

#include <cmath>

namespace rast {

void DeviceScene::uploadAlphaDraws(const Scene& s) {
  std::vector<AlphaDraw> a;
  a.reserve(s.draws.size());
  for (const Draw& dr : s.draws) {
    const MeshPrim& p = s.prims[dr.prim];
    AlphaDraw g{0, 0.5f, float3{0.0f, 0.0f, 0.0f}};
    if (p.material >= 0 && size_t(p.material) < s.materials.size() && p.triCount > 0) {
      const Material& m = s.materials[size_t(p.material)];
      g.cls = m.alphaMode == AlphaMode::Mask ? 1 : m.alphaMode == AlphaMode::Blend ? 2 : 0;
      // glTF: alphaCutoff >= 0; a NaN or negative one keeps every fragment.
      g.cutoff = std::isfinite(m.alphaCutoff) ? m.alphaCutoff : 0.0f;
    }
    if (g.cls != 0 && p.vertexCount > 0) {
      float3 lo = s.positions[p.firstVertex], hi = lo;
      for (uint32_t k = 1; k < p.vertexCount; ++k) {
        const float3 v = s.positions[size_t(p.firstVertex) + k];
        lo = float3{std::fmin(lo.x, v.x), std::fmin(lo.y, v.y), std::fmin(lo.z, v.z)};
        hi = float3{std::fmax(hi.x, v.x), std::fmax(hi.y, v.y), std::fmax(hi.z, v.z)};
      }
      g.centre = float3{0.5f * (lo.x + hi.x), 0.5f * (lo.y + hi.y), 0.5f * (lo.z + hi.z)};
    }
    hasMask |= g.cls == 1;
    hasBlend |= g.cls == 2;
    a.push_back(g);
  }
  if (!hasAlphaClasses()) return;
  alphaDraws = allocUninit<AlphaDraw>("scene.alphaDraws", a.size());
  Kokkos::View<const AlphaDraw*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>> h(a.data(), a.size());
  Kokkos::deep_copy(alphaDraws, h);
}

}  // namespace rast
