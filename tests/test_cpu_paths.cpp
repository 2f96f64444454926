// The CPU's fast paths give the images of the general ones (issue #11):
// * the sRGB encoder's bucket lookup returns the byte of a binary search over
//   the same 256 thresholds, for every kind of input;
// * shading in runs (per-triangle lookups kept along a row) and the span
//   kernel (core/shade_spans.h) give the ids, depth and colours of one pixel
//   per work item (RenderSettings::shadeRun = 1), on scenes that exercise
//   textures, vertex colours, lights, lines, background and the float film;
// * the host fine raster of the binned method matches the other methods on
//   ids and depth bit for bit (also covered by the stability suite), here on
//   textured models seen whole.
#include <catch2/catch.hpp>

#include "core/color.h"
#include "core/device_scene.h"
#include "core/gltf_loader.h"
#include "models/procedural.h"
#include "test_support.h"

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
  rs.shadeRun = 1;
  const Frame ref = renderFrame(s, cam, rs);
  for (int run : {0, 7, 64}) {
    for (RasterMethod m : {RasterMethod::Binned, RasterMethod::VisBuffer}) {
      rs.shadeRun = run;
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
