// The CPU's fast paths give the images of the general ones (issue #11):
// * the sRGB encoder's bucket lookup returns the byte of a binary search over
//   the same 256 thresholds, for every kind of input;
// * shading in runs (per-triangle lookups kept along a row) and the span
//   kernel (pipeline/cpu/shade_spans.h) give the ids, depth and colours of one pixel
//   per work item (TestHooks::shadeRun = 1), on scenes that exercise
//   textures, vertex colours, lights, lines, background and the float film;
// * the span kernel's vectorized texturing (branch-free floor, coordinate
//   reduction and wrapping, then the blend) gives sampleBilinear's bits for
//   every wrap mode and any coordinate, and textured frames whose texture
//   coordinates leave [0, 1] render the same colours, to the bit, per pixel
//   and in spans;
// * the host fine raster of the binned method matches the other methods on
//   ids and depth bit for bit (also covered by the stability suite), here on
//   textured models seen whole;
// * the GPU's primitive setup (one team per chunk, the look-back between
//   chunks), run on the host, gives the host setup's images.
#include <catch2/catch.hpp>

#include "base/color.h"
#include "pipeline/data/device_scene.h"
#include "pipeline/cpu/shade_spans.h"
#include "pipeline/data/test_hooks.h"
#include "pipeline/geometry/geometry.h"
#include "pipeline/raster/raster.h"
#include "pipeline/shade/texture_sampling.h"
#include "host/gltf/gltf_loader.h"
#include "scenes/procedural.h"
#include "tests/support/test_support.h"

#include <cmath>
#include <cstdlib>
#include <limits>

using namespace rast;
using namespace rast::test;

namespace {

// The encoder before the bucket table: the largest b with t(b) <= c.
uint32_t binarySearchEncode(float c, const std::vector<float>& t) {
  uint32_t lo = 0;
  for (uint32_t step = 128; step; step >>= 1)
    if (t[lo + step] <= c) lo += step;
  return lo;
}

int maxChannelDiff(uint32_t a, uint32_t b) {
  int d = 0;
  for (int s = 0; s < 32; s += 8) d = std::max(d, std::abs(int((a >> s) & 255) - int((b >> s) & 255)));
  return d;
}

void compareRuns(const std::string& name, const Scene& s, const Camera& cam, RenderSettings rs) {
  rs.width = 203;  // not a multiple of any run length
  rs.height = 61;
  testHooks().shadeRun = 1;
  const Frame ref = renderFrame(s, cam, rs);
  // Run 1 of each method: the per-pixel kernel, which skips the keys of 8x8
  // blocks the raster did not tag (visbuffer, naive).
  for (int run : {0, 1, 7, 64}) {
    for (RasterMethod m : {RasterMethod::Binned, RasterMethod::VisBuffer, RasterMethod::Naive}) {
      testHooks().shadeRun = run;
      rs.raster = m;
      INFO(name << ", run " << run << ", " << toString(m));
      const Frame f = renderFrame(s, cam, rs);
      REQUIRE(f.ids == ref.ids);
      REQUIRE(f.depth == ref.depth);
      int worst = 0;
      size_t covered = 0;
      for (size_t i = 0; i < f.color.size(); ++i) worst = std::max(worst, maxChannelDiff(f.color[i], ref.color[i]));
      for (uint32_t id : f.ids) covered += id != 0;
      CHECK(covered > 0);
      CHECK(worst <= 1);  // colours within 1/255 (the project's rule)
    }
  }
}

}  // namespace

