// The exact rasterisation rules: fill rule, watertightness, snapping, clipping.
//
// Coverage counts come from the same device functions the raster methods use
// (setupTriangle, Edges), evaluated on the host for every triangle, so a pixel
// covered twice or not at all is visible; the renderer's own output is then
// checked against the same counts. The rules behind the visbuffer raster's
// block skipping (depth bounds, occluders, work hints) are tested in
// test_raster_rules_blocks.cpp.
#include <catch2/catch.hpp>

#include "pipeline/rules/raster_rules.h"
#include "tests/support/test_support.h"

#include <algorithm>
#include <glm/gtc/matrix_transform.hpp>
#include <random>

using namespace rast;
using namespace rast::test;

namespace {

// Per-pixel coverage counts of a triangle list given in window coordinates.
std::vector<int> coverageCounts(const std::vector<double>& wx, const std::vector<double>& wy,
                                const std::vector<uint32_t>& idx, int W, int H) {
  std::vector<int> count(size_t(W) * H, 0);
  const Viewport vp{W, H, SamplePattern{}};
  for (size_t t = 0; t < idx.size(); t += 3) {
    ClipVert v[3];
    for (int k = 0; k < 3; ++k) {
      const rast::float3 n = windowToNdc(wx[idx[t + k]], wy[idx[t + k]], 0.0, W, H);
      v[k].p = rast::float4{n.x, n.y, n.z, 1.0f};
      v[k].b1 = v[k].b2 = 0.0f;
    }
    RasterTri rt;
    if (!setupTriangle(v[0], v[1], v[2], vp, false, true, uint32_t(t / 3), rt)) continue;
    const Edges e(rt);
    for (int y = rt.minY; y <= rt.maxY; ++y)
      for (int x = rt.minX; x <= rt.maxX; ++x)
        if (e.inside(e.eval(0, x, y), e.eval(1, x, y), e.eval(2, x, y))) ++count[size_t(y) * W + x];
  }
  return count;
}

Scene windowScene(const std::vector<double>& wx, const std::vector<double>& wy, const std::vector<uint32_t>& idx, int W,
                  int H) {
  std::vector<rast::float3> p;
  for (size_t i = 0; i < wx.size(); ++i) p.push_back(windowToNdc(wx[i], wy[i], 0.0, W, H));
  return trianglesScene(p, idx);
}

// A grid of (n+1)^2 vertices over [x0, x1] x [y0, y1], interior vertices jittered,
// two triangles per cell with alternating diagonals and alternating winding.
void grid(int n, double x0, double y0, double x1, double y1, double jitter, uint32_t seed, std::vector<double>& wx,
          std::vector<double>& wy, std::vector<uint32_t>& idx) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-jitter, jitter);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const bool border = i == 0 || j == 0 || i == n || j == n;
      wx.push_back(x0 + (x1 - x0) * i / n + (border ? 0.0 : U(rng)));
      wy.push_back(y0 + (y1 - y0) * j / n + (border ? 0.0 : U(rng)));
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      if ((i + j) & 1) idx.insert(idx.end(), {a, b, d, a, d, c});
      else idx.insert(idx.end(), {a, b, c, b, d, c});
      if (i % 3 == 0) std::swap(idx[idx.size() - 1], idx[idx.size() - 2]);  // clockwise too
    }
}

// Pixel centres inside an axis-aligned rectangle, by the top-left rule: on the
// left border and on the border that is on top in the image (y0: window y is
// up, images are stored top row first) they belong to it, on the others not.
int expectedInRect(int x, int y, double x0, double y0, double x1, double y1) {
  const double cx = x + 0.5, cy = y + 0.5;
  return (cx >= x0 && cx < x1 && cy >= y0 && cy < y1) ? 1 : 0;
}

}  // namespace

TEST_CASE("shared edges cover every pixel exactly once (grid, jittered, sub-pixel offsets)", "[raster][fillrule]") {
  const int W = 96, H = 80;
  for (uint32_t seed = 1; seed <= 6; ++seed) {
    // Offsets land the border on pixel centres (.5) and on arbitrary sub-pixel positions.
    const double off = seed % 2 ? 0.5 : 0.3 + 0.01 * seed;
    std::vector<double> wx, wy;
    std::vector<uint32_t> idx;
    grid(12, 8 + off, 6 + off, 88 + off, 74 + off, seed < 3 ? 0.0 : 1.3, seed, wx, wy, idx);
    const auto count = coverageCounts(wx, wy, idx, W, H);
    int twice = 0, holes = 0;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        const int c = count[size_t(y) * W + x];
        const int want = expectedInRect(x, y, 8 + off, 6 + off, 88 + off, 74 + off);
        if (c > 1) ++twice;
        if (want && c == 0) ++holes;
        INFO("seed " << seed << " pixel " << x << "," << y);
        REQUIRE(c <= 1);
        REQUIRE(c == want);
      }
    CHECK(twice == 0);
    CHECK(holes == 0);
  }
}

