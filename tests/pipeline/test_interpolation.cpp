// Perspective-correct interpolation against an analytic reference, and texture
// sampling (nearest, bilinear, wrap modes) against hand-computed values.
#include <catch2/catch.hpp>

#include "pipeline/shade/texture_sampling.h"
#include "tests/support/test_support.h"

#include <cmath>

using namespace rast;
using namespace rast::test;

namespace {

// The texture coordinates of the plane y = 0 at world (x, z), as the test quad maps them.
glm::dvec2 planeUV(double x, double z) { return {(x + 1.0) / 2.0 * 0.99, (z + 1.0) / -7.0 * 0.99}; }

}  // namespace

TEST_CASE("attributes are interpolated perspective-correctly", "[interp]") {
  const int W = 160, H = 120;
  // A floor quad x in [-1, 1], z in [-8, -1], seen at a grazing angle.
  std::vector<rast::float3> p = {{-1, 0, -1}, {1, 0, -1}, {1, 0, -8}, {-1, 0, -8}};
  std::vector<rast::float2> uv;
  for (const rast::float3& v : p) {
    const glm::dvec2 t = planeUV(v.x, v.z);
    uv.push_back({float(t.x), float(t.y)});
  }
  Scene s = trianglesScene(p, {0, 1, 2, 0, 2, 3}, &uv);
  s.textures.push_back(Texture{1, 1, {0xffffffffu}});  // any texture: makes the uv stream travel
  s.materials[0].texture = 0;
  Camera cam;
  cam.eye = {0, 0.6, 0};
  cam.target = {0, 0, -3};
  cam.znear = 0.1;
  cam.zfar = 50;
  RenderSettings rs;
  rs.width = W;
  rs.height = H;
  rs.shading = ShadingMode::TexCoord;
  const Frame f = renderFrame(s, cam, rs);

  const glm::dmat4 inv = glm::inverse(cam.projection(W, H) * cam.view());
  double maxErr = 0.0, maxAffineGap = 0.0;
  int checked = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      // Ray through the pixel centre, intersected with y = 0.
      const double nx = (x + 0.5) / W * 2 - 1, ny = (y + 0.5) / H * 2 - 1;
      glm::dvec4 a = inv * glm::dvec4(nx, ny, -1, 1), b = inv * glm::dvec4(nx, ny, 1, 1);
      const glm::dvec3 o = glm::dvec3(a) / a.w, d = glm::dvec3(b) / b.w - o;
      if (d.y >= 0) continue;
      const glm::dvec3 hit = o + d * (-o.y / d.y);
      // Stay a pixel's footprint away from the quad's border.
      if (std::abs(hit.x) > 0.95 || hit.z > -1.1 || hit.z < -7.6) continue;
      const uint32_t id = f.id(x, y);
      REQUIRE(id != 0);
      const uint32_t c = f.color[size_t(H - 1 - y) * W + x];
      const glm::dvec2 want = planeUV(hit.x, hit.z);
      const double gotU = (c & 0xff) / 255.0, gotV = ((c >> 8) & 0xff) / 255.0;
      maxErr = std::max({maxErr, std::abs(gotU - want.x), std::abs(gotV - want.y)});
      // What screen-space (affine) interpolation would give: v linear in window y
      // between the quad's near and far edges.
      const glm::dvec4 cn = cam.projection(W, H) * cam.view() * glm::dvec4(0, 0, -1, 1);
      const glm::dvec4 cf = cam.projection(W, H) * cam.view() * glm::dvec4(0, 0, -8, 1);
      const double yn = (cn.y / cn.w * 0.5 + 0.5) * H, yf = (cf.y / cf.w * 0.5 + 0.5) * H;
      const double affineV = 0.99 * (y + 0.5 - yn) / (yf - yn);
      maxAffineGap = std::max(maxAffineGap, std::abs(affineV - want.y));
      ++checked;
    }
  CHECK(checked > 3000);
  // 8-bit output: half a step of rounding plus float interpolation error.
  CHECK(maxErr < 1.5 / 255.0);
  // The view is steep enough that affine interpolation would be far off.
  CHECK(maxAffineGap > 0.1);
}