TEST_CASE("sRGB bucket encoders (two reads, and one packed read) equal the binary search over the thresholds", "[cpu-paths]") {
  const std::vector<float> t = srgbEncodeThresholds();
  REQUIRE(t.size() == kSrgbEncodeTableSize);
  const Kokkos::View<const float*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>> table(t.data(), t.size());
  const std::vector<uint32_t> packed = srgbEncodePacked();
  REQUIRE(packed.size() == kSrgbBuckets);
  size_t checked = 0, wrong = 0;
  auto check = [&](float c) {
    ++checked;
    const uint32_t want = binarySearchEncode(c, t), got = encodeSrgb8(c, table), flat = encodeSrgb8Flat(c, t.data());
    const uint32_t one = encodeSrgb8Packed(c, packed.data());
    if (want != got || want != flat || want != one) {
      if (++wrong <= 5)
        UNSCOPED_INFO("c = " << c << " (bits " << floatBits(c) << "): " << got << ", " << flat << ", " << one << " != " << want);
    }
  };
  // Every 17th float from 0 to past 1, then the neighbourhood of every
  // threshold and of every bucket's lower end, where an off-by-one would show.
  for (uint32_t bits = 0; bits <= floatBits(1.25f); bits += 17) check(bitsFloat(bits));
  for (int b = 1; b < 256; ++b)
    for (int d = -3; d <= 3; ++d) check(bitsFloat(uint32_t(int64_t(floatBits(t[b])) + d)));
  for (uint32_t k = 0; k <= kSrgbBuckets + 1; ++k)
    for (int d = -2; d <= 2; ++d) check(bitsFloat(uint32_t(int64_t((kSrgbBucketFirst + k) << kSrgbBucketShift) + d)));
  for (float c : {0.0f, -0.0f, -1e-30f, -1.0f, 1.0f, 2.0f, 1e30f, std::numeric_limits<float>::max(), std::numeric_limits<float>::infinity(),
                  -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::denorm_min()})
    check(c);
  CHECK(encodeSrgb8(std::nanf(""), table) == 0);
  CHECK(encodeSrgb8(-std::nanf(""), table) == 0);
  CHECK(encodeSrgb8Flat(std::nanf(""), t.data()) == 0);
  CHECK(encodeSrgb8Flat(-std::nanf(""), t.data()) == 0);
  CHECK(encodeSrgb8Packed(std::nanf(""), packed.data()) == 0);
  CHECK(encodeSrgb8Packed(-std::nanf(""), packed.data()) == 0);
  CHECK(checked > 60000000);
  CHECK(wrong == 0);
}

TEST_CASE("shading in runs and spans gives the per-pixel images", "[cpu-paths]") {
  RenderSettings rs;
  for (const char* spec : {"builtin:default", "builtin:bigtri", "builtin:tiny?n=20000", "builtin:overdraw?layers=8",
                           "builtin:slivers", "builtin:zfight", "builtin:lines", "builtin:points"}) {
    const Scene s = builtinScene(spec);
    compareRuns(spec, s, defaultCamera(s), rs);
  }
  const Scene d = builtinScene("builtin:default");
  RenderSettings lit = rs;
  lit.lights = {DirectionalLight{{0.3f, 0.5f, 1.0f}, 0.7f}, DirectionalLight{{-1.0f, 0.2f, 0.3f}, 0.4f}};
  lit.background = {0.2f, 0.3f, 0.4f, 1.0f};
  compareRuns("default, two lights, background", d, defaultCamera(d), lit);
  RenderSettings film = rs;
  film.post.exposure = 0.5f;  // the float film instead of packed colour
  compareRuns("default, float film", d, defaultCamera(d), film);
  RenderSettings affine = rs;
  affine.perspectiveCorrect = false;
  compareRuns("default, affine", d, defaultCamera(d), affine);
  RenderSettings wire = rs;
  wire.wireframe = Wireframe::On;
  compareRuns("default, wireframe", d, defaultCamera(d), wire);
  RenderSettings other = rs;  // frames the span kernel leaves to the per-pixel one
  for (ShadingMode m : {ShadingMode::BlinnPhong, ShadingMode::Normals, ShadingMode::Depth}) {
    other.shading = m;
    compareRuns(std::string("default, ") + toString(m), d, defaultCamera(d), other);
  }
  RenderSettings msaa = rs;
  msaa.msaa = 4;
  compareRuns("default, msaa4", d, defaultCamera(d), msaa);
  // Pixels of tiny triangles, shaded as lanes of a batch (ShadeSpans::
  // shadeBatch): with lights, the float film, affine weights and vertex colours.
  Scene tiny = builtinScene("builtin:tiny?n=20000");
  const Camera tinyCam = defaultCamera(tiny);
  compareRuns("tiny, two lights, background", tiny, tinyCam, lit);
  compareRuns("tiny, float film", tiny, tinyCam, film);
  compareRuns("tiny, affine", tiny, tinyCam, affine);
  tiny.colors.resize(tiny.positions.size());
  for (size_t v = 0; v < tiny.colors.size(); ++v)
    tiny.colors[v] = rast::float4{float(v % 7) / 6.0f, float(v % 5) / 4.0f, float(v % 3) / 2.0f, 1.0f};
  compareRuns("tiny, vertex colours", tiny, tinyCam, rs);

  const std::string a = assimpDir();
  if (!a.empty()) {  // textured: bilinear and nearest
    const Scene box = loadGltf(a + "/BoxTextured-glTF-Binary/BoxTextured.glb");
    compareRuns("BoxTextured", box, autoFrame(box), rs);
    RenderSettings nearest = rs;
    nearest.filter = TexFilter::Nearest;
    compareRuns("BoxTextured, nearest", box, autoFrame(box), nearest);
  }
  const std::string sh = sharedDir();
  if (!sh.empty()) {
    for (const char* m : {"duck", "milktruck", "checkerboard"}) {
      const std::string p = sh + "/models/" + m + ".glb";
      if (!fileExists(p)) continue;
      const Scene s = loadGltf(p);
      compareRuns(m, s, autoFrame(s), rs);
    }
  }
  if (a.empty() && sh.empty()) skipTest("neither assimp's glTF models nor ../shared: textured cases not run");
}