TEST_CASE("a fan around a vertex on a pixel centre covers each pixel once", "[raster][fillrule]") {
  const int W = 64, H = 64;
  std::vector<double> wx = {32.5, 32.5 + 20.0}, wy = {32.5, 32.5};
  std::vector<uint32_t> idx;
  const int n = 16;  // spokes at 22.5 degrees; 0, 90, 180, 270 lie on pixel-centre lines
  for (int k = 1; k < n; ++k) {
    const double a = 2.0 * M_PI * k / n;
    wx.push_back(32.5 + 20.0 * std::cos(a));
    wy.push_back(32.5 + 20.0 * std::sin(a));
  }
  for (int k = 0; k < n; ++k) idx.insert(idx.end(), {0u, uint32_t(1 + k), uint32_t(1 + (k + 1) % n)});
  const auto count = coverageCounts(wx, wy, idx, W, H);
  int covered = 0;
  for (int c : count) {
    REQUIRE(c <= 1);
    covered += c;
  }
  // The centre pixel (whose centre is the shared vertex) belongs to exactly one triangle.
  CHECK(count[32 * W + 32] == 1);
  CHECK(covered > 1000);  // the 16-gon of radius 20 has area ~1225 pixels
}

TEST_CASE("the top-left rule decides pixel centres exactly on edges", "[raster][fillrule]") {
  const int W = 16, H = 16;
  // Axis-aligned square with all four edges on pixel-centre lines: x in [2.5, 6.5], y in [2.5, 6.5].
  std::vector<double> wx = {2.5, 6.5, 6.5, 2.5}, wy = {2.5, 2.5, 6.5, 6.5};
  std::vector<uint32_t> idx = {0, 1, 2, 0, 2, 3};
  const auto count = coverageCounts(wx, wy, idx, W, H);
  // Left edge x=2.5 included (columns 2..5), right edge x=6.5 excluded. Window
  // y is up and images are stored top row first, so the edge y=2.5 is the top
  // one in the image: included (rows 2..5); y=6.5 excluded.
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const int want = (x >= 2 && x <= 5 && y >= 2 && y <= 5) ? 1 : 0;
      INFO("pixel " << x << "," << y);
      REQUIRE(count[size_t(y) * W + x] == want);
    }
}

TEST_CASE("vertices snap to 1/256 pixel before coverage is decided", "[raster][snap]") {
  const int W = 32, H = 32;
  // A left edge at x = 10.5 + 1/1024 px: unsnapped, the centres at x = 10.5 lie
  // left of it (outside); snapped to 8 sub-pixel bits the edge passes exactly
  // through them, and the left-edge rule covers them.
  const double eps = 1.0 / 1024.0;
  std::vector<double> wx = {10.5 + eps, 20.0, 10.5 + eps}, wy = {2.0, 2.0, 30.0};
  std::vector<uint32_t> idx = {0, 1, 2};
  const auto count = coverageCounts(wx, wy, idx, W, H);
  for (int y = 3; y < 29; ++y) REQUIRE(count[size_t(y) * W + 10] == 1);
  // And a displacement below half a sub-pixel step changes nothing at all.
  std::vector<double> wx2 = {10.5 + 1.0 / 1024.0, 20.0 - 1.0 / 2048.0, 10.5 - 1.0 / 4096.0};
  CHECK(coverageCounts(wx2, wy, idx, W, H) == count);
}

TEST_CASE("the renderer's coverage and ids equal the rule-level coverage", "[raster][fillrule]") {
  const int W = 96, H = 80;
  std::vector<double> wx, wy;
  std::vector<uint32_t> idx;
  grid(9, 4.3, 3.7, 91.1, 77.9, 2.0, 42, wx, wy, idx);
  const auto count = coverageCounts(wx, wy, idx, W, H);
  const Scene s = windowScene(wx, wy, idx, W, H);
  RenderSettings rs;
  rs.width = W;
  rs.height = H;
  for (RasterMethod m : allRasterMethods()) {
    rs.raster = m;
    const Frame f = renderFrame(s, identityCamera(), rs);
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        const uint32_t id = f.id(x, y);
        REQUIRE((id != 0) == (count[size_t(y) * W + x] == 1));
        if (id) {  // the winner covers the pixel by itself
          const auto one = coverageCounts(wx, wy, {idx[3 * (id - 1)], idx[3 * (id - 1) + 1], idx[3 * (id - 1) + 2]}, W, H);
          REQUIRE(one[size_t(y) * W + x] == 1);
        }
      }
  }
}

