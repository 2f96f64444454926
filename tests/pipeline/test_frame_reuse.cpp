// Frames rendered one after another by one Renderer equal frames rendered by a
// fresh one. The per-pixel shade kernel clears each visibility key after
// reading it, and the next frame then skips its clearing pass
// (FrameBuffers::visClear): a key left behind by the previous view would show
// here as a stale id or depth. Views alternate between a close one and a far
// one, so that pixels covered in one are background in the other, across
// raster methods, sample counts and polygon modes, in an order that changes
// method between frames (binned writes every key; the others need a clear).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>

#include "pipeline/frame/renderer.h"
#include "scenes/procedural.h"
#include "pipeline/data/test_hooks.h"
#include "tests/support/test_support.h"

using namespace rast;
using namespace rast::test;

namespace {

struct Step {
  const char* what;
  RasterMethod method;
  int msaa;
  PolygonMode polygon;
  bool far;
};

// n views around base's target about the vertical, `step` radians apart,
// the near plane 10% further each view.
std::vector<Camera> orbit(const Camera& base, int n, double step) {
  std::vector<Camera> cams;
  for (int i = 0; i < n; ++i) {
    Camera cam = base;
    const double a = step * i;
    const glm::dvec3 d = base.eye - base.target;
    cam.eye = base.target + glm::dvec3(d.x * std::cos(a) + d.z * std::sin(a), d.y, -d.x * std::sin(a) + d.z * std::cos(a));
    cam.znear = base.znear * (1.0 + 0.1 * i);
    cams.push_back(cam);
  }
  return cams;
}

}  // namespace

TEST_CASE("frames rendered in sequence by one renderer equal fresh renders", "[frame-reuse]") {
  const Scene s = builtinScene("builtin:default");
  const Camera close = defaultCamera(s);
  Camera far = close;
  far.eye = close.target + (close.eye - close.target) * 3.0;
  RenderSettings rs;
  rs.width = 157;  // not a multiple of the shading run
  rs.height = 93;
  rs.wantPrimId = true;
  rs.wantDepth = true;
  testHooks().shadeRun = 1;  // on a CPU, the per-pixel kernel (the span kernel does not clear)
  const Step steps[] = {
      {"visbuffer close", RasterMethod::VisBuffer, 1, PolygonMode::Fill, false},
      {"visbuffer far", RasterMethod::VisBuffer, 1, PolygonMode::Fill, true},
      {"naive close", RasterMethod::Naive, 1, PolygonMode::Fill, false},
      {"naive far", RasterMethod::Naive, 1, PolygonMode::Fill, true},
      {"binned close", RasterMethod::Binned, 1, PolygonMode::Fill, false},
      {"visbuffer far after binned", RasterMethod::VisBuffer, 1, PolygonMode::Fill, true},
      {"lines close", RasterMethod::VisBuffer, 1, PolygonMode::Line, false},
      {"points far", RasterMethod::VisBuffer, 1, PolygonMode::Point, true},
      {"msaa4 close", RasterMethod::VisBuffer, 4, PolygonMode::Fill, false},
      {"msaa4 far", RasterMethod::VisBuffer, 4, PolygonMode::Fill, true},
      {"one sample again, far", RasterMethod::VisBuffer, 1, PolygonMode::Fill, true},
  };
  Renderer r(s);
  size_t changed = 0;
  std::vector<uint32_t> lastIds;
  for (const Step& st : steps) {
    INFO(st.what);
    rs.raster = st.method;
    rs.msaa = st.msaa;
    rs.polygon = st.polygon;
    const Camera& cam = st.far ? far : close;
    r.render(cam, rs);
    const std::vector<uint32_t> ids = r.primIdsBottomUp();
    const Frame fresh = renderFrame(s, cam, rs);
    REQUIRE(ids == fresh.ids);
    REQUIRE(r.depthBottomUp() == fresh.depth);
    REQUIRE(r.colorTopDown() == fresh.color);
    // The views must differ where it matters: covered pixels turn background.
    if (!lastIds.empty())
      for (size_t i = 0; i < ids.size(); ++i) changed += lastIds[i] != 0 && ids[i] == 0;
    lastIds = ids;
  }
  CHECK(changed > 1000);
}

