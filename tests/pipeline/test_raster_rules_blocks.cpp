// The rules behind the visibility-buffer raster's block skipping: a
// triangle's depth bounds and its 8x8 blocks' (depthBounds, rectNearest), the
// occluders' block bounds and the setup's filter for them (occluderBound,
// occluderSegments), rectangles a triangle misses (rectOutside), the work
// hints that find an item's triangle, and small boxes taken as one item. A
// block skipped wrongly loses pixels, so each is checked against brute force
// per pixel or against another raster method's ids and depth.
//
// Apart from test_raster_rules.cpp (fill rule, snapping, clipping), which
// these cases outgrew; they test pipeline/rules/visbuffer_blocks.h and the
// parts of raster_rules.h it rests on (depthBounds, rectOutside).
#include <catch2/catch.hpp>

#include "pipeline/data/test_hooks.h"
#include "pipeline/rules/raster_rules.h"
#include "pipeline/rules/visbuffer_blocks.h"
#include "tests/support/test_support.h"

#include <algorithm>
#include <glm/gtc/matrix_transform.hpp>
#include <random>

using namespace rast;
using namespace rast::test;

TEST_CASE("a triangle's depth bounds, and its blocks', hold the depth of every pixel it covers", "[raster][hiz]") {
  // The visibility-buffer raster skips an 8x8 block when a triangle's lower
  // bound lies behind the block's bound, and lowers that to the upper bound of
  // a triangle covering the block: a fragment outside [lo, hi] could then be
  // skipped while it would win. Random triangles of every size and slant, with
  // depths near 0, near 1 (where float steps are coarse) and spread out.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> pos(-20.0, 84.0), unit(0.0, 1.0);
  const int W = 64, H = 64;
  const Viewport vp{W, H, SamplePattern{}};
  size_t fragments = 0, outside = 0, narrow = 0, belowRect = 0, tighter = 0;
  for (int n = 0; n < 4000; ++n) {
    const int kind = n % 4;
    ClipVert v[3];
    for (int k = 0; k < 3; ++k) {
      double z = unit(rng);
      if (kind == 1) z = 0.999 + 0.001 * unit(rng);
      if (kind == 2) z = 0.5 + 1e-5 * unit(rng);
      if (kind == 3) z = 1e-4 * unit(rng);
      const rast::float3 p = windowToNdc(pos(rng), pos(rng), 0.0, W, H);
      v[k].p = rast::float4{p.x, p.y, float(2.0 * z - 1.0), 1.0f};
      v[k].b1 = v[k].b2 = 0.0f;
    }
    RasterTri t;
    if (!setupTriangle(v[0], v[1], v[2], vp, false, true, 0, t)) continue;
    const DepthBounds b = depthBounds(t);
    narrow += b.hi - b.lo < 1e-3f;
    const Edges e(t);
    for (int y = t.minY; y <= t.maxY; ++y)
      for (int x = t.minX; x <= t.maxX; ++x) {
        const int64_t e0 = e.eval(0, x, y), e1 = e.eval(1, x, y), e2 = e.eval(2, x, y);
        if (!e.inside(e0, e1, e2)) continue;
        const float d = depthAt(t, e0, e1, e2);
        ++fragments;
        if (d < b.lo || d > b.hi) {
          if (++outside <= 3) UNSCOPED_INFO("depth " << d << " outside [" << b.lo << ", " << b.hi << "]");
        }
        // The bound of the pixel's 8x8 block within the box (rectNearest),
        // from corners the triangle may only cross.
        const int bx0 = std::max(t.minX, x & ~7), bx1 = std::min(t.maxX, (x & ~7) + 7);
        const int by0 = std::max(t.minY, y & ~7), by1 = std::min(t.maxY, (y & ~7) + 7);
        const float near = rectNearest(e, DepthTerms(t), bx0, bx1, by0, by1);
        tighter += near > b.lo;
        if (d < near && ++belowRect <= 3) UNSCOPED_INFO("depth " << d << " below its block's bound " << near);
      }
  }
  CHECK(fragments > 100000);
  CHECK(narrow > 1000);  // the bounds are tight enough to cull with
  CHECK(outside == 0);
  CHECK(belowRect == 0);
  CHECK(tighter * 4 > fragments);  // the blocks' bounds are often nearer the pixels than the triangle's
}

