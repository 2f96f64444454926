// Points and lines (docs/points-lines.md): OpenGL's non-antialiased rules
// checked pixel for pixel against hand-computed tables, through the whole
// renderer; LINE_LOOP vertices lit exactly once; near-plane clipping keeps the
// visible part; depth testing against triangles under every raster method;
// the loader's expansion of loops and strips; the primitive id numbering; and
// glTF's Mesh_PrimitiveMode files.
#include <catch2/catch.hpp>

#include "host/gltf/gltf_loader.h"
#include "pipeline/raster/raster_lines.h"
#include "scenes/gltf_export.h"
#include "scenes/stress_scenes.h"
#include "tests/support/test_support.h"

#include <cstdio>
#include <fstream>
#include <map>
#include <random>
#include <set>

using namespace rast;
using namespace rast::test;

namespace {

using Pixels = std::set<std::pair<int, int>>;

// A scene of line segments and points given in window coordinates (identity
// camera: positions are NDC), plus optional triangles.
struct WindowScene {
  int W, H;
  std::vector<rast::float3> pos;
  std::vector<uint32_t> seg, pts;
  Scene build() const {
    Scene s;
    s.name = "test";
    s.materials.push_back(Material{});
    s.draws.push_back(Draw{addLinePrim(s, pos, nullptr, seg, pts, 0), glm::dmat4(1.0)});
    return s;
  }
  uint32_t vertex(double x, double y, double z = 0.0) {
    pos.push_back(windowToNdc(x, y, z, W, H));
    return uint32_t(pos.size() - 1);
  }
  void line(double x0, double y0, double x1, double y1, double z = 0.0) {
    seg.push_back(vertex(x0, y0, z));
    seg.push_back(vertex(x1, y1, z));
  }
  void point(double x, double y, double z = 0.0) { pts.push_back(vertex(x, y, z)); }
};

Pixels litPixels(const Frame& f) {
  Pixels p;
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x)
      if (f.id(x, y)) p.insert({x, y});
  return p;
}

Frame renderWindow(const Scene& s, int W, int H, RenderSettings rs = RenderSettings{}) {
  rs.width = W;
  rs.height = H;
  return renderFrame(s, identityCamera(), rs);
}

std::string show(const Pixels& p) {
  std::string out;
  for (const auto& q : p) out += "(" + std::to_string(q.first) + "," + std::to_string(q.second) + ")";
  return out;
}

}  // namespace

TEST_CASE("width-1 lines from pixel centre to pixel centre light the diamond-exit pixels", "[lines]") {
  // Hand-computed: for an x-major line the pixel of column X is the row whose
  // diamond the line crosses at the column centre X + 0.5 (on a diamond corner,
  // the row below); the start pixel is lit, the end pixel (the line ends in its
  // diamond) is not. y-major lines likewise with rows and columns swapped (on a
  // corner, the column to the left).
  struct Case {
    int x0, y0, x1, y1;
    Pixels expect;
  };
  const std::vector<Case> cases = {
      {1, 2, 6, 2, {{1, 2}, {2, 2}, {3, 2}, {4, 2}, {5, 2}}},                  // horizontal, right
      {6, 2, 1, 2, {{6, 2}, {5, 2}, {4, 2}, {3, 2}, {2, 2}}},                  // horizontal, left
      {3, 1, 3, 5, {{3, 1}, {3, 2}, {3, 3}, {3, 4}}},                          // vertical, up
      {3, 5, 3, 1, {{3, 5}, {3, 4}, {3, 3}, {3, 2}}},                          // vertical, down
      {1, 1, 5, 5, {{1, 1}, {2, 2}, {3, 3}, {4, 4}}},                          // exact diagonal
      {5, 5, 1, 1, {{5, 5}, {4, 4}, {3, 3}, {2, 2}}},                          // exact diagonal, reversed
      {1, 5, 5, 1, {{1, 5}, {2, 4}, {3, 3}, {4, 2}}},                          // anti-diagonal
      {5, 1, 1, 5, {{5, 1}, {4, 2}, {3, 3}, {2, 4}}},                          // anti-diagonal, reversed
      {1, 1, 7, 4, {{1, 1}, {2, 1}, {3, 2}, {4, 2}, {5, 3}, {6, 3}}},          // slope 1/2 (corners at x=2,4,6)
      {7, 4, 1, 1, {{7, 4}, {6, 3}, {5, 3}, {4, 2}, {3, 2}, {2, 1}}},          // slope 1/2, reversed
      {0, 0, 6, 2, {{0, 0}, {1, 0}, {2, 1}, {3, 1}, {4, 1}, {5, 2}}},          // slope 1/3
      {2, 1, 4, 5, {{2, 1}, {2, 2}, {3, 3}, {3, 4}}},                          // slope 2 (y-major, corners at y=2,4)
      {4, 5, 2, 1, {{4, 5}, {3, 4}, {3, 3}, {2, 2}}},                          // slope 2, reversed
  };
  for (const Case& c : cases) {
    WindowScene ws{12, 8, {}, {}, {}};
    ws.line(c.x0 + 0.5, c.y0 + 0.5, c.x1 + 0.5, c.y1 + 0.5);
    const Frame f = renderWindow(ws.build(), ws.W, ws.H);
    INFO("line (" << c.x0 << "," << c.y0 << ") -> (" << c.x1 << "," << c.y1 << "): got " << show(litPixels(f))
                  << ", expected " << show(c.expect));
    CHECK(litPixels(f) == c.expect);
  }
}