namespace {

// Coordinates that exercise every branch of the samplers: inside, on texel
// centres and edges, outside by a little and a lot, negative, huge, non-finite.
std::vector<float> awkwardCoords() {
  std::vector<float> c = {0.0f, -0.0f, 0.5f, 1.0f, -1.0f, 2.0f, 3.0f, -3.0f, 0.999999f, 1.000001f, -0.000001f,
                          1e-30f, -1e-30f, 4194304.5f, -4194304.5f, 8388607.0f, 8388608.0f, -8388608.0f, 8388609.0f,
                          1e9f, -1e9f, 3.0e38f, -3.0e38f, std::numeric_limits<float>::infinity(),
                          -std::numeric_limits<float>::infinity(), std::nanf(""), -std::nanf("")};
  for (int i = -400; i <= 400; ++i) c.push_back(float(i) * 0.01237f);
  for (int i = 0; i < 64; ++i) c.push_back(float(i) / 7.0f - 4.5f);
  return c;
}

}  // namespace

TEST_CASE("the span kernel's branch-free texel addressing equals the per-pixel one", "[cpu-paths]") {
  for (float x : awkwardCoords()) {
    for (float s : {1.0f, 0.5f, 540.0f, 1e-3f}) {
      const float v = x * s;
      INFO("x = " << v);
      CHECK(floatBits(shading::floorTexelFlat(v)) == floatBits(floorTexel(v)));
      for (int32_t mode : {int32_t(WrapRepeat), int32_t(WrapClamp), int32_t(WrapMirror)})
        CHECK(floatBits(shading::reduceCoordFlat(v, mode)) == floatBits(reduceCoord(v, mode)));
    }
  }
  for (int32_t n : {1, 2, 3, 7, 540}) {
    for (int32_t mode : {int32_t(WrapRepeat), int32_t(WrapClamp), int32_t(WrapMirror)}) {
      for (int32_t i = -n; i < 3 * n; ++i) {
        int32_t bad = 0;
        INFO("n = " << n << ", mode " << mode << ", i = " << i);
        CHECK(shading::wrapIndexFlat(i, n, mode, bad) == wrapIndex(i, n, mode));
        CHECK(bad == 0);
      }
      int32_t bad = 0;
      shading::wrapIndexFlat(3 * n, n, mode, bad);  // outside the closed forms' range: flagged (but for clamp)
      CHECK(bad == (mode == WrapClamp ? 0 : 1));
    }
  }
}