// On CUDA the frame after vertexUniforms is recorded as a graph on its second
// frame and replayed from the third (backends/frame_graphs.h): the camera then
// reaches the kernels only through device memory. Every frame of an orbit,
// with each shading mode that reads the camera (the headlight's eye, the
// depth range's near and far, SSAO's view matrix), must equal a fresh render.
TEST_CASE("a moving camera on one renderer gives the frames of fresh renderers", "[frame-reuse][graphs]") {
  const Scene s = builtinScene("builtin:default");
  const Camera base = defaultCamera(s);
  RenderSettings rs;
  rs.width = 160;
  rs.height = 96;
  rs.wantPrimId = true;
  rs.wantDepth = true;
  for (ShadingMode mode : {ShadingMode::BlinnPhong, ShadingMode::Depth, ShadingMode::Lambert}) {
    rs.shading = mode;
    rs.post.ssao = mode == ShadingMode::Lambert;  // the view matrix reaches SSAO's geometry
    INFO("shading " << toString(mode) << (rs.post.ssao ? " with SSAO" : ""));
    const std::vector<Camera> cams = orbit(base, 8, 0.25);  // the depth mode reads near and far
    // The fresh frames first: a renderer's allocations drop every recording
    // (the allocation count is process-wide), so interleaving them would
    // keep the renderer under test from ever replaying.
    std::vector<Frame> fresh;
    for (const Camera& cam : cams) fresh.push_back(renderFrame(s, cam, rs));
    Renderer r(s);
    std::vector<uint32_t> firstColor;
    size_t differ = 0;
    for (int i = 0; i < 8; ++i) {
      INFO("frame " << i);
      r.render(cams[i], rs);
      const Frame& f = fresh[i];
      REQUIRE(r.primIdsBottomUp() == f.ids);
      REQUIRE(r.depthBottomUp() == f.depth);
      const std::vector<uint32_t> color = r.colorTopDown();
      REQUIRE(color == f.color);
      if (i == 0) firstColor = color;
      differ += color != firstColor;
    }
    CHECK(differ == 7);  // the camera moved every frame, and so did the image
  }
}

// The same for frames with BLEND layers: on CUDA the listed methods' passes
// launch lightweight, so their frames are recorded and replayed too
// (blendLaunchesLightweight): the sorted keys read the camera's view, the
// weights its near and far planes, and the resolve's scratch size comes from
// the last frame's longest list (blendLaunchKey). Each frame's float film,
// ids and depth must equal a fresh renderer's.
TEST_CASE("a moving camera over BLEND layers gives the frames of fresh renderers", "[frame-reuse][graphs][blend]") {
  const Scene s = builtinScene("builtin:layers?n=6&mixed=1&cross=1&unlit=0");
  const Camera base = defaultCamera(s);
  RenderSettings rs;
  rs.width = 96;
  rs.height = 64;
  rs.wantPrimId = true;
  rs.wantDepth = true;
  rs.environment = "none";  // the glTF shading's lights, not a fresh environment built per renderer
  const std::vector<Camera> cams = orbit(base, 5, 0.04);
  for (Transparency method : {Transparency::Exact, Transparency::Sorted, Transparency::Weighted})
    for (ShadingMode mode : {ShadingMode::Lambert, ShadingMode::Pbr}) {
      rs.transparency = method;
      rs.shading = mode;
      INFO("transparency " << toString(method) << ", shading " << toString(mode));
      // Fresh frames first: their allocations would drop the recordings.
      struct Fresh {
        std::vector<rast::float4> film;
        std::vector<uint32_t> ids;
        std::vector<float> depth;
      };
      std::vector<Fresh> fresh;
      for (const Camera& cam : cams) {
        Renderer f(s);
        f.render(cam, rs);
        fresh.push_back({f.filmBottomUp(), f.primIdsBottomUp(), f.depthBottomUp()});
      }
      Renderer r(s);
      size_t differ = 0;
      for (size_t i = 0; i < cams.size(); ++i) {
        INFO("frame " << i);
        r.render(cams[i], rs);
        const std::vector<rast::float4> film = r.filmBottomUp();
        REQUIRE(film.size() == fresh[i].film.size());
        REQUIRE(std::memcmp(film.data(), fresh[i].film.data(), film.size() * sizeof(rast::float4)) == 0);
        REQUIRE(r.primIdsBottomUp() == fresh[i].ids);
        REQUIRE(r.depthBottomUp() == fresh[i].depth);
        if (i > 0) differ += std::memcmp(film.data(), fresh[0].film.data(), film.size() * sizeof(rast::float4)) != 0;
      }
      CHECK(differ == cams.size() - 1);  // every view changed the image
    }
}