TEST_CASE("wide lines follow the parallelogram rule", "[lines]") {
  struct Case {
    double x0, y0, x1, y1, width;
    Pixels expect;
  };
  Pixels h3, h2, d2;
  for (int x = 2; x <= 7; ++x)
    for (int y = 4; y <= 6; ++y) h3.insert({x, y});  // centres x in [2.5, 8.5), y in [4.0, 7.0)
  for (int x = 2; x <= 7; ++x)
    for (int y = 4; y <= 5; ++y) h2.insert({x, y});  // y centres in [4.5, 6.5)
  for (int x = 2; x <= 7; ++x) {                     // y centres in [x + 0.5 - 1, x + 0.5 + 1)
    d2.insert({x, x - 1});
    d2.insert({x, x});
  }
  const std::vector<Case> cases = {{2.5, 5.5, 8.5, 5.5, 3.0, h3}, {2.5, 5.5, 8.5, 5.5, 2.0, h2}, {2.5, 2.5, 8.5, 8.5, 2.0, d2}};
  for (const Case& c : cases) {
    WindowScene ws{12, 12, {}, {}, {}};
    ws.line(c.x0, c.y0, c.x1, c.y1);
    RenderSettings rs;
    rs.lineWidth = float(c.width);
    const Frame f = renderWindow(ws.build(), ws.W, ws.H, rs);
    INFO("width " << c.width << ": got " << show(litPixels(f)) << ", expected " << show(c.expect));
    CHECK(litPixels(f) == c.expect);
  }
}

TEST_CASE("points are squares of their size by the pixel-centre rule", "[points]") {
  // Pixels whose centres lie in [x - s/2, x + s/2) x [y - s/2, y + s/2).
  struct Case {
    double x, y, size;
    int x0, x1, y0, y1;
  };
  const std::vector<Case> cases = {
      {5.5, 5.5, 1, 5, 5, 5, 5}, {5.0, 5.0, 1, 4, 4, 4, 4}, {5.5, 5.5, 2, 4, 5, 4, 5}, {5.0, 5.0, 2, 4, 5, 4, 5},
      {5.0, 5.0, 3, 3, 5, 3, 5}, {5.5, 5.5, 3, 4, 6, 4, 6}, {5.25, 5.75, 4, 3, 6, 4, 7}, {0.2, 0.2, 5, 0, 2, 0, 2},
  };
  for (const Case& c : cases) {
    WindowScene ws{12, 12, {}, {}, {}};
    ws.point(c.x, c.y);
    RenderSettings rs;
    rs.pointSize = float(c.size);
    Pixels expect;
    for (int y = c.y0; y <= c.y1; ++y)
      for (int x = c.x0; x <= c.x1; ++x) expect.insert({x, y});
    const Frame f = renderWindow(ws.build(), ws.W, ws.H, rs);
    INFO("point (" << c.x << "," << c.y << ") size " << c.size << ": got " << show(litPixels(f)));
    CHECK(litPixels(f) == expect);
  }
}