TEST_CASE("the span kernel's bilinear texturing gives sampleBilinear's bits", "[cpu-paths]") {
  // A 5x3 texture of distinct colours and alphas (odd sizes: no power of two to hide behind).
  const int32_t W = 5, H = 3;
  std::vector<uint32_t> tx(size_t(W) * H);
  for (int32_t i = 0; i < W * H; ++i)
    tx[size_t(i)] = uint32_t(17 * i + 3) | uint32_t(255 - 13 * i) << 8 | uint32_t(40 + 11 * i) << 16 | uint32_t(255 - 7 * i) << 24;
  const std::vector<float> lutv = srgbDecodeTable();
  const Kokkos::View<const uint32_t*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>> T(tx.data(), tx.size());
  const Kokkos::View<const float*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>> L(lutv.data(), lutv.size());
  const std::vector<float> coords = awkwardCoords();
  size_t checked = 0;
  const int32_t modes[3] = {int32_t(WrapRepeat), int32_t(WrapClamp), int32_t(WrapMirror)};
  for (int32_t ms : modes)
    for (int32_t mt : modes) {
      TextureGPU t{0, W, H, ms, mt, 1, 9729, 9987};
      shading::SpanTex st{tx.data(), lutv.data(), W, H, ms, mt, 0, 0, 0, 0, 0, 0, 1};
      // Spans of up to 64 pixels whose weights put u and v anywhere: pixel j
      // interpolates corner coordinates with weights (b0, b1, b2).
      for (size_t start = 0; start < coords.size(); start += 61) {
        const int32_t m = int32_t(std::min<size_t>(61, coords.size() - start));
        st.u0 = coords[start];
        st.u1 = coords[(start * 7 + 3) % coords.size()];
        st.u2 = 0.25f;
        st.v0 = coords[(start * 13 + 5) % coords.size()];
        st.v1 = -0.75f;
        st.v2 = coords[(start * 3 + 1) % coords.size()];
        float b0[shading::kMaxSpanRun], b1[shading::kMaxSpanRun], b2[shading::kMaxSpanRun];
        for (int32_t j = 0; j < shading::kMaxSpanRun; ++j) {
          b0[j] = float(j % 9) / 8.0f;
          b1[j] = float((j * 5) % 11) / 10.0f - 0.3f;
          b2[j] = 1.0f - b0[j] - b1[j];
        }
        int32_t i00[shading::kMaxSpanRun], i10[shading::kMaxSpanRun], i01[shading::kMaxSpanRun], i11[shading::kMaxSpanRun];
        float fa[shading::kMaxSpanRun], fb[shading::kMaxSpanRun];
        float r[shading::kMaxSpanRun], g[shading::kMaxSpanRun], b[shading::kMaxSpanRun], a[shading::kMaxSpanRun];
        for (int32_t wide = 0; wide < 2; ++wide) {
          std::fill(r, r + shading::kMaxSpanRun, 1.0f);
          std::fill(g, g + shading::kMaxSpanRun, 1.0f);
          std::fill(b, b + shading::kMaxSpanRun, 1.0f);
          std::fill(a, a + shading::kMaxSpanRun, 1.0f);
          const int32_t bad = wide ? shading::bilinearSetupWide(st, m, b0, b1, b2, i00, i10, i01, i11, fa, fb)
                                   : shading::bilinearSetup(st, m, b0, b1, b2, i00, i10, i01, i11, fa, fb);
          REQUIRE(bad == 0);  // reduced coordinates always fall in the closed forms' range
          if (wide) shading::bilinearBlendWide(tx.data(), lutv.data(), m, i00, i10, i01, i11, fa, fb, r, g, b, a);
          else shading::bilinearBlend(tx.data(), lutv.data(), m, i00, i10, i01, i11, fa, fb, r, g, b, a);
          for (int32_t j = 0; j < m; ++j) {
            const float u = st.u0 * b0[j] + st.u1 * b1[j] + st.u2 * b2[j], v = st.v0 * b0[j] + st.v1 * b1[j] + st.v2 * b2[j];
            const rast::float4 want = rast::float4{1.0f, 1.0f, 1.0f, 1.0f} * sampleBilinear(t, T, L, u, v);
            INFO("wrap " << ms << "/" << mt << ", u = " << u << ", v = " << v << ", wide " << wide);
            REQUIRE(floatBits(r[j]) == floatBits(want.x));
            REQUIRE(floatBits(g[j]) == floatBits(want.y));
            REQUIRE(floatBits(b[j]) == floatBits(want.z));
            REQUIRE(floatBits(a[j]) == floatBits(want.w));
            ++checked;
          }
        }
      }
    }
  CHECK(checked > 10000);
}

