// Scenes of many draws look a drawn triangle's or vertex's draw up in a table
// (DeviceScene::triDraw, vertDraw; kDrawTableMinDraws) instead of searching
// the draws' starts. The tables must name the draw the search names, and a
// frame drawn through them must equal one drawn through the search.
#include <catch2/catch.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

#include "host/scene/camera.h"
#include "pipeline/data/device_scene.h"
#include "pipeline/frame/renderer.h"
#include "tests/support/test_support.h"

using namespace rast;

namespace {

// `draws` draws in a grid of 8 columns, cycling over three primitives of 2, 7
// and 1 triangles, each draw with a material of its own colour.
Scene manyDraws(int draws) {
  Scene s;
  const std::vector<rast::float3> quad = {{-0.4f, -0.4f, 0}, {0.4f, -0.4f, 0}, {0.4f, 0.4f, 0}, {-0.4f, 0.4f, 0}};
  std::vector<rast::float3> fan = {{0, 0, 0}};
  std::vector<uint32_t> fanIdx;
  for (int k = 0; k < 8; ++k) {
    const float a = 6.2831853f * float(k) / 8.0f;
    fan.push_back({0.45f * std::cos(a), 0.45f * std::sin(a), 0});
  }
  for (uint32_t k = 1; k < 8; ++k) fanIdx.insert(fanIdx.end(), {0, k, k + 1});
  const std::vector<rast::float3> tri = {{-0.4f, -0.4f, 0}, {0.4f, -0.4f, 0}, {0.0f, 0.4f, 0}};
  for (int d = 0; d < draws; ++d) {
    Material m;
    m.baseColorFactor = rast::float4{float(d % 5) / 4.0f, float(d % 7) / 6.0f, float(d % 3) / 2.0f, 1.0f};
    s.materials.push_back(m);
  }
  std::vector<uint32_t> prims;
  prims.push_back(addPrim(s, quad, nullptr, nullptr, nullptr, {0, 1, 2, 0, 2, 3}, 0));
  prims.push_back(addPrim(s, fan, nullptr, nullptr, nullptr, fanIdx, 0));
  prims.push_back(addPrim(s, tri, nullptr, nullptr, nullptr, {0, 1, 2}, 0));
  for (int d = 0; d < draws; ++d) {
    // A primitive per material: the draw's colour comes from its own copy.
    const uint32_t base = prims[size_t(d % 3)];
    MeshPrim p = s.prims[base];
    p.material = d;
    s.prims.push_back(p);
    const glm::dmat4 model = glm::translate(glm::dmat4(1.0), glm::dvec3(d % 8, -(d / 8), 0));
    s.draws.push_back(Draw{uint32_t(s.prims.size() - 1), model});
  }
  s.validate();
  return s;
}

// The search's answer: the last draw whose start is at or before key.
uint32_t searched(const std::vector<uint32_t>& starts, uint32_t key) {
  return uint32_t(std::upper_bound(starts.begin(), starts.end(), key) - starts.begin()) - 1;
}

}  // namespace

TEST_CASE("draw tables name the draw the search names", "[draws]") {
  {
    const DeviceScene few = DeviceScene::upload(manyDraws(int(kDrawTableMinDraws)));
    CHECK(few.triDraw.data() == nullptr);  // few draws: no tables, the search
    CHECK(few.vertDraw.data() == nullptr);
  }
  const DeviceScene d = DeviceScene::upload(manyDraws(40));
  REQUIRE(d.numDraws == 40);
  REQUIRE(d.triDraw.extent(0) == d.numTris);
  REQUIRE(d.vertDraw.extent(0) == d.numVerts);
  const std::vector<DrawIndex> triDraw = test::download(d.triDraw), vertDraw = test::download(d.vertDraw);
  const std::vector<uint32_t> triStart = test::download(d.drawTriStart), vertStart = test::download(d.drawVertStart);
  size_t wrongTris = 0, wrongVerts = 0;
  for (uint32_t t = 0; t < d.numTris; ++t) wrongTris += triDraw[t] != searched(triStart, t);
  for (uint32_t v = 0; v < d.numVerts; ++v) wrongVerts += vertDraw[v] != searched(vertStart, v);
  CHECK(wrongTris == 0);
  CHECK(wrongVerts == 0);
  CHECK(triDraw.back() == 39);  // the last draw (one triangle) owns the last triangle
}

TEST_CASE("a frame drawn through the draw tables equals one drawn through the search", "[draws]") {
  // The first 16 draws alone take the search; with 24 more beside them, the
  // tables. Their pixels must not change.
  const Scene many = manyDraws(40), few = manyDraws(int(kDrawTableMinDraws));
  const Camera cam = defaultCamera(many);
  RenderSettings rs;
  rs.width = 320;
  rs.height = 200;
  rs.wantPrimId = rs.wantDepth = true;
  Renderer a(many), b(few);
  a.render(cam, rs);
  b.render(cam, rs);
  const std::vector<uint32_t> ia = a.primIdsBottomUp(), ib = b.primIdsBottomUp();
  const std::vector<float> za = a.depthBottomUp(), zb = b.depthBottomUp();
  const std::vector<uint32_t> ca = a.colorTopDown(), cb = b.colorTopDown();
  REQUIRE(ia.size() == ib.size());
  size_t fewPixels = 0, manyPixels = 0, differ = 0;
  for (size_t i = 0; i < ia.size(); ++i) {
    manyPixels += ia[i] != 0;
    if (ib[i] == 0) continue;
    ++fewPixels;
    differ += ia[i] != ib[i] || za[i] != zb[i];
  }
  // Colours: the same pixels, flipped vertically (colour is stored top-down).
  size_t colourDiffer = 0;
  for (int y = 0; y < rs.height; ++y)
    for (int x = 0; x < rs.width; ++x)
      if (ib[size_t(y) * rs.width + x] != 0) {
        const size_t top = size_t(rs.height - 1 - y) * rs.width + x;
        colourDiffer += ca[top] != cb[top];
      }
  CHECK(fewPixels > 1000);
  CHECK(manyPixels > fewPixels * 2);
  CHECK(differ == 0);
  CHECK(colourDiffer == 0);
}