TEST_CASE("a closed polyline lights every vertex pixel exactly once", "[lines]") {
  // Counted per segment with the renderer's own device functions on the host,
  // then compared with the rendered image (which must light the union).
  const int W = 64, H = 48;
  const Viewport vp{W, H, SamplePattern{}};
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> px(2, W - 3), py(2, H - 3);
  std::uniform_real_distribution<double> off(-0.2, 0.2);  // inside the vertex pixel's diamond
  for (int trial = 0; trial < 40; ++trial) {
    WindowScene ws{W, H, {}, {}, {}};
    const int n = 3 + trial % 6;
    std::vector<std::pair<int, int>> vpix;
    std::vector<uint32_t> loop;
    for (int k = 0; k < n; ++k) {
      int x, y;
      do {
        x = px(rng);
        y = py(rng);
      } while (std::find(vpix.begin(), vpix.end(), std::make_pair(x, y)) != vpix.end());
      vpix.push_back({x, y});
      loop.push_back(ws.vertex(x + 0.5 + off(rng), y + 0.5 + off(rng)));
    }
    for (int k = 0; k < n; ++k) {  // the loader's LINE_LOOP expansion
      ws.seg.push_back(loop[k]);
      ws.seg.push_back(loop[(k + 1) % n]);
    }
    // Pixels each segment lights (segment k runs from vertex k to vertex k+1).
    std::vector<std::map<std::pair<int, int>, int>> count(n);
    Pixels expect;
    for (int k = 0; k < n; ++k) {
      const rast::float3 a = ws.pos[ws.seg[2 * k]], b = ws.pos[ws.seg[2 * k + 1]];
      LineRaster r{};
      if (!setupLine(rast::float4{a.x, a.y, a.z, 1.0f}, rast::float4{b.x, b.y, b.z, 1.0f}, vp, guardBand(W), guardBand(H),
                     kSubOne, r))
        continue;
      for (int32_t P = r.lo; P <= r.hi; ++P)
        lineColumn(r, P, [&](int32_t X, int32_t Y, float) {
          ++count[k][{X, Y}];
          expect.insert({X, Y});
        });
    }
    // The vertex's pixel: lit by the segment leaving it, not by the one
    // arriving (segments of a polygon that merely pass elsewhere may cross it).
    for (int k = 0; k < n; ++k) {
      INFO("trial " << trial << ": vertex pixel (" << vpix[k].first << "," << vpix[k].second << ")");
      CHECK(count[k][vpix[k]] == 1);
      CHECK(count[(k + n - 1) % n][vpix[k]] == 0);
    }
    const Frame f = renderWindow(ws.build(), W, H);
    CHECK(litPixels(f) == expect);
  }
}

TEST_CASE("a line crossing the near plane keeps its visible part", "[lines][clip]") {
  // Camera at z = 5 looking down -z; the line runs from (0, -1, 0), in view,
  // to (0, -1, 10), behind the camera. Its visible part runs from the point's
  // projection (window y = 32 * (1 - 1/5 / tan 45) = 25.6) straight down to the
  // bottom edge, in the column the x = 0 line falls in.
  Scene s;
  s.name = "near";
  s.materials.push_back(Material{});
  std::vector<rast::float3> pos = {{0.0f, -1.0f, 0.0f}, {0.0f, -1.0f, 10.0f}};
  s.draws.push_back(Draw{addLinePrim(s, pos, nullptr, {0, 1}, {}, 0), glm::dmat4(1.0)});
  Camera cam;
  cam.eye = {0, 0, 5};
  cam.target = {0, 0, 0};
  cam.fovyDeg = 90.0;
  cam.znear = 0.5;
  cam.zfar = 100.0;
  RenderSettings rs;
  rs.width = rs.height = 64;
  const Frame f = renderFrame(s, cam, rs);
  const Pixels lit = litPixels(f);
  std::set<int> rows;
  for (const auto& p : lit) {
    CHECK((p.first == 31 || p.first == 32));
    rows.insert(p.second);
  }
  CHECK(lit.size() == rows.size());  // one pixel per row
  for (int y = 0; y <= 24; ++y) CHECK(rows.count(y) == 1);
  CHECK(*rows.rbegin() <= 26);
}

