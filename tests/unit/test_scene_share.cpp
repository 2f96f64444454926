// Sort-last cuts a scene by geometry (host/distributed/scene_share.h): every
// drawn triangle, segment and point must land in exactly one rank's share, in
// the whole scene's order and in the same world position, so that global ids
// are a rank's ids plus its offset; and a camera list file's entries must be
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
      CHECK(sh[r].t1 - sh[r].t0 >= 10 / ranks);
      CHECK(sh[r].t1 - sh[r].t0 <= 10 / ranks + 1);
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