namespace {

struct HostTexels {
  const std::vector<uint32_t>* t;
  uint32_t operator()(uint32_t i) const { return (*t)[i]; }
};
struct IdentityLut {  // byte -> byte/255: makes hand computation easy
  float operator()(uint32_t b) const { return float(b) / 255.0f; }
};

uint32_t grey(int v) { return uint32_t(v) | uint32_t(v) << 8 | uint32_t(v) << 16 | 0xff000000u; }

}  // namespace

TEST_CASE("nearest and bilinear sampling with every wrap mode", "[texture]") {
  // 2x2 texture, first row = top: [0, 100; 200, 255] (grey levels).
  const std::vector<uint32_t> texels = {grey(0), grey(100), grey(200), grey(255)};
  const HostTexels T{&texels};
  const IdentityLut L;
  TextureGPU t{0, 2, 2, WrapRepeat, WrapRepeat, 1, 9729, 9987};
  auto g = [](rast::float4 c) { return double(c.x) * 255.0; };

  SECTION("nearest picks the texel containing the coordinate") {
    CHECK(g(sampleNearest(t, T, L, 0.25f, 0.25f)) == Approx(0));
    CHECK(g(sampleNearest(t, T, L, 0.75f, 0.25f)) == Approx(100));
    CHECK(g(sampleNearest(t, T, L, 0.25f, 0.75f)) == Approx(200));
    CHECK(g(sampleNearest(t, T, L, 0.75f, 0.75f)) == Approx(255));
    CHECK(g(sampleNearest(t, T, L, 1.25f, -0.25f)) == Approx(200));  // repeat: (0.25, 0.75)
  }
  SECTION("bilinear at texel centres returns the texel, between them the average") {
    CHECK(g(sampleBilinear(t, T, L, 0.25f, 0.25f)) == Approx(0).margin(1e-3));
    CHECK(g(sampleBilinear(t, T, L, 0.75f, 0.75f)) == Approx(255).margin(1e-3));
    CHECK(g(sampleBilinear(t, T, L, 0.5f, 0.25f)) == Approx(50).margin(1e-3));
    CHECK(g(sampleBilinear(t, T, L, 0.5f, 0.5f)) == Approx((0 + 100 + 200 + 255) / 4.0).margin(1e-3));
    // 1/8 of a texel right of centre (0.25 + 0.0625): 0.875*0 + 0.125*100
    CHECK(g(sampleBilinear(t, T, L, 0.3125f, 0.25f)) == Approx(12.5).margin(1e-3));
  }
  SECTION("repeat wraps across the border") {
    // u = 0 lies between texel 1 (wrapped) and texel 0: average of 100 and 0 on the top row.
    CHECK(g(sampleBilinear(t, T, L, 0.0f, 0.25f)) == Approx(50).margin(1e-3));
  }
  SECTION("clamp to edge repeats the border texel") {
    t.wrapS = t.wrapT = WrapClamp;
    CHECK(g(sampleBilinear(t, T, L, 0.0f, 0.25f)) == Approx(0).margin(1e-3));
    CHECK(g(sampleBilinear(t, T, L, 1.0f, 0.25f)) == Approx(100).margin(1e-3));
    CHECK(g(sampleNearest(t, T, L, 7.0f, -3.0f)) == Approx(100));
  }
  SECTION("mirrored repeat reflects every other period") {
    t.wrapS = t.wrapT = WrapMirror;
    CHECK(g(sampleNearest(t, T, L, 1.25f, 0.25f)) == Approx(100));  // mirrored: 0.75
    CHECK(g(sampleNearest(t, T, L, 2.25f, 0.25f)) == Approx(0));    // period 2: back to 0.25
    CHECK(g(sampleNearest(t, T, L, -0.25f, 0.25f)) == Approx(0));   // mirror of 0.25
    // At u = 1 the mirrored neighbour of texel 1 is texel 1 itself.
    CHECK(g(sampleBilinear(t, T, L, 1.0f, 0.25f)) == Approx(100).margin(1e-3));
  }
  SECTION("non-finite and huge coordinates stay inside the texture") {
    CHECK(g(sampleNearest(t, T, L, std::nanf(""), 0.25f)) == Approx(0));
    CHECK(g(sampleBilinear(t, T, L, 3.0e9f, 0.25f)) >= 0.0);
  }
}