TEST_CASE("lines and points depth-test against the triangles of the frame under every raster method", "[lines][points]") {
  // A full-frame quad at depth 0.5; one line and one point in front of it
  // (0.25), one line and one point behind it (0.75). Primitive ids: the two
  // quad triangles are 1 and 2, then the segments 3 and 4, then the points 5, 6.
  const int W = 40, H = 24;
  Scene s;
  s.name = "depth";
  s.materials.push_back(Material{});
  std::vector<rast::float3> q = {windowToNdc(0, 0, 0.0, W, H), windowToNdc(W, 0, 0.0, W, H), windowToNdc(W, H, 0.0, W, H),
                                 windowToNdc(0, H, 0.0, W, H)};
  s.draws.push_back(Draw{addPrim(s, q, nullptr, nullptr, nullptr, {0, 1, 2, 0, 2, 3}, 0), glm::dmat4(1.0)});
  WindowScene ws{W, H, {}, {}, {}};
  ws.line(2.5, 5.5, 30.5, 5.5, -0.5);   // window depth 0.25: in front
  ws.line(2.5, 15.5, 30.5, 15.5, 0.5);  // window depth 0.75: hidden
  ws.point(35.5, 5.5, -0.5);
  ws.point(35.5, 15.5, 0.5);
  s.draws.push_back(Draw{addLinePrim(s, ws.pos, nullptr, ws.seg, ws.pts, 0), glm::dmat4(1.0)});
  for (RasterMethod m : allRasterMethods()) {
    for (int msaa : {1, 4}) {
      RenderSettings rs;
      rs.raster = m;
      rs.msaa = msaa;
      const Frame f = renderWindow(s, W, H, rs);
      INFO("method " << toString(m) << ", msaa " << msaa);
      for (int x = 2; x <= 29; ++x) {
        CHECK(f.id(x, 5) == 3);
        CHECK(f.depth[size_t(5) * W + x] == Approx(0.25f).margin(1e-6));
        CHECK(f.id(x, 15) <= 2);
      }
      CHECK(f.id(35, 5) == 5);
      CHECK(f.id(35, 15) <= 2);
      CHECK(f.id(35, 10) <= 2);
      CHECK(f.id(35, 10) >= 1);
    }
  }
}

TEST_CASE("a 4000-pixel line is split into bounded work items and lit end to end", "[lines]") {
  const int W = 4096, H = 4;
  WindowScene ws{W, H, {}, {}, {}};
  ws.line(10.5, 1.5, 4010.5, 2.5);
  LineRaster r{};
  const rast::float3 a = ws.pos[0], b = ws.pos[1];
  REQUIRE(setupLine(rast::float4{a.x, a.y, a.z, 1}, rast::float4{b.x, b.y, b.z, 1}, Viewport{W, H, SamplePattern{}},
                    guardBand(W), guardBand(H), kSubOne, r));
  CHECK(lineSpans(r) >= 4000 / kLineSpan);
  const Frame f = renderWindow(ws.build(), W, H);
  const Pixels lit = litPixels(f);
  CHECK(lit.size() == 4000);
  for (int x = 10; x < 4010; ++x) CHECK(f.id(x, 1) + f.id(x, 2) == 1);
}