TEST_CASE("narrow triangles with edges through pixel centres: every method's ids follow the fill rule", "[raster][fillrule]") {
  // Cells of 3 to 5 pixels with vertices on pixel centres, so that many pixel
  // centres lie exactly on edges (the top-left rule decides them), on
  // triangles narrow enough for the host binned raster's coverage masks
  // (depthBox) as well as wider ones.
  const int W = 96, H = 80;
  for (const double cell : {3.0, 4.0, 5.0}) {
    std::vector<double> wx, wy;
    std::vector<uint32_t> idx;
    const int n = int(88.0 / cell);
    grid(n, 2.5, 1.5, 2.5 + cell * n, 1.5 + cell * n * 0.85, 0.0, 7, wx, wy, idx);
    const auto count = coverageCounts(wx, wy, idx, W, H);
    const Scene s = windowScene(wx, wy, idx, W, H);
    RenderSettings rs;
    rs.width = W;
    rs.height = H;
    for (RasterMethod m : allRasterMethods()) {
      rs.raster = m;
      const Frame f = renderFrame(s, identityCamera(), rs);
      INFO("cell " << cell << ", " << toString(m));
      int covered = 0;
      for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
          const uint32_t id = f.id(x, y);
          REQUIRE((id != 0) == (count[size_t(y) * W + x] == 1));
          covered += id != 0;
          if (id) {
            const auto one = coverageCounts(wx, wy, {idx[3 * (id - 1)], idx[3 * (id - 1) + 1], idx[3 * (id - 1) + 2]}, W, H);
            REQUIRE(one[size_t(y) * W + x] == 1);
          }
        }
      CHECK(covered > W * H / 2);
    }
  }
}

namespace {

// Host ray cast: does the ray through pixel centre (x, y) hit triangle abc
// (world space) in front of the camera, between near and far?
bool rayHits(const Camera& c, int W, int H, int x, int y, glm::dvec3 a, glm::dvec3 b, glm::dvec3 cc) {
  const glm::dmat4 inv = glm::inverse(c.projection(W, H) * c.view());
  const double nx = (x + 0.5) / W * 2 - 1, ny = (y + 0.5) / H * 2 - 1;
  glm::dvec4 p0 = inv * glm::dvec4(nx, ny, -1, 1), p1 = inv * glm::dvec4(nx, ny, 1, 1);
  const glm::dvec3 o = glm::dvec3(p0) / p0.w, e = glm::dvec3(p1) / p1.w, d = e - o;
  // Moller-Trumbore, t in [0, 1] along near -> far.
  const glm::dvec3 e1 = b - a, e2 = cc - a, pv = glm::cross(d, e2);
  const double det = glm::dot(e1, pv);
  if (std::abs(det) < 1e-300) return false;
  const glm::dvec3 tv = o - a;
  const double u = glm::dot(tv, pv) / det;
  const glm::dvec3 qv = glm::cross(tv, e1);
  const double v = glm::dot(d, qv) / det, t = glm::dot(e2, qv) / det;
  return u >= 0 && v >= 0 && u + v <= 1 && t >= 0 && t <= 1;
}

}  // namespace

TEST_CASE("a triangle crossing the near plane renders exactly its visible part", "[raster][clip]") {
  const int W = 160, H = 120;
  // A floor triangle with one corner far behind the camera: clipped to a quad.
  const glm::dvec3 a(-6, -1, 4), b(6, -1, -30), c(-8, -1, -30);
  const Scene s = trianglesScene({{float(a.x), float(a.y), float(a.z)}, {float(b.x), float(b.y), float(b.z)},
                                  {float(c.x), float(c.y), float(c.z)}},
                                 {0, 1, 2});
  Camera cam;
  cam.eye = {0, 0, 0};
  cam.target = {0, -0.2, -1};
  cam.znear = 0.5;
  cam.zfar = 100;
  RenderSettings rs;
  rs.width = W;
  rs.height = H;
  const Frame f = renderFrame(s, cam, rs);
  CHECK(f.stats.rasterTris >= 2);  // the clipped quad is two raster triangles
  int covered = 0, mismatch = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const bool want = rayHits(cam, W, H, x, y, a, b, c);
      const bool got = f.id(x, y) == 1;
      covered += got;
      if (want != got) ++mismatch;
    }
  // Disagreement only where a pixel centre is within rounding of an edge.
  CHECK(covered > W * H / 20);
  CHECK(mismatch <= 3);
}