TEST_CASE("sRGB decode and encode round-trip every byte", "[texture]") {
  // The decode table of the device scene and the encoder of the shade stage.
  Scene s = trianglesScene({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {0, 1, 2});
  const DeviceScene d = DeviceScene::upload(s);
  auto lut = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), d.srgbToLinear);
  const auto packed = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), d.srgbEncodePacked);
  auto enc = [&](float c) { return encodeSrgb8Packed(c, packed.data()); };
  for (uint32_t b = 0; b < 256; ++b) {
    REQUIRE(linearToSrgb8(lut(b)) == b);
    REQUIRE(enc(lut(b)) == b);
  }
  // The table encoder rounds like the formula everywhere (up to powf's last
  // bit at the 255 decision points).
  int differ = 0;
  for (int i = 0; i <= 100000; ++i) {
    const float c = float(i) / 100000.0f;
    differ += enc(c) != linearToSrgb8(c);
  }
  CHECK(differ <= 2);
  CHECK(enc(-1.0f) == 0);
  CHECK(enc(2.0f) == 255);
  CHECK(enc(std::nanf("")) == 0);
  CHECK(lut(128) == Approx(0.2158605).epsilon(1e-5));
}

namespace {

// An 8x8 texture (CLAMP_TO_EDGE) with its three further levels, each level a
// grey ramp along x of its own slope, so that every level and every texel
// rule gives another value: level 0 texel x = 30 x, level 1 = 5 + 50 x,
// level 2 = 100 + 50 x, level 3 = 128.
struct MipRamp {
  std::vector<uint32_t> texels;
  MipRamp() {
    const int slope[4] = {30, 50, 50, 0}, base[4] = {0, 5, 100, 128};
    for (int l = 0, n = 8; l < 4; ++l, n /= 2)
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) texels.push_back(grey(base[l] + slope[l] * x));
  }
  TextureGPU texture(int32_t minFilter) const { return {0, 8, 8, WrapClamp, WrapClamp, 4, 9729, minFilter}; }
};

}  // namespace