TEST_CASE("an occluder's block bound holds every pixel of the block, and the area filter loses no occluder",
          "[raster][hiz]") {
  // Before the visbuffer raster, each 8x8 block a large triangle covers whole
  // takes the triangle's farthest depth there plus a margin as its depth bound
  // (occluderBound), and items behind it are skipped. The bound must hold the
  // depth of every pixel of the block, as depthAt() rounds it; and the setup's
  // filter (occluderSegments: a bounding box holding a whole block, an area of
  // kOccluderMinArea pixels) must keep every triangle that covers a block.
  // Random triangles from 6 to 160 pixels across, sloped, with depths spread,
  // near 1 (coarse float steps) and within 1e-5 of 0.5.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const int W = 256, H = 256;
  const Viewport vp{W, H, SamplePattern{}};
  size_t wholeBlocks = 0, pixels = 0, above = 0, filteredOut = 0, tight = 0;
  for (int n = 0; n < 3000; ++n) {
    const int kind = n % 3;
    const double size = 6.0 + 154.0 * unit(rng) * unit(rng), cx = 16.0 + 224.0 * unit(rng), cy = 16.0 + 224.0 * unit(rng);
    ClipVert v[3];
    for (int k = 0; k < 3; ++k) {
      double z = unit(rng);
      if (kind == 1) z = 0.999 + 0.001 * unit(rng);
      if (kind == 2) z = 0.5 + 1e-5 * unit(rng);
      const rast::float3 p = windowToNdc(cx + size * (unit(rng) - 0.5), cy + size * (unit(rng) - 0.5), 0.0, W, H);
      v[k].p = rast::float4{p.x, p.y, float(2.0 * z - 1.0), 1.0f};
      v[k].b1 = v[k].b2 = 0.0f;
    }
    RasterTri t;
    if (!setupTriangle(v[0], v[1], v[2], vp, false, true, 0, t)) continue;
    const Edges e(t);
    const bool candidate = occluderSegments(t) > 0;
    const DepthBounds db = depthBounds(t);
    for (int by = 0; by < H / 8; ++by) {
      BlockCorners stepped(e, 0, by);  // as the occluder pass steps along a row
      for (int bx = 0; bx < W / 8; ++bx, stepped.stepRight(e)) {
        uint32_t bits = 0, steppedBits = 0;
        const bool bounded = occluderBound(t, bx, by, bits);
        REQUIRE(occluderBound(e, DepthTerms(t), stepped, steppedBits) == bounded);
        if (bounded) REQUIRE(steppedBits == bits);
        // Whole coverage by brute force, to check the filter and the corners.
        bool whole = true;
        for (int y = by * 8; y < by * 8 + 8; ++y)
          for (int x = bx * 8; x < bx * 8 + 8; ++x) whole = whole && e.inside(e.eval(0, x, y), e.eval(1, x, y), e.eval(2, x, y));
        if (whole && !candidate) ++filteredOut;
        if (!bounded) continue;
        REQUIRE(whole);
        ++wholeBlocks;
        tight += bitsFloat(bits) < db.hi;
        for (int y = by * 8; y < by * 8 + 8; ++y)
          for (int x = bx * 8; x < bx * 8 + 8; ++x) {
            const int64_t e0 = e.eval(0, x, y), e1 = e.eval(1, x, y), e2 = e.eval(2, x, y);
            ++pixels;
            if (floatBits(depthAt(t, e0, e1, e2)) > bits && ++above <= 3)
              UNSCOPED_INFO("depth " << depthAt(t, e0, e1, e2) << " above the bound " << bitsFloat(bits));
          }
      }
    }
  }
  CHECK(wholeBlocks > 2000);
  CHECK(pixels == wholeBlocks * 64);
  CHECK(above == 0);
  CHECK(filteredOut == 0);
  CHECK(tight * 2 > wholeBlocks);  // most blocks' bounds are nearer than the triangle's farthest depth
}