TEST_CASE("a triangle behind the camera renders nothing", "[raster][clip]") {
  const Scene s = trianglesScene({{-1, -1, 5}, {1, -1, 5}, {0, 1, 5}}, {0, 1, 2});
  Camera cam;
  cam.eye = {0, 0, 0};
  cam.target = {0, 0, -1};
  RenderSettings rs;
  rs.width = 64;
  rs.height = 48;
  const Frame f = renderFrame(s, cam, rs);
  CHECK(f.stats.rasterTris == 0);
  for (uint32_t id : f.ids) REQUIRE(id == 0);
}

// The setup skips clipping a triangle that lies beyond one side of the
// viewport (outsideViewportSide in clip.h): clipping it would leave pieces
// that cover no pixel centre. The test is on the viewport's own planes, not
// the guard band's, in clip space, behind the camera too.
TEST_CASE("triangles beyond a side of the viewport are skipped before clipping, and only those", "[raster][clip]") {
  using rast::float4;
  // Beyond each side: x > w, x < -w, y > w, y < -w at all three corners,
  // one corner behind the camera (w < 0), as a triangle crossing the near
  // plane at the side of the view is.
  CHECK(outsideViewportSide(float4{2, 0, 0, 1}, float4{3, 1, 0, 2}, float4{1, 0, 0, -1}));
  CHECK(outsideViewportSide(float4{-2, 0, 0, 1}, float4{-3, 1, 0, 2}, float4{-1, 0, 0, -1}));
  CHECK(outsideViewportSide(float4{0, 2, 0, 1}, float4{1, 3, 0, 2}, float4{0, 1, 0, -1}));
  CHECK(outsideViewportSide(float4{0, -2, 0, 1}, float4{1, -3, 0, 2}, float4{0, -1, 0, -1}));
  // Not beyond: one corner inside, a corner on the plane itself (x/w = 1 is
  // the viewport's edge), or beyond two different sides.
  CHECK_FALSE(outsideViewportSide(float4{2, 0, 0, 1}, float4{3, 1, 0, 2}, float4{0.5f, 0, 0, 1}));
  CHECK_FALSE(outsideViewportSide(float4{2, 0, 0, 1}, float4{3, 1, 0, 2}, float4{1, 0, 0, 1}));
  CHECK_FALSE(outsideViewportSide(float4{2, 0, 0, 1}, float4{0, 2, 0, 1}, float4{-2, 0, 0, 1}));
  // In a frame: triangles crossing the near plane, one beyond the right edge
  // of the view (skipped: draws nothing) and one across it (clipped: draws
  // its visible part, as many pixels as with the skip left out would).
  Camera cam;
  cam.eye = {0, 0, 0};
  cam.target = {0, 0, -1};
  cam.znear = 0.5;
  cam.zfar = 100;
  RenderSettings rs;
  rs.width = 96;
  rs.height = 64;
  for (RasterMethod m : allRasterMethods()) {
    rs.raster = m;
    INFO(toString(m));
    const Frame beyond = renderFrame(trianglesScene({{3, -1, -2}, {4, 1, -2}, {3, 0, 2}}, {0, 1, 2}), cam, rs);
    CHECK(beyond.stats.rasterTris == 0);
    for (uint32_t id : beyond.ids) REQUIRE(id == 0);
    const Frame across = renderFrame(trianglesScene({{-0.2f, -1, -2}, {4, 1, -2}, {0.5f, 0, 2}}, {0, 1, 2}), cam, rs);
    CHECK(across.stats.rasterTris >= 1);
    int covered = 0;
    for (uint32_t id : across.ids) covered += id == 1;
    CHECK(covered > 200);
  }
}