TEST_CASE("polygon modes draw triangle edges and corners with the triangle's id", "[lines][polygon]") {
  // Two triangles sharing the diagonal of a square [4, 20] x [4, 20].
  const int W = 24, H = 24;
  std::vector<rast::float3> p = {windowToNdc(4.5, 4.5, 0, W, H), windowToNdc(20.5, 4.5, 0, W, H),
                                 windowToNdc(20.5, 20.5, 0, W, H), windowToNdc(4.5, 20.5, 0, W, H)};
  const Scene s = trianglesScene(p, {0, 1, 2, 0, 2, 3});
  RenderSettings rs;
  rs.polygon = PolygonMode::Line;
  Frame f = renderWindow(s, W, H, rs);
  CHECK(f.id(12, 4) == 1);   // bottom edge: triangle 1
  CHECK(f.id(4, 12) == 2);   // left edge: triangle 2
  CHECK(f.id(10, 10) >= 1);  // the shared diagonal
  CHECK(f.id(15, 8) == 0);   // inside: not filled
  CHECK(litPixels(f).size() < 100);
  rs.polygon = PolygonMode::Point;
  rs.pointSize = 3;
  f = renderWindow(s, W, H, rs);
  const Pixels lit = litPixels(f);
  CHECK(lit.size() == 4 * 9);  // four corners, 3x3 each
  CHECK(f.id(4, 4) >= 1);
  CHECK(f.id(20, 12) == 0);
}

TEST_CASE("the wireframe overlay draws edges over the fill, and hidden-line hides the edges behind it", "[lines][polygon]") {
  // A back square (z = 0.5, triangles 1 and 2) over the whole frame, and a
  // front square (z = -0.5, triangles 3 and 4) over its left half.
  const int W = 32, H = 16;
  std::vector<rast::float3> p = {windowToNdc(0.5, 0.5, 0.5, W, H),  windowToNdc(31.5, 0.5, 0.5, W, H),
                                 windowToNdc(31.5, 15.5, 0.5, W, H), windowToNdc(0.5, 15.5, 0.5, W, H),
                                 windowToNdc(0, 0, -0.5, W, H),      windowToNdc(16, 0, -0.5, W, H),
                                 windowToNdc(16, 16, -0.5, W, H),    windowToNdc(0, 16, -0.5, W, H)};
  const Scene s = trianglesScene(p, {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7});
  const Frame fill = renderWindow(s, W, H);
  RenderSettings rs;
  rs.wireframe = Wireframe::Hidden;
  const Frame hidden = renderWindow(s, W, H, rs);
  rs.wireframe = Wireframe::On;
  const Frame on = renderWindow(s, W, H, rs);
  int blackHidden = 0, backIdsOverFront = 0, backIdsOverFrontHidden = 0;
  const uint32_t black = 0xff000000u;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      blackHidden += hidden.color[size_t(H - 1 - y) * W + x] == black;
      if (x < 16) {
        CHECK(fill.id(x, y) >= 3);
        backIdsOverFront += on.id(x, y) <= 2;
        backIdsOverFrontHidden += hidden.id(x, y) <= 2;
      }
    }
  CHECK(blackHidden > 40);             // the visible edges are drawn (black) over the fill
  CHECK(backIdsOverFrontHidden == 0);  // the back square's edges stay behind the front square
  CHECK(backIdsOverFront > 10);        // unless drawn on top of everything
  CHECK(hidden.id(24, 8) == fill.id(24, 8));
}

TEST_CASE("ids: triangles first, then line segments, then points, in traversal order", "[lines][points]") {
  const int W = 16, H = 16;
  Scene s;
  s.name = "ids";
  s.materials.push_back(Material{});
  WindowScene ws{W, H, {}, {}, {}};
  ws.point(13.5, 13.5);
  ws.line(1.5, 13.5, 6.5, 13.5);
  s.draws.push_back(Draw{addLinePrim(s, ws.pos, nullptr, {}, {0}, 0), glm::dmat4(1.0)});          // points first in the file
  s.draws.push_back(Draw{addLinePrim(s, ws.pos, nullptr, {1, 2}, {}, 0), glm::dmat4(1.0)});       // then a segment
  std::vector<rast::float3> t = {windowToNdc(1, 1, 0, W, H), windowToNdc(8, 1, 0, W, H), windowToNdc(1, 8, 0, W, H)};
  s.draws.push_back(Draw{addPrim(s, t, nullptr, nullptr, nullptr, {0, 1, 2}, 0), glm::dmat4(1.0)});  // a triangle last
  const Frame f = renderWindow(s, W, H);
  CHECK(f.id(2, 2) == 1);    // the triangle
  CHECK(f.id(3, 13) == 2);   // the segment
  CHECK(f.id(13, 13) == 3);  // the point
}