TEST_CASE("a rectangle outside a triangle's edges holds none of its pixels", "[raster][hiz]") {
  // rectOutside lets the visibility-buffer raster skip the 8x8 blocks of a
  // bounding box that the triangle misses; it must never skip a covered pixel.
  // Random triangles (including ones with edges through pixel centres, where
  // the top-left bias decides) against every 8x8 block of their boxes.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> pos(-30.0, 94.0);
  std::uniform_int_distribution<int> cell(-30, 94);
  const int W = 64, H = 64;
  const Viewport vp{W, H, SamplePattern{}};
  size_t skipped = 0, kept = 0, wrong = 0;
  for (int n = 0; n < 3000; ++n) {
    ClipVert v[3];
    for (int k = 0; k < 3; ++k) {
      // Every other triangle has its corners on pixel centres.
      const double x = n % 2 ? cell(rng) + 0.5 : pos(rng), y = n % 2 ? cell(rng) + 0.5 : pos(rng);
      const rast::float3 p = windowToNdc(x, y, 0.0, W, H);
      v[k].p = rast::float4{p.x, p.y, 0.0f, 1.0f};
      v[k].b1 = v[k].b2 = 0.0f;
    }
    RasterTri t;
    if (!setupTriangle(v[0], v[1], v[2], vp, false, true, 0, t)) continue;
    const Edges e(t);
    for (int by = t.minY >> 3; by <= t.maxY >> 3; ++by)
      for (int bx = t.minX >> 3; bx <= t.maxX >> 3; ++bx) {
        const int x0 = std::max(t.minX, bx * 8), x1 = std::min(t.maxX, bx * 8 + 7);
        const int y0 = std::max(t.minY, by * 8), y1 = std::min(t.maxY, by * 8 + 7);
        if (!rectOutside(e, x0, x1, y0, y1)) {
          ++kept;
          continue;
        }
        ++skipped;
        for (int y = y0; y <= y1; ++y)
          for (int x = x0; x <= x1; ++x) wrong += e.inside(e.eval(0, x, y), e.eval(1, x, y), e.eval(2, x, y));
      }
  }
  CHECK(skipped > 1000);
  CHECK(kept > 1000);
  CHECK(wrong == 0);
}

// Triangles at window positions (pixels, y up) and NDC depths, for a scene
// drawn with identityCamera() into a w x h frame.
struct WindowTriangles {
  int w, h;
  std::vector<rast::float3> p;
  std::vector<uint32_t> idx;
  WindowTriangles(int width, int height) : w(width), h(height) {}
  void add(double ax, double ay, double az, double bx, double by, double bz, double cx, double cy, double cz) {
    const uint32_t b = uint32_t(p.size());
    p.push_back(windowToNdc(ax, ay, az, w, h));
    p.push_back(windowToNdc(bx, by, bz, w, h));
    p.push_back(windowToNdc(cx, cy, cz, w, h));
    idx.insert(idx.end(), {b, b + 1, b + 2});
  }
  void add(double ax, double ay, double bx, double by, double cx, double cy, double z) { add(ax, ay, z, bx, by, z, cx, cy, z); }
  Scene scene() const { return trianglesScene(p, idx); }
  // The frame's settings: its size, with ids and depth.
  RenderSettings settings() const { return withIdsAndDepth(w, h); }
};