TEST_CASE("edge values from 32-bit factors equal the 64-bit edge functions at the coordinate limits and sample offsets", "[raster][edges]") {
  // On GPUs Edges::eval multiplies 32-bit factors (a widening multiply,
  // Edges::factorEval); the setup keeps snapped vertices within
  // +-kMaxWindowCoord pixels and pixel coordinates lie below
  // kMaxFramebufferSide. At those limits and at random points in between,
  // both forms must equal A X + B Y + C exactly.
  const int32_t lim = kMaxWindowCoord * kSubOne - 1;
  const int32_t side = kMaxFramebufferSide - 1;
  std::mt19937 rng(7);
  std::uniform_int_distribution<int32_t> coord(-lim, lim), pixel(0, side);
  const int32_t corners[2] = {-lim, lim};
  for (int n = 0; n < 2000; ++n) {
    RasterTri t{};
    for (int k = 0; k < 3; ++k) {
      // The first 64 triangles take only the extremes; the rest random points.
      t.x[k] = n < 64 ? corners[(n >> k) & 1] : coord(rng);
      t.y[k] = n < 64 ? corners[(n >> (k + 3)) & 1] : coord(rng);
    }
    const Edges e(t);
    const int32_t xs[4] = {0, side, pixel(rng), pixel(rng)}, ys[4] = {0, side, pixel(rng), pixel(rng)};
    for (int i = 0; i < 3; ++i)
      for (int32_t X : xs)
        for (int32_t Y : ys) {
          const int64_t plane = e.A[i] * X + e.B[i] * Y + e.C[i];
          REQUIRE(Edges::factorEval(t, i, X, Y) == plane);
          REQUIRE(e.eval(i, X, Y) == plane);
          // At a sample's offset (and the derivatives' neighbours, a pixel
          // further): the factors with the offset folded in, and the offset's
          // step from the factors (atSample's and sample's GPU forms), equal
          // the 64-bit coefficients' A/256 and B/256 steps (the extremes and
          // every eighth random triangle).
          if (n >= 64 && n % 8 != 0) continue;
          const Edges::Factors g = Edges::factorsOf(t);
          for (int32_t ox : {-2 * kSubOne, -kSubHalf, -37, 0, 91, kSubOne + kSubHalf})
            for (int32_t oy : {-kSubOne - kSubHalf, -5, 0, kSubHalf, 2 * kSubOne}) {
              const int64_t at = plane + (e.A[i] / kSubOne) * ox + (e.B[i] / kSubOne) * oy;
              REQUIRE(g.sample(i, X, Y, ox, oy) == at);
              REQUIRE(plane + e.offsetWith(g, i, ox, oy) == at);
              REQUIRE(e.sample(i, X, Y, ox, oy) == at);
              REQUIRE(e.atSample(i, plane, ox, oy) == at);
            }
        }
  }
}

TEST_CASE("huge coordinates do not overflow the fixed-point setup", "[raster][clip]") {
  // One triangle far larger than the guard band, around the view direction.
  const Scene s = trianglesScene({{-1e6f, -1e6f, -10}, {1e6f, -1e6f, -10}, {0, 1e6f, -10}}, {0, 1, 2});
  Camera cam;
  cam.eye = {0, 0, 0};
  cam.target = {0, 0, -1};
  RenderSettings rs;
  rs.width = 128;
  rs.height = 96;
  for (RasterMethod m : allRasterMethods()) {
    rs.raster = m;
    const Frame f = renderFrame(s, cam, rs);
    for (uint32_t id : f.ids) REQUIRE(id == 1);
    // The depth of a plane facing the camera is the same everywhere.
    for (float d : f.depth) REQUIRE(d == Approx(f.depth[0]).margin(1e-6));
  }
}

TEST_CASE("non-finite and degenerate triangles are dropped, the rest still drawn", "[raster][clip]") {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::nanf("");
  const int W = 64, H = 64;
  std::vector<rast::float3> p = {windowToNdc(4, 4, 0, W, H),   windowToNdc(60, 4, 0, W, H), windowToNdc(32, 60, 0, W, H),
                           {inf, 0, 0},                   {nan, 0, 0},                 {0, 0, 0},
                           windowToNdc(10, 10, 0, W, H), windowToNdc(20, 20, 0, W, H), windowToNdc(30, 30, 0, W, H)};
  Scene s;
  s.materials.push_back(Material{});
  // Positions go in unchecked here (the loader rejects non-finite files; the
  // pipeline must still survive them from procedural or streamed geometry).
  s.positions = p;
  s.normals.assign(p.size(), rast::float3{0, 0, 1});
  s.indices = {3, 4, 5, 6, 7, 8, 0, 1, 2, 0, 0, 1};
  s.prims.push_back(MeshPrim{0, uint32_t(p.size()), 0, 4, 0});
  s.draws.push_back(Draw{0, glm::dmat4(1.0)});
  RenderSettings rs;
  rs.width = W;
  rs.height = H;
  const Frame f = renderFrame(s, identityCamera(), rs);
  CHECK(f.stats.rasterTris == 1);
  int covered = 0;
  for (uint32_t id : f.ids) {
    REQUIRE((id == 0 || id == 3));
    covered += id == 3;
  }
  CHECK(covered > 1000);
}