TEST_CASE("textured frames with texture coordinates outside 0..1 shade the same colours in spans", "[cpu-paths]") {
  // A floor whose texture coordinates run from -2.3 to 3.6, seen in
  // perspective, with every pair of wrap modes: the span kernel (fused binned
  // raster and the visibility-buffer spans) against one pixel per work item,
  // colour for colour to the bit. The floor is a grid of small triangles at
  // the back and large ones at the front, so that a tile's short runs are
  // shaded in batches across rows and long ones as row spans.
  std::vector<rast::float3> p;
  std::vector<rast::float2> uv;
  std::vector<uint32_t> idx;
  const int N = 24;
  for (int j = 0; j <= N; ++j)
    for (int i = 0; i <= N; ++i) {
      const float fx = float(i) / N, fz = float(j) / N;
      p.push_back({-1.0f + 2.0f * fx, 0.0f, -1.0f - 5.0f * fz * fz});  // rows bunch up towards the front
      uv.push_back({-2.3f + 5.9f * fx, -1.7f + 4.6f * fz});
    }
  for (int j = 0; j < N; ++j)
    for (int i = 0; i < N; ++i) {
      const uint32_t a = uint32_t(j * (N + 1) + i), b = a + 1, c = a + N + 1, d = c + 1;
      idx.insert(idx.end(), {a, b, d, a, d, c});
    }
  Scene s = trianglesScene(p, idx, &uv);
  Texture tex;
  tex.width = 7;
  tex.height = 5;
  for (int i = 0; i < tex.width * tex.height; ++i)
    tex.rgba.push_back(uint32_t(29 * i + 11) % 256 | (uint32_t(97 * i + 5) % 256) << 8 | (uint32_t(53 * i) % 256) << 16 | 0xff000000u);
  s.textures.push_back(tex);
  s.materials[0].texture = 0;
  Camera cam;
  cam.eye = {0.2, 0.9, 0.3};
  cam.target = {0, 0, -3};
  cam.znear = 0.1;
  cam.zfar = 50;
  const int32_t modes[3] = {int32_t(WrapRepeat), int32_t(WrapClamp), int32_t(WrapMirror)};
  for (int32_t ms : modes)
    for (int32_t mt : modes) {
      s.textures[0].wrapS = ms;
      s.textures[0].wrapT = mt;
      RenderSettings rs;
      rs.width = 203;
      rs.height = 97;
      testHooks().shadeRun = 1;
      const Frame ref = renderFrame(s, cam, rs);
      size_t covered = 0;
      for (uint32_t id : ref.ids) covered += id != 0;
      REQUIRE(covered > size_t(rs.width) * rs.height / 4);
      for (RasterMethod method : {RasterMethod::Binned, RasterMethod::VisBuffer}) {
        testHooks().shadeRun = 0;
        rs.raster = method;
        const Frame f = renderFrame(s, cam, rs);
        INFO("wrap " << ms << "/" << mt << ", " << toString(method));
        REQUIRE(f.ids == ref.ids);
        REQUIRE(f.depth == ref.depth);
        CHECK(f.color == ref.color);
      }
    }
}


