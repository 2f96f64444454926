// Sort-last cuts a scene by geometry (host/distributed/scene_share.h): every
// drawn triangle, segment and point must land in exactly one rank's share, in
// the whole scene's order and in the same world position, so that global ids
// are a rank's ids plus its offset; the first share keeps glTF BLEND draws
// whole, the triangles it adds numbered after its range and mapped to global
// ids by its runs (rank 0 composites BLEND surfaces); and a camera list file's entries must be
// the cameras their keys say (host/scene/camera_list.h).
#include <catch2/catch.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

#include "host/distributed/scene_share.h"
#include "host/scene/camera_list.h"

using namespace rast;

namespace {

// Two draws of one 5-triangle fan, a line strip's 3 segments and 2 points.
Scene mixedScene() {
  Scene s;
  std::vector<rast::float3> fan = {{0, 0, 0}};
  std::vector<uint32_t> idx;
  for (int k = 0; k < 6; ++k) fan.push_back({float(k), 1.0f + float(k % 2), 0});
  for (uint32_t k = 0; k < 5; ++k) idx.insert(idx.end(), {0, k + 1, k + 2});
  const uint32_t tri = addPrim(s, fan, nullptr, nullptr, nullptr, idx, -1);
  const std::vector<rast::float3> pts = {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  const uint32_t lines = addLinePrim(s, pts, nullptr, {0, 1, 1, 2, 2, 3}, {}, -1);
  const uint32_t points = addLinePrim(s, pts, nullptr, {}, {3, 0}, -1);
  s.draws.push_back(Draw{tri, glm::dmat4(1.0)});
  s.draws.push_back(Draw{lines, glm::dmat4(1.0)});
  s.draws.push_back(Draw{tri, glm::translate(glm::dmat4(1.0), glm::dvec3(10, 0, 0))});
  s.draws.push_back(Draw{points, glm::dmat4(1.0)});
  return s;
}

// World positions of every drawn triangle (3), segment (2) or point (1), in order.
std::vector<glm::dvec3> drawn(const Scene& s, int kind) {
  std::vector<glm::dvec3> out;
  for (const Draw& d : s.draws) {
    const MeshPrim& p = s.prims[d.prim];
    const auto at = [&](uint32_t v) {
      const rast::float3 q = s.positions[p.firstVertex + v];
      return glm::dvec3(d.model * glm::dvec4(q.x, q.y, q.z, 1.0));
    };
    if (kind == 0)
      for (uint32_t i = 3 * p.firstTri; i < 3 * (p.firstTri + p.triCount); ++i) out.push_back(at(s.indices[i]));
    if (kind == 1)
      for (uint32_t i = 2 * p.firstLine; i < 2 * (p.firstLine + p.lineCount); ++i) out.push_back(at(s.lineIndices[i]));
    if (kind == 2)
      for (uint32_t i = p.firstPoint; i < p.firstPoint + p.pointCount; ++i) out.push_back(at(s.pointIndices[i]));
  }
  return out;
}

}  // namespace

TEST_CASE("shares are contiguous, balanced and cover everything once", "[distributed]") {
  for (int ranks : {1, 2, 3, 4, 7}) {
    const auto sh = planShares(10, 3, 0, ranks);
    REQUIRE(sh.size() == size_t(ranks));
    CHECK(sh.front().t0 == 0);
    CHECK(sh.back().t1 == 10);
    CHECK(sh.back().l1 == 3);
    for (int r = 0; r < ranks; ++r) {
      CHECK(sh[r].t1 - sh[r].t0 >= uint64_t(10 / ranks));
      CHECK(sh[r].t1 - sh[r].t0 <= uint64_t(10 / ranks + 1));
      if (r > 0) CHECK(sh[r].t0 == sh[r - 1].t1);
      if (r > 0) CHECK(sh[r].l0 == sh[r - 1].l1);
    }
  }
}

TEST_CASE("a scene's shares draw its primitives in order, in place, once", "[distributed]") {
  const Scene full = mixedScene();
  REQUIRE(full.triangleCount() == 10);
  for (int ranks : {1, 2, 3, 4, 6, 12}) {
    const auto sh = planShares(full.triangleCount(), full.lineCount(), full.pointCount(), ranks);
    std::vector<glm::dvec3> tris, lines, points;
    for (int r = 0; r < ranks; ++r) {
      const Scene part = takeShare(full, sh[size_t(r)]);
      REQUIRE_NOTHROW(part.validate());
      CHECK(part.triangleCount() == sh[size_t(r)].t1 - sh[size_t(r)].t0);
      CHECK(part.lineCount() == sh[size_t(r)].l1 - sh[size_t(r)].l0);
      CHECK(part.pointCount() == sh[size_t(r)].p1 - sh[size_t(r)].p0);
      for (int k = 0; k < 3; ++k) {
        const auto d = drawn(part, k);
        (k == 0 ? tris : k == 1 ? lines : points).insert((k == 0 ? tris : k == 1 ? lines : points).end(), d.begin(), d.end());
      }
    }
    CHECK(tris == drawn(full, 0));
    CHECK(lines == drawn(full, 1));
    CHECK(points == drawn(full, 2));
  }
  // Drawn whole, a primitive used by two draws is stored once in the share.
  const Scene whole = takeShare(full, planShares(10, 3, 2, 1)[0]);
  CHECK(whole.prims.size() == 3);
  CHECK(whole.draws.size() == 4);
}

TEST_CASE("the first share keeps BLEND draws whole and maps its added triangles to global ids", "[distributed]") {
  // Opaque fan (5), BLEND fan (5, with a vertex no triangle uses), opaque fan again, BLEND fan again, lines.
  Scene full = mixedScene();
  Material blend;
  blend.alphaMode = AlphaMode::Blend;
  full.materials.push_back(blend);
  std::vector<rast::float3> fan = {{0, 0, 2}, {9, 9, 9}};
  std::vector<uint32_t> idx;
  for (int k = 0; k < 6; ++k) fan.push_back({float(k), 1.0f + float(k % 3), 2});
  for (uint32_t k = 0; k < 5; ++k) idx.insert(idx.end(), {0, k + 2, k + 3});
  const std::vector<rast::float3> up(fan.size(), rast::float3{0, 0, 1});  // with normals: the vertices as given
  const uint32_t glass = addPrim(full, fan, &up, nullptr, nullptr, idx, 0);
  full.draws.insert(full.draws.begin() + 1, Draw{glass, glm::dmat4(1.0)});
  full.draws.push_back(Draw{glass, glm::translate(glm::dmat4(1.0), glm::dvec3(0, 5, 0))});
  REQUIRE(full.triangleCount() == 20);
  CHECK(drawsBlend(full));
  CHECK(!drawsBlend(mixedScene()));
  const std::vector<glm::dvec3> all = drawn(full, 0);
  for (int ranks : {2, 3, 4, 7}) {
    const auto sh = planShares(full.triangleCount(), full.lineCount(), full.pointCount(), ranks);
    std::vector<TriRun> runs;
    const Scene first = takeShare(full, sh[0], &runs);
    REQUIRE_NOTHROW(first.validate());
    const std::vector<glm::dvec3> mine = drawn(first, 0);
    // Its range in place, then the added BLEND triangles, in order, where the runs say.
    const uint64_t Tr = sh[0].t1;
    uint64_t local = Tr, blendTris = 0;
    for (uint64_t t = 0; t < Tr; ++t)
      for (int c = 0; c < 3; ++c) CHECK(mine[3 * t + c] == all[3 * t + c]);
    for (const TriRun& r : runs) {
      CHECK(r.local == local);
      CHECK(r.global >= Tr);
      for (uint64_t k = 0; k < r.count; ++k)
        for (int c = 0; c < 3; ++c) CHECK(mine[3 * (r.local + k) + c] == all[3 * (r.global + k) + c]);
      local += r.count;
    }
    CHECK(local == first.triangleCount());
    // Every BLEND triangle is there (10), with all of its primitive's vertices (the centre's box).
    for (const Draw& d : first.draws)
      if (isBlendDraw(first, d)) {
        blendTris += first.prims[d.prim].triCount;
        CHECK(first.prims[d.prim].vertexCount == 8);
      }
    CHECK(blendTris == 10);
    CHECK(first.lineCount() == sh[0].l1 - sh[0].l0);
    // The other shares are cut as without BLEND.
    CHECK(takeShare(full, sh[1]).triangleCount() == sh[1].t1 - sh[1].t0);
  }
  std::vector<TriRun> runs;
  CHECK_THROWS_AS(takeShare(full, planShares(20, 3, 2, 2)[1], &runs), Error);
}

TEST_CASE("camera lists: flag keys, defaults from the base camera, NeRF frames", "[distributed]") {
  Camera base;
  base.eye = {0, 0, 5};
  base.fovyDeg = 30;
  const auto cams = parseCameraList(R"([{"eye": [1, 2, 3]}, {"target": [0, 1, 0], "fovy": 50, "near": 0.5, "far": 9}])",
                                    "t.json", base, 200, 100);
  REQUIRE(cams.size() == 2);
  CHECK(cams[0].eye == glm::dvec3(1, 2, 3));
  CHECK(cams[0].fovyDeg == 30);
  CHECK(cams[1].eye == glm::dvec3(0, 0, 5));
  CHECK(cams[1].target == glm::dvec3(0, 1, 0));
  CHECK(cams[1].znear == 0.5);
  CHECK(cams[1].zfar == 9);
  const auto nerf = parseCameraList(
      R"({"camera_angle_x": 1.0, "frames": [{"transform_matrix": [[1,0,0,1],[0,1,0,2],[0,0,1,3],[0,0,0,1]]}]})", "n.json",
      base, 200, 100);
  REQUIRE(nerf.size() == 1);
  CHECK(nerf[0].eye == glm::dvec3(1, 2, 3));
  CHECK(nerf[0].target.z < 3.0);
  CHECK(nerf[0].up == glm::dvec3(0, 1, 0));
  CHECK(std::abs(nerf[0].fovyDeg - glm::degrees(2.0 * std::atan(std::tan(0.5) * 0.5))) < 1e-9);
  CHECK_THROWS_WITH(parseCameraList("[{\"eye\": 1}]", "b.json", base, 8, 8), Catch::Contains("'eye'"));
}