// The visbuffer raster finds each work item's triangle between search hints
// the setup writes (visbuffer_blocks.h, workHint): every kWorkHintItems-th
// item's triangle, tagged with the frame. A triangle spanning more than
// kWorkHintsWritten hints writes only the first and last hints of its items,
// so its interior's are whatever an earlier frame (or the zeroed buffer)
// left: the tag must reject them. Large triangles between small ones, drawn
// by one renderer from three cameras that move the items, must give the ids
// and depth of the naive raster. (Coordinates are given for 640x480 and
// scaled, so that the first large triangle spans more hints than are written.)
TEST_CASE("the visbuffer raster finds every item's triangle: large triangles among small ones, frame after frame",
          "[raster][hints]") {
  const int W = 1600, H = 1200;
  const double k = W / 640.0;
  WindowTriangles tris{W, H};
  auto tri = [&](double ax, double ay, double bx, double by, double cx, double cy, double z) {
    tris.add(k * ax, k * ay, k * bx, k * by, k * cx, k * cy, z);
  };
  for (int i = 0; i < 60; ++i) tri(8 + 10 * i, 4, 15 + 10 * i, 5, 10 + 10 * i, 12, 0.1);  // small, in front
  tri(10, 20, 630, 30, 320, 470, 0.5);          // about 27,000 items: 107 hints, 105 of them left unwritten
  for (int i = 0; i < 40; ++i) tri(20 + 15 * i, 440, 31 + 15 * i, 441, 25 + 15 * i, 452, 0.2);
  tri(40, 100, 300, 110, 170, 300, 0.3);        // about 5,200 items: 20 hints, all written
  tri(330, 380, 600, 60, 620, 400, 0.6);        // large again, partly behind the first
  for (int i = 0; i < 30; ++i) tri(100 + 12 * i, 200, 109 + 12 * i, 202, 104 + 12 * i, 210, 0.05);
  const Scene s = tris.scene();
  RenderSettings rs = tris.settings();
  Renderer r(s);
  int covered = 0;
  for (const double shift : {0.0, 37.0, -61.0}) {
    Camera cam = identityCamera();
    cam.viewProjOverride = glm::translate(glm::dmat4(1.0), glm::dvec3(2.0 * k * shift / W, 1.4 * k * shift / H, 0.0));
    INFO("shift " << shift);
    rs.raster = RasterMethod::Naive;
    const Frame ref = renderFrame(s, cam, rs);
    rs.raster = RasterMethod::VisBuffer;
    const FrameStats st = r.render(cam, rs);
    // The large triangles span more hints than a triangle writes.
    REQUIRE(st.rasterWork > (kWorkHintsWritten + 8) * kWorkHintItems);
    REQUIRE(r.primIdsBottomUp() == ref.ids);
    REQUIRE(r.depthBottomUp() == ref.depth);
    for (uint32_t id : ref.ids) covered += id != 0;
  }
  CHECK(covered > W * H);  // most of the frame, three times
}

// Occluders (raster_visbuffer.cpp): before the raster, large triangles lower
// the depth bounds of the blocks they cover whole, and the raster skips items
// behind them. Layers drawn back to front (every later one in front: the case
// the bounds are for), sloped planes that cross inside blocks, layers two float
// steps apart and layers at equal depth (the earlier triangle keeps the pixel)
// must give the naive raster's ids and depth. One renderer draws four frames
// whose cameras move and scale the layers: the setup's list of occluders is
// rebuilt each frame (a list left from the last frame would bound blocks with
// other triangles).
TEST_CASE("occluders: layers back to front, crossing, two float steps apart and level give the naive raster's ids and depth",
          "[raster][hiz]") {
  const int W = 640, H = 480;
  WindowTriangles tris{W, H};
  auto tri = [&](auto... a) { tris.add(a...); };
  auto quad = [&](double x0, double y0, double x1, double y1, double z00, double z10, double z01, double z11) {
    tri(x0, y0, z00, x1, y0, z10, x1, y1, z11);
    tri(x0, y0, z00, x1, y1, z11, x0, y1, z01);
  };
  for (int i = 0; i < 12; ++i) {  // back to front, each a little smaller
    const double m = 6.0 * i, z = 0.9 - 0.06 * i;
    quad(m, m, W - m, H - m, z, z, z, z);
  }
  quad(0, 0, W, H, 0.05, 0.5, 0.5, 0.05);  // sloped planes crossing each other along a diagonal
  quad(0, 0, W, H, 0.5, 0.05, 0.05, 0.5);
  // A layer, then one two float steps of window depth nearer (far less than
  // the bounds' margin), then a level one. (z here is NDC: window depth is
  // half of it plus a half.)
  const double near = 0.03, step = near - 2e-7;
  quad(40, 40, 300, 300, near, near, near, near);
  quad(60, 60, 320, 320, step, step, step, step);
  quad(50, 50, 310, 310, step, step, step, step);
  for (int i = 0; i < 40; ++i) tri(330 + 7 * i, 350, 0.02, 336 + 7 * i, 352, 0.02, 332 + 7 * i, 360, 0.02);
  const Scene s = tris.scene();
  RenderSettings rs = tris.settings();
  Renderer r(s);
  size_t stepWins = 0;
  for (const double shift : {0.0, 23.0, -41.0, 5.0}) {
    Camera cam = identityCamera();
    const double scale = shift == 5.0 ? 0.6 : 1.0;
    cam.viewProjOverride = glm::translate(glm::dmat4(1.0), glm::dvec3(2.0 * shift / W, 1.4 * shift / H, 0.0)) *
                           glm::scale(glm::dmat4(1.0), glm::dvec3(scale, scale, 1.0));
    INFO("shift " << shift);
    rs.raster = RasterMethod::Naive;
    const Frame ref = renderFrame(s, cam, rs);
    rs.raster = RasterMethod::VisBuffer;
    r.render(cam, rs);
    REQUIRE(r.primIdsBottomUp() == ref.ids);
    REQUIRE(r.depthBottomUp() == ref.depth);
    const uint32_t stepQuad = 2 * 12 + 4 + 2 + 1;  // the id of the nearer layer's first triangle
    for (uint32_t id : ref.ids) stepWins += id == stepQuad || id == stepQuad + 1;
  }
  CHECK(stepWins > 4 * 20000);  // the nearer layer shows (and the level one behind it does not)
}