TEST_CASE("the GPU's primitive setup, run on the host, gives the host's images", "[cpu-paths]") {
  // A scene of one chunk of 256 triangles, of a few and of a few hundred (the
  // look-back: each team waits for the totals of the chunks before it), of
  // many (a count pass first), and scenes with clipped triangles; teams of one thread
  // (several teams wait on each other at once) and of several (the team's
  // scans and copies split between threads). Also the host's own setup with
  // a buffer of 3 staged triangles (nearly every chunk fills it, waits for
  // its place and writes the rest directly), with 1, and with and without
  // streaming stores.
  struct Case {
    std::string name;
    Scene scene;
    Camera cam;
  };
  std::vector<Case> cases;
  for (const char* spec : {"builtin:default", "builtin:tiny?n=4000", "builtin:tiny?n=140000", "builtin:nearplane",
                           "builtin:bigtri", "builtin:tiny?n=60000"}) {
    Scene s = builtinScene(spec);
    const Camera cam = defaultCamera(s);
    cases.push_back({spec, std::move(s), cam});
  }
  REQUIRE(cases[1].scene.triangleCount() > 2 * 256);  // a few chunks
  REQUIRE(cases[1].scene.triangleCount() <= kSetupLookBackMaxChunks * 256);
  REQUIRE(cases[2].scene.triangleCount() > kSetupLookBackMaxChunks * 256);  // many
  REQUIRE(cases[5].scene.triangleCount() > 200 * 256);  // a long look-back (engine's 475 chunks take it)
  REQUIRE(cases[5].scene.triangleCount() <= kSetupLookBackMaxChunks * 256);
  // A grid seen from just above it, the near plane cutting a row of visible
  // triangles: dozens of clipped triangles in a chunk whose pieces are drawn
  // (elsewhere, clipped triangles yield no piece, or one chunk a handful),
  // with the look-back (n=100) and after a count pass (n=400).
  for (const char* spec : {"builtin:grid?n=100", "builtin:grid?n=400"}) {
    Camera cam;
    cam.eye = {0, -0.9, 0.03};
    cam.target = {0, 1, 0.03};
    cam.up = {0, 0, 1};
    cam.fovyDeg = 90;
    cam.znear = 0.1;
    cam.zfar = 10;
    cases.push_back({std::string(spec) + ", near plane across", builtinScene(spec), cam});
  }
  REQUIRE(cases[6].scene.triangleCount() <= kSetupLookBackMaxChunks * 256);
  REQUIRE(cases[7].scene.triangleCount() > kSetupLookBackMaxChunks * 256);
  const std::string sh = sharedDir();
  if (!sh.empty() && fileExists(sh + "/models/cow.glb")) {  // a few chunks of a model, the eye inside it
    Scene cow = loadGltf(sh + "/models/cow.glb");
    Camera cam = autoFrame(cow);
    cam.eye = cam.target + (cam.eye - cam.target) * 0.02;
    cases.push_back({"cow, eye inside", std::move(cow), cam});
  }
  const int most = std::min(4, int(Exec().concurrency()));
  for (const Case& c : cases) {
    for (RasterMethod m : {RasterMethod::VisBuffer, RasterMethod::Binned}) {
      RenderSettings rs;
      rs.width = 320;
      rs.height = 180;
      rs.raster = m;
      // The GPU's setup first, the reference last: a renderer's buffers
      // often reuse the memory of the one before, and a raster triangle the
      // setup failed to write would still hold the reference's copy.
      const int teams[2] = {1, most};
      std::vector<Frame> gpu;
      std::vector<std::string> what;
      for (int team : teams) {
        testHooks().gpuSetupOnHostTeam = team;
        gpu.push_back(renderFrame(c.scene, c.cam, rs));
        what.push_back("the GPU's setup, teams of " + std::to_string(team));
      }
      testHooks().gpuSetupOnHostTeam = 0;
      const std::pair<int, int> hostSetups[] = {{3, 1}, {1, -1}, {0, 1}};  // staged, stream
      for (const std::pair<int, int>& host : hostSetups) {
        testHooks().hostSetupStaged = host.first, testHooks().hostSetupStream = host.second;
        gpu.push_back(renderFrame(c.scene, c.cam, rs));
        what.push_back("the host's setup staging " + std::to_string(host.first) + (host.second > 0 ? ", streamed" : ""));
      }
      testHooks().hostSetupStaged = 0, testHooks().hostSetupStream = -1;
      const Frame ref = renderFrame(c.scene, c.cam, rs);
      size_t covered = 0;
      for (uint32_t id : ref.ids) covered += id != 0;
      CHECK(covered > 0);
      for (size_t k = 0; k < gpu.size(); ++k) {
        INFO(c.name << ", " << toString(m) << ", " << what[k]);
        const Frame& f = gpu[k];
        CHECK(f.stats.rasterTris == ref.stats.rasterTris);
        CHECK(f.stats.rasterWork == ref.stats.rasterWork);
        REQUIRE(f.ids == ref.ids);
        REQUIRE(f.depth == ref.depth);
        CHECK(f.color == ref.color);
      }
    }
  }
}