// A keys-only frame (RenderSettings::keysOnly: rast::lib::rasterize) ends with
// its keys, which the caller's pass reads through FrameKeys::take; take
// clears them and resets the visbuffer's block bounds, as shading does. The
// ids taken must be a shaded frame's, and the frames after it, keys-only or
// shaded, must not see a key it left: close and far views alternate. The
// pass's first thread publishes the counters (FrameKeys::publish), which
// lastFrameFit then reads without a copy: they must be this frame's (the two
// views rasterise different numbers of triangles).
TEST_CASE("keys-only frames give the shaded frame's ids and leave the keys clear", "[frame-reuse][keys]") {
  const Scene s = builtinScene("builtin:default");
  const Camera close = defaultCamera(s);
  Camera far = close;
  far.eye = close.target + (close.eye - close.target) * 3.0;
  RenderSettings rs;
  rs.width = 157;
  rs.height = 93;
  rs.wantPrimId = true;
  rs.wantDepth = true;
  testHooks().shadeRun = 1;  // on a CPU, the per-pixel kernel (the span kernel does not clear)
  const int64_t n = int64_t(rs.width) * rs.height;
  for (RasterMethod method : {RasterMethod::VisBuffer, RasterMethod::Naive, RasterMethod::Binned}) {
    rs.raster = method;
    INFO("method " << int(method));
    Renderer r(s);
    size_t changed = 0, trisChanged = 0;
    uint32_t lastTris = 0;
    std::vector<uint32_t> last;
    for (int step = 0; step < 6; ++step) {
      const bool keys = step % 3 != 2;  // two keys-only frames, then a shaded one
      const Camera& cam = step % 2 ? far : close;
      INFO("step " << step << (keys ? " keys-only" : " shaded"));
      const Frame fresh = renderFrame(s, cam, rs);
      std::vector<uint32_t> ids;
      if (keys) {
        RenderSettings k = rs;
        k.keysOnly = true;
        r.enqueue(cam, k);
        const FrameKeys fk = r.takeKeys();
        Kokkos::View<uint32_t*, Exec::memory_space> out("ids", size_t(n));
        const int32_t w = rs.width;
        Kokkos::parallel_for(
            "rast::test::take_keys", Kokkos::RangePolicy<Exec>(0, n), KOKKOS_LAMBDA(const int64_t i) {
              if (i == 0) fk.publish();
              const int64_t t = fk.take(i, int32_t(i % w), int32_t(i / w));
              out(i) = uint32_t(t + 1);
            });
        FrameStats got, want;
        REQUIRE(r.lastFrameFit(&got));
        Renderer shaded(s);
        shaded.render(cam, rs);
        shaded.lastFrameFit(&want);
        REQUIRE(got.rasterTris == want.rasterTris);
        trisChanged += step > 0 && got.rasterTris != lastTris;
        lastTris = got.rasterTris;
        auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), out);
        ids.assign(h.data(), h.data() + n);
        REQUIRE_THROWS(r.takeKeys());  // once a frame
      } else {
        r.render(cam, rs);
        ids = r.primIdsBottomUp();
        REQUIRE(r.depthBottomUp() == fresh.depth);
      }
      REQUIRE(ids == fresh.ids);
      if (!last.empty())
        for (size_t i = 0; i < ids.size(); ++i) changed += last[i] != 0 && ids[i] == 0;
      last = ids;
    }
    CHECK(changed > 1000);
    CHECK(trisChanged > 0);  // stale counters would have been caught
  }
}