TEST_CASE("anisotropic filtering follows the GL footprint and level of detail", "[texture][aniso]") {
  // EXT_texture_filter_anisotropic (core in OpenGL 4.6, section 8.14): Pmax and
  // Pmin the lengths in texels of the footprint's longer and shorter sides,
  // N = min(ceil(Pmax / Pmin), maxAniso) taps, lambda' = log2(Pmax / N).
  auto fp = [](float px, float py, int32_t maxAniso) { return anisoFootprint(px * px, py * py, maxAniso); };
  CHECK(fp(8, 1, 16).taps == 8);
  CHECK(fp(8, 1, 16).lod == Approx(0.0).margin(1e-6));
  CHECK(fp(8, 3, 16).taps == 3);
  CHECK(fp(8, 3, 16).lod == Approx(std::log2(8.0 / 3.0)).margin(1e-5));
  CHECK(fp(8, 7.9f, 16).taps == 2);  // ceil: a footprint barely longer than wide takes 2 taps, a level finer
  CHECK(fp(8, 7.9f, 16).lod == Approx(2.0).margin(1e-5));
  CHECK(fp(5, 5, 16).taps == 1);
  CHECK(fp(5, 5, 16).lod == Approx(std::log2(5.0)).margin(1e-5));
  CHECK(fp(64, 1, 16).taps == 16);  // the ratio clamped to maxAniso
  CHECK(fp(64, 1, 16).lod == Approx(2.0).margin(1e-5));
  CHECK(fp(1, 64, 16).taps == 16);  // either side
  CHECK(fp(64, 1, 4).taps == 4);
  CHECK(fp(64, 1, 4).lod == Approx(4.0).margin(1e-5));
  CHECK(fp(4, 0, 16).taps == 16);  // a degenerate side: the most taps
  // The isotropic level of detail: log2 of the longer side's length (not of its components).
  CHECK(textureLod(3.0f / 8, 4.0f / 8, 0.0f, 1.0f / 8, 8, 8) == Approx(std::log2(5.0)).margin(1e-5));
  CHECK(textureLod(0.0f, 1.0f / 8, 2.0f / 8, 0.0f, 8, 8) == Approx(1.0).margin(1e-6));

  const MipRamp ramp;
  const HostTexels T{&ramp.texels};
  const IdentityLut L;
  auto g = [](rast::float4 c) { return double(c.x) * 255.0; };
  const float u = 3.76f / 8, v = 0.4f;
  auto tapsMean = [&](auto sampleAt, rast::float2 axis, int n) {
    double acc = 0.0;
    for (int i = 0; i < n; ++i) {
      const float s = (float(i) + 0.5f) / float(n) - 0.5f;
      acc += g(sampleAt(u + axis.x * s, v + axis.y * s));
    }
    return acc / n;
  };

  SECTION("magnified by lambda': every tap takes the magnification filter at level 0") {
    // Pmax = 4 texels, Pmin = 0.5: 8 taps at lambda' = -1. Minified by the
    // isotropic lambda = 2, but magnified by lambda': the sampler's LINEAR
    // magnification, not NEAREST_MIPMAP_LINEAR's nearest texel.
    const TextureGPU t = ramp.texture(9986);
    const rast::float2 dx{4.0f / 8, 0.0f}, dy{0.0f, 0.5f / 8};
    const double linear = tapsMean([&](float a, float b) { return sampleBilinear(t, T, L, a, b); }, dx, 8);
    const double nearest = tapsMean([&](float a, float b) { return sampleNearest(t, T, L, a, b); }, dx, 8);
    CHECK(linear == Approx(30.0 * (3.76 - 0.5)).margin(1e-3));  // the ramp at the centre
    CHECK(std::fabs(linear - nearest) > 5.0);                   // the two rules differ here
    CHECK(g(sampleSampler(t, T, L, u, v, dx, dy, 16)) == Approx(linear).margin(1e-3));
  }
  SECTION("minified: the taps at lambda' along the longer side") {
    // Pmax = 8 texels (along y this time), Pmin = 2: 4 taps at level 1 exactly.
    const TextureGPU t = ramp.texture(9987);
    const rast::float2 dx{2.0f / 8, 0.0f}, dy{0.0f, 8.0f / 8};
    const TextureGPU l1 = mipLevel(t, 1);
    const double expect = tapsMean([&](float a, float b) { return sampleBilinear(l1, T, L, a, b); }, dy, 4);
    CHECK(g(sampleSampler(t, T, L, u, v, dx, dy, 16)) == Approx(expect).margin(1e-3));
    // Without anisotropy: one tap at lambda = log2(8) = 3, the last level.
    CHECK(g(sampleSampler(t, T, L, u, v, dx, dy, 1)) == Approx(128.0).margin(1e-3));
  }
  SECTION("NEAREST_MIPMAP_NEAREST picks level ceil(lambda + 1/2) - 1") {
    const TextureGPU t = ramp.texture(9984);
    // lambda = 0.5 exactly (a side of sqrt(2) texels): level 0, whose nearest texel is x = 3.
    CHECK(g(sampleSampler(t, T, L, u, v, rast::float2{1.0f / 8, 1.0f / 8}, rast::float2{0.0f, 0.0f}, 1)) == Approx(90.0));
    // lambda = log2(1.5) = 0.58: level 1, texel x = 1 (5 + 50).
    CHECK(g(sampleSampler(t, T, L, u, v, rast::float2{1.5f / 8, 0.0f}, rast::float2{0.0f, 0.0f}, 1)) == Approx(55.0));
  }
}
