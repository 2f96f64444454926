// rast-tangent-dump: the tangents rast's loader keeps for a glTF file (the
// file's TANGENT or generated, host/scene/tangents.h), with the vertices they
// belong to, as JSON on stdout, for scripts/measure/tangent_agreement.py to
// hold against MikkTSpace (the Khronos Sample Renderer's generator).
//
//   rast-tangent-dump SCENE.gltf|glb
//
// One entry per primitive that has tangents: positions, normals, texture
// coordinates (the normal texture's set, its transform applied), triangle
// indices (local to the primitive) and tangents (x, y, z, w). Exit 2 on bad input.
#include "host/gltf/gltf_loader.h"

#include <cstdio>
#include <exception>
#include <string>

using namespace rast;

namespace {

template <class F>
void list(const char* name, uint32_t n, F item, bool last = false) {
  std::printf("\"%s\":[", name);
  for (uint32_t i = 0; i < n; ++i) {
    if (i) std::printf(",");
    item(i);
  }
  std::printf("]%s", last ? "" : ",");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: rast-tangent-dump SCENE\n");
    return 2;
  }
  try {
    const Scene s = loadGltf(argv[1]);
    std::printf("{\"prims\":[");
    bool first = true;
    for (const MeshPrim& p : s.prims) {
      if (s.tangents.empty() || p.triCount == 0) continue;
      bool any = false;
      for (uint32_t v = 0; v < p.vertexCount; ++v) any |= s.tangents[p.firstVertex + v].w != 0.0f;
      if (!any) continue;
      std::printf("%s{", first ? "" : ",");
      first = false;
      const uint32_t v0 = p.firstVertex;
      list("positions", p.vertexCount, [&](uint32_t i) {
        const rast::float3 q = s.positions[v0 + i];
        std::printf("%.9g,%.9g,%.9g", q.x, q.y, q.z);
      });
      list("normals", p.vertexCount, [&](uint32_t i) {
        const rast::float3 q = s.normals[v0 + i];
        std::printf("%.9g,%.9g,%.9g", q.x, q.y, q.z);
      });
      list("uvs", p.vertexCount, [&](uint32_t i) {
        const rast::float2 q = s.uvs[v0 + i];
        std::printf("%.9g,%.9g", q.x, q.y);
      });
      list("indices", 3 * p.triCount, [&](uint32_t i) { std::printf("%u", s.indices[3 * size_t(p.firstTri) + i]); });
      list("tangents", p.vertexCount, [&](uint32_t i) {
        const rast::float4 q = s.tangents[v0 + i];
        std::printf("%.9g,%.9g,%.9g,%.9g", q.x, q.y, q.z, q.w);
      }, true);
      std::printf("}");
    }
    std::printf("]}\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rast-tangent-dump: %s\n", e.what());
    return 2;
  }
  return 0;
}
