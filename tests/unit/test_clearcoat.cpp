// KHR_materials_clearcoat under `--shading pbr` (#37), checked against the
// extension's formulas evaluated here in double precision, as
// test_pbr_shading.cpp checks the base model: a square facing the camera, lit
// along the view axis by a directional light, so that at the centre pixel
// N = V = L = H and the coat's terms have closed forms (its Fresnel weight
// is then f0 = 0.04). Each part has a case that fails without it: the layer
// itself, its factor and roughness and their textures (R and G), its normal
// map; a coat of 0 draws the bytes of no extension; a texture index that does
// not exist, or a factor out of range, is one clear error.
#include <catch2/catch.hpp>

#include "host/image/image_io.h"
#include "tests/unit/pbr_axis_square.h"

#include <cmath>

using namespace rast;
using namespace rast::loader_test;
using namespace rast::pbr_axis;
using Catch::Matchers::Contains;

namespace {

// The axis square with TEXCOORD_0 and material `material`, lit by a
// directional light of 1 lux shining along -z; the textures' images are the
// files `images` (one texture each).
Doc litSquare(const json& material, const std::vector<std::string>& images = {}) {
  const json sun = {{"type", "directional"}, {"intensity", 1.0}};
  Doc doc = square(material, &sun, {{"translation", {0, 0, 5}}}, true);
  doc.j["extensionsUsed"].push_back("KHR_materials_clearcoat");
  for (size_t k = 0; k < images.size(); ++k) {
    doc.j["textures"].push_back({{"source", int(k)}});
    doc.j["images"].push_back({{"uri", images[k]}});
  }
  return doc;
}

// A white dielectric of roughness 1 with the coat `coat` (none when null).
json coated(const json* coat) {
  json m = {{"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 0.0}, {"roughnessFactor", 1.0}}}};
  if (coat) m["extensions"] = {{"KHR_materials_clearcoat", *coat}};
  return m;
}

// The centre pixel's red channel, linear (decoded from the 8-bit sRGB image).
double centre(const Scene& s) { return centreLinear(axisFrame(s)).x; }

// At N = V = L = H under 1 lux: the white base (Appendix B, roughness 1) and
// the coat's GGX lobe (visibility 1/4, D = 1 / (pi a^2), a = roughness^2),
// mixed by factor x Fresnel, which is f0 = 0.04 at normal incidence.
double baseAxis() {
  const double D = 1.0 / kPi, specular = 0.25 * D;
  return (1.0 / kPi) * (1.0 - 0.04) + specular * 0.04;
}
double coatAxis(double factor, double roughness) {
  const double a = roughness * roughness, D = 1.0 / (kPi * a * a), w = factor * 0.04;
  return baseAxis() * (1.0 - w) + 0.25 * D * w;
}

}  // namespace

TEST_CASE("clearcoat: a second GGX layer over the base, weighted by factor x Fresnel", "[pbr][clearcoat]") {
  TempDir d;
  near(centre(loadDoc(litSquare(coated(nullptr)), d, "none")), baseAxis());
  const json full = {{"clearcoatFactor", 1.0}, {"clearcoatRoughnessFactor", 0.5}};
  const double got = centre(loadDoc(litSquare(coated(&full)), d, "full"));
  near(got, coatAxis(1.0, 0.5));
  CHECK(got > baseAxis() * 1.05);  // the layer's highlight: not the base alone
  const json half = {{"clearcoatFactor", 0.5}, {"clearcoatRoughnessFactor", 0.5}};
  near(centre(loadDoc(litSquare(coated(&half)), d, "half")), coatAxis(0.5, 0.5));
  const json rough = {{"clearcoatFactor", 1.0}, {"clearcoatRoughnessFactor", 0.8}};
  near(centre(loadDoc(litSquare(coated(&rough)), d, "rough")), coatAxis(1.0, 0.8));
}

TEST_CASE("clearcoat: a coat of 0 draws the bytes of no coat", "[pbr][clearcoat]") {
  TempDir d;
  const std::vector<uint32_t> none = axisFrame(loadDoc(litSquare(coated(nullptr)), d, "none")).color;
  const json zero = {{"clearcoatFactor", 0.0}, {"clearcoatRoughnessFactor", 0.3}};
  CHECK(axisFrame(loadDoc(litSquare(coated(&zero)), d, "zero")).color == none);
  // A coat whose texture's R is 0 everywhere: the coat's instance, the base's bytes.
  writePng(d.file("black.png"), 1, 1, {0xff000000u});
  const json masked = {{"clearcoatFactor", 1.0}, {"clearcoatRoughnessFactor", 0.5}, {"clearcoatTexture", {{"index", 0}}}};
  CHECK(axisFrame(loadDoc(litSquare(coated(&masked), {"black.png"}), d, "masked")).color == none);
}

TEST_CASE("clearcoat: factor x texture R, roughness x texture G, the coat's normal map", "[pbr][clearcoat]") {
  TempDir d;
  // R = 0x80 (0.502): half a coat; G = 0x80: roughness 1 x 0.502.
  writePng(d.file("rg.png"), 1, 1, {0xff008080u});
  const double half = 128.0 / 255.0;
  const json byR = {{"clearcoatFactor", 1.0}, {"clearcoatRoughnessFactor", 0.5}, {"clearcoatTexture", {{"index", 0}}}};
  near(centre(loadDoc(litSquare(coated(&byR), {"rg.png"}), d, "r")), coatAxis(half, 0.5));
  const json byG = {{"clearcoatFactor", 1.0}, {"clearcoatRoughnessFactor", 1.0},
                    {"clearcoatRoughnessTexture", {{"index", 0}}}};
  near(centre(loadDoc(litSquare(coated(&byG), {"rg.png"}), d, "g")), coatAxis(1.0, half));
  // A coat normal map tilted 90 degrees towards +u: the coat faces away from
  // light and viewer, its Fresnel weight near 1 hides the base, its lobe
  // reflects nothing back; a flat map changes nothing; scale 0 flattens the tilt.
  writePng(d.file("tilt.png"), 1, 1, {0xff8080ffu});  // (255, 128, 128): x = 1
  writePng(d.file("flat.png"), 1, 1, {0xffff8080u});  // (128, 128, 255): z = 1
  const json tilt = {{"clearcoatFactor", 1.0}, {"clearcoatRoughnessFactor", 0.5}, {"clearcoatNormalTexture", {{"index", 0}}}};
  CHECK(centre(loadDoc(litSquare(coated(&tilt), {"tilt.png"}), d, "tilt")) < 0.03);
  near(centre(loadDoc(litSquare(coated(&tilt), {"flat.png"}), d, "flat")), coatAxis(1.0, 0.5));
  const json flatten = {{"clearcoatFactor", 1.0}, {"clearcoatRoughnessFactor", 0.5},
                        {"clearcoatNormalTexture", {{"index", 0}, {"scale", 0.0}}}};
  near(centre(loadDoc(litSquare(coated(&flatten), {"tilt.png"}), d, "flatten")), coatAxis(1.0, 0.5));
}

TEST_CASE("clearcoat: bad values and texture indices are refused in one line", "[pbr][clearcoat]") {
  TempDir d;
  auto bad = [&](const json& coat, const char* message) {
    INFO(coat.dump());
    CHECK_THAT(docError(litSquare(coated(&coat)), d, "bad"), Contains(message));
  };
  bad({{"clearcoatFactor", 1.5}}, "KHR_materials_clearcoat: clearcoatFactor must be a number in [0, 1]");
  bad({{"clearcoatFactor", 1.0}, {"clearcoatRoughnessFactor", -0.1}}, "clearcoatRoughnessFactor must be a number in [0, 1]");
  bad({{"clearcoatFactor", 1.0}, {"clearcoatTexture", {{"index", 3}}}},
      "materials[0] KHR_materials_clearcoat: clearcoatTexture.index 3 does not exist (the file has 0 textures)");
  bad({{"clearcoatFactor", 1.0}, {"clearcoatNormalTexture", {{"index", "one"}}}}, "clearcoatNormalTexture.index must be an integer");
  bad({{"clearcoatFactor", 1.0}, {"clearcoatRoughnessTexture", 2}}, "clearcoatRoughnessTexture must be an object");
  bad({{"clearcoatFactor", "much"}}, "clearcoatFactor must be a finite number");
}