TEST_CASE("the loader expands LINE_LOOP and LINE_STRIP into segments", "[lines][loader]") {
  // A .gltf with four vertices (embedded buffer) drawn by one primitive per mode.
  const char* b64 = "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAACAPwAAgD8AAAAAAAAAAAAAgD8AAAAA";  // (0,0,0) (1,0,0) (1,1,0) (0,1,0)
  for (int mode : {0, 1, 2, 3}) {
    const std::string path = scratchPath("line_mode_" + std::to_string(mode) + ".gltf");
    std::ofstream(path) << R"({"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],)"
                        << R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"mode":)" << mode << "}]}],"
                        << R"("accessors":[{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3",)"
                        << R"("min":[0,0,0],"max":[1,1,0]}],"bufferViews":[{"buffer":0,"byteLength":48}],)"
                        << R"("buffers":[{"byteLength":48,"uri":"data:application/octet-stream;base64,)" << b64 << "\"}]}";
    const Scene s = loadGltf(path);
    std::remove(path.c_str());
    INFO("mode " << mode);
    if (mode == 0) {
      CHECK(s.pointCount() == 4);
      CHECK(s.lineCount() == 0);
      continue;
    }
    const std::vector<uint32_t> expect = mode == 1   ? std::vector<uint32_t>{0, 1, 2, 3}
                                         : mode == 2 ? std::vector<uint32_t>{0, 1, 1, 2, 2, 3, 3, 0}
                                                     : std::vector<uint32_t>{0, 1, 1, 2, 2, 3};
    CHECK(s.lineIndices == expect);
    CHECK(s.triangleCount() == 0);
  }
}

TEST_CASE("Mesh_PrimitiveMode_00..15 load and render non-empty", "[lines][points][assimp]") {
  const std::string dir = assimpDir();
  if (dir.empty()) {
    WARN("SKIPPED: assimp-testmodels not installed");
    return;
  }
  int found = 0;
  for (int i = 0; i <= 15; ++i) {
    char name[64];
    std::snprintf(name, sizeof name, "Mesh_PrimitiveMode_%02d.gltf", i);
    const std::string path = dir + "/glTF-Asset-Generator/Mesh_PrimitiveMode/" + name;
    if (!fileExists(path)) continue;
    ++found;
    INFO(name);
    const Scene s = loadGltf(path);
    RenderSettings rs;
    rs.width = 160;
    rs.height = 120;
    const Frame f = renderFrame(s, defaultCamera(s), rs);
    CHECK(litPixels(f).size() > 50);
  }
  CHECK(found == 16);
}

TEST_CASE("exported point and line scenes load back with the same segments, points and ids", "[lines][points][export]") {
  for (const char* name : {"lines?n=50", "points?n=50"}) {
    Scene s;
    REQUIRE(makeStressScene(name, s));
    const std::string path = scratchPath("export_" + std::string(name).substr(0, 5) + ".glb");
    exportGlb(s, path);
    const Scene back = loadGltf(path);
    std::remove(path.c_str());
    INFO(name);
    CHECK(back.triangleCount() == s.triangleCount());
    CHECK(back.lineCount() == s.lineCount());
    CHECK(back.pointCount() == s.pointCount());
    RenderSettings rs;
    rs.width = 96;
    rs.height = 54;
    const Camera cam = defaultCamera(s);
    CHECK(renderFrame(back, cam, rs).ids == renderFrame(s, cam, rs).ids);
  }
}