TEST_CASE("the visbuffer raster with a block's rows on lanes gives the same keys", "[cpu-paths][visbuffer]") {
  // RasterBlockRows (raster_visbuffer.cpp) runs on GPUs under `auto` for
  // frames of large triangles; forced here on any backend, against the
  // lane-per-block layout: large and small triangles, small boxes that
  // straddle blocks, clipped triangles, layers with and without the occluder
  // pass (explicit visbuffer runs it; auto does not at these sizes), and
  // moving frames of one renderer (the block bounds and tags it keeps).
  struct Case {
    std::string name;
    Scene scene;
    Camera cam;
  };
  std::vector<Case> cases;
  for (const char* spec : {"builtin:default", "builtin:bigtri", "builtin:tiny?n=20000", "builtin:nearplane",
                           "builtin:overdraw?layers=16", "builtin:slivers", "builtin:zfight"}) {
    Scene s = builtinScene(spec);
    const Camera cam = defaultCamera(s);
    cases.push_back({spec, std::move(s), cam});
  }
  const std::string sh = sharedDir();
  if (!sh.empty() && fileExists(sh + "/models/milktruck.glb")) {  // the benchmark's view from the cab
    cases.push_back({"milktruck, from the cab", loadGltf(sh + "/models/milktruck.glb"), milktruckCabCamera()});
  }
  for (const Case& c : cases) {
    for (RasterMethod m : {RasterMethod::VisBuffer, RasterMethod::Auto}) {
      RenderSettings rs;
      rs.width = 333;  // not a multiple of the 8x8 blocks
      rs.height = 187;
      rs.raster = m;
      rs.wantPrimId = true;
      rs.wantDepth = true;
      Renderer lanes(c.scene), blocks(c.scene);
      for (int frame = 0; frame < 3; ++frame) {
        Camera cam = c.cam;
        cam.eye = cam.target + (cam.eye - cam.target) * (1.0 - 0.15 * frame);  // a moving camera
        testHooks().rowLanes = 1;
        const FrameStats a = lanes.render(cam, rs);
        testHooks().rowLanes = -1;
        const FrameStats b = blocks.render(cam, rs);
        INFO(c.name << ", " << toString(m) << ", frame " << frame);
        if (a.method != RasterMethod::VisBuffer) continue;  // auto chose another method
        CHECK(a.rowLanes);
        CHECK_FALSE(b.rowLanes);
        const std::vector<uint32_t> ids = lanes.primIdsBottomUp();
        size_t covered = 0;
        for (uint32_t id : ids) covered += id != 0;
        CHECK(covered > 0);
        REQUIRE(ids == blocks.primIdsBottomUp());
        REQUIRE(lanes.depthBottomUp() == blocks.depthBottomUp());
        CHECK(lanes.colorTopDown() == blocks.colorTopDown());
      }
    }
  }
}