// A raster triangle whose box is at most 8x8 pixels is one visbuffer item,
// whatever 8x8 blocks it straddles (smallBox, visbuffer_blocks.h). Such an item
// must tag every block it writes a key in (shading reads no key of an
// untagged block), and may be skipped only behind the bounds of all the
// blocks it meets. Small triangles straddle block edges and corners across
// the frame; a column of them straddles the edge of an occluder's blocks
// (near bounds on the left, far on the right), behind it on the left and seen
// on the right. With the GPU's interleaved shading (shadeRun 1, block tags
// read), ids and depth must be those of the binned raster, which tags nothing.
TEST_CASE("small boxes are one visbuffer item each, tag every block they draw in, and hide only behind all of them",
          "[raster][hiz]") {
  const int W = 256, H = 128;
  WindowTriangles tris{W, H};
  auto tri = [&](auto... a) { tris.add(a...); };
  tri(0, 0, 64, 0, 64, 128, 0.1);  // the occluder: blocks 0..7 of every row, whole
  tri(0, 0, 64, 128, 0, 128, 0.1);
  uint32_t small = 0;
  for (int y = 4; y < H; y += 8, small += 1) tri(60.3, y - 3.2, 67.7, y - 2.9, 63.1, y + 3.4, 0.5);  // across x = 64 only
  for (int y = 16; y < H; y += 16)
    for (int x = 88; x < W; x += 16, small += 1)  // across block corners, at depths in turn
      tri(x - 3.6, y - 3.3, x + 3.7, y - 2.8, x + 0.4, y + 3.5, 0.2 + 0.1 * ((x / 16 + y / 16) % 5));
  const Scene s = tris.scene();
  RenderSettings rs = tris.settings();
  rs.raster = RasterMethod::Binned;
  const Frame ref = renderFrame(s, identityCamera(), rs);
  rs.raster = RasterMethod::VisBuffer;
  testHooks().shadeRun = 1;  // the interleaved shading, which reads the block tags
  Renderer r(s);
  const FrameStats st = r.render(identityCamera(), rs);
  CHECK(st.rasterWork == 2 * 128 + small);  // the occluder's blocks (its box: 8x16 each), one item per small box
  REQUIRE(r.primIdsBottomUp() == ref.ids);
  REQUIRE(r.depthBottomUp() == ref.depth);
  size_t seenRight = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 64; x < 68; ++x) seenRight += ref.ids[size_t(y) * W + x] > 2;
  CHECK(seenRight > 100);  // the column's right halves show
}
