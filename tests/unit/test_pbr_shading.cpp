// The glTF material model under `--shading pbr` (#37), checked pixel by pixel
// against the specification's formulas evaluated here independently in
// double precision: a square facing the camera, lit along the view axis, so
// that at the centre pixel N = V = L = H and every term of Appendix B's BRDF
// has a closed form. Each property has a case that fails without it: the
// metal/dielectric mix, roughness, the metallicRoughness texture's channels,
// emission and its strength, unlit, the lights' falloff, range window and
// spot cone, single- and double-sided faces, normal maps and their tangent
// frame (the file's TANGENT, its handedness, a mirroring node, generated),
// each texture's own texCoord set and transform, and the mipmaps of colour
// (averaged in linear light) and data textures (averaged as stored).
#include <catch2/catch.hpp>

#include "host/image/image_io.h"
#include "tests/unit/pbr_axis_square.h"

#include <cmath>

using namespace rast;
using namespace rast::loader_test;
using namespace rast::pbr_axis;
using Catch::Matchers::Contains;

namespace {

using pbr_axis::near;

// The centre pixel's colour, linear, seen from `eye`.
rast::float3 centre(const Scene& s, const glm::dvec3& eye = {0, 0, 3}) { return centreLinear(axisFrame(s, eye)); }

void near(const rast::float3& got, double r, double g, double b) {
  near(got.x, r);
  near(got.y, g);
  near(got.z, b);
}

// Appendix B at N = V = L = H (all cosines 1) under irradiance E: the
// dielectric (f0 0.04) and metal (f0 = base) lobes mixed by `metal`.
double brdfAxis(double base, double metal, double rough, double E) {
  const double a = rough * rough;
  const double D = 1.0 / (kPi * a * a);  // a^2 / (pi (NdotH^2 (a^2 - 1) + 1)^2) at NdotH = 1
  const double specular = 0.25 * D;       // visibility 1 / (4 NdotL NdotV) = 1/4
  const double diffuse = base / kPi;
  const double dielectric = diffuse * (1.0 - 0.04) + specular * 0.04;
  const double metallic = base * specular;
  return E * (dielectric * (1.0 - metal) + metallic * metal);
}

const json kSun = {{"type", "directional"}, {"intensity", 1.0}};  // shines along its node's -Z: onto the square

json pbrMaterial(double r, double g, double b, double metal, double rough) {
  return {{"pbrMetallicRoughness", {{"baseColorFactor", {r, g, b, 1.0}}, {"metallicFactor", metal}, {"roughnessFactor", rough}}}};
}

}  // namespace

TEST_CASE("pbr: dielectric and metal lobes, roughness", "[pbr]") {
  TempDir d;
  const json kNode = {{"translation", {0, 0, 5}}};
  // A white rough dielectric, a coloured rough metal, a smoother dielectric.
  near(centre(loadDoc(square(pbrMaterial(1, 1, 1, 0, 1), &kSun, kNode), d, "a")), brdfAxis(1, 0, 1, 1),
       brdfAxis(1, 0, 1, 1), brdfAxis(1, 0, 1, 1));
  near(centre(loadDoc(square(pbrMaterial(1, 0.5, 0.25, 1, 1), &kSun, kNode), d, "b")), brdfAxis(1, 1, 1, 1),
       brdfAxis(0.5, 1, 1, 1), brdfAxis(0.25, 1, 1, 1));
  near(centre(loadDoc(square(pbrMaterial(0.5, 0.5, 0.5, 0, 0.6), &kSun, kNode), d, "c")), brdfAxis(0.5, 0, 0.6, 1),
       brdfAxis(0.5, 0, 0.6, 1), brdfAxis(0.5, 0, 0.6, 1));
  // Intensity scales linearly.
  json bright = kSun;
  bright["intensity"] = 2.5;
  near(centre(loadDoc(square(pbrMaterial(0.2, 0.2, 0.2, 0, 1), &bright, kNode), d, "e")).x, brdfAxis(0.2, 0, 1, 2.5));
}

TEST_CASE("pbr: emission, its strength, and unlit materials", "[pbr]") {
  TempDir d;
  const json kNode = {{"translation", {0, 0, 5}}};
  json m = pbrMaterial(0, 0, 0, 0, 1);  // black: only the specular 4% and the emission
  m["emissiveFactor"] = {0.25, 0.0, 0.0};
  near(centre(loadDoc(square(m, &kSun, kNode), d, "e1")).x, 0.25 + brdfAxis(0, 0, 1, 1));
  m["extensions"] = {{"KHR_materials_emissive_strength", {{"emissiveStrength", 3.0}}}};
  near(centre(loadDoc(square(m, &kSun, kNode), d, "e2")).x, 0.75 + brdfAxis(0, 0, 1, 1));
  // Unlit: the base colour itself, whatever the light.
  json u = pbrMaterial(0.3, 0.6, 0.9, 1, 0.2);
  u["extensions"] = {{"KHR_materials_unlit", json::object()}};
  json strong = kSun;
  strong["intensity"] = 40.0;
  near(centre(loadDoc(square(u, &strong, kNode), d, "u")), 0.3, 0.6, 0.9);
}

TEST_CASE("pbr: point and spot lights fall off as KHR_lights_punctual says", "[pbr]") {
  TempDir d;
  const json m = pbrMaterial(1, 1, 1, 0, 1);
  // A point light 2 units in front: inverse square; with range 4, the window 1 - (d/r)^4.
  json point = {{"type", "point"}, {"intensity", 8.0}};
  const json at2 = {{"translation", {0, 0, 2}}};
  near(centre(loadDoc(square(m, &point, at2), d, "p")).x, brdfAxis(1, 0, 1, 8.0 / 4.0));
  point["range"] = 4.0;
  near(centre(loadDoc(square(m, &point, at2), d, "pr")).x, brdfAxis(1, 0, 1, 8.0 / 4.0 * (1.0 - std::pow(0.5, 4))));
  // A spot on the axis lights the centre fully; turned 60 degrees away
  // (outside its 45-degree outer cone), not at all; between the cones,
  // the squared linear ramp in cos(angle).
  json spot = {{"type", "spot"}, {"intensity", 8.0}, {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.6}}}};
  near(centre(loadDoc(square(m, &spot, at2), d, "s")).x, brdfAxis(1, 0, 1, 2.0));
  const double ang = 0.4, s = std::sin(ang / 2), c = std::cos(ang / 2);
  const json turned = {{"translation", {0, 0, 2}}, {"rotation", {s, 0, 0, c}}};
  const double t = (std::cos(ang) - std::cos(0.6)) / (std::cos(0.2) - std::cos(0.6));
  near(centre(loadDoc(square(m, &spot, turned), d, "s2")).x, brdfAxis(1, 0, 1, 2.0 * t * t));
  const json away = {{"translation", {0, 0, 2}}, {"rotation", {std::sin(0.5236), 0, 0, std::cos(0.5236)}}};
  near(centre(loadDoc(square(m, &spot, away), d, "s3")).x, 0.0);
}

TEST_CASE("pbr: single-sided back faces are culled, double-sided ones turn their normal", "[pbr]") {
  TempDir d;
  // Seen from behind (eye at -z), lit from behind.
  const json behind = {{"translation", {0, 0, -5}}, {"rotation", {0, 1, 0, 0}}};
  json m = pbrMaterial(1, 1, 1, 0, 1);
  const Scene single = loadDoc(square(m, &kSun, behind), d, "single");
  near(centre(single, {0, 0, -3}), 0, 0, 0);  // culled: the background
  m["doubleSided"] = true;
  near(centre(loadDoc(square(m, &kSun, behind), d, "double"), {0, 0, -3}).x, brdfAxis(1, 0, 1, 1));
  // The Lambert shading keeps drawing every face, as glref does.
  Camera cam;
  cam.eye = {0, 0, -3};
  RenderSettings rs;
  rs.width = rs.height = kSize;
  rs.shading = ShadingMode::Lambert;
  CHECK(test::renderFrame(single, cam, rs).ids[size_t(kSize / 2) * kSize + kSize / 2] != 0u);
}

TEST_CASE("pbr: metallicRoughness and normal textures", "[pbr]") {
  TempDir d;
  const json kNode = {{"translation", {0, 0, 5}}};
  // One texel each: metallic-roughness (G = roughness 0.6, B = metal 1), a
  // normal map tilted 90 degrees towards +u (tangent-space (1, 0, 0)), a flat one.
  writePng(d.file("mr.png"), 1, 1, {0xffff9900u});       // R 0, G 0x99 = 0.6, B 0xff
  writePng(d.file("tilt.png"), 1, 1, {0xff8080ffu});  // (255, 128, 128): x = 1
  writePng(d.file("flat.png"), 1, 1, {0xffff8080u});     // (128, 128, 255): z = 1
  auto textured = [&](const json& extra, const char* image, const json& base = pbrMaterial(1, 0.5, 0.25, 1, 1)) {
    json m = base;
    for (auto it = extra.begin(); it != extra.end(); ++it) {
      if (it.key() == "metallicRoughnessTexture") m["pbrMetallicRoughness"][it.key()] = it.value();
      else m[it.key()] = it.value();
    }
    Doc doc = square(m, &kSun, kNode, true);
    doc.j["textures"] = json::array({{{"source", 0}}});
    doc.j["images"] = json::array({{{"uri", image}}});
    return doc;
  };
  const rast::float3 mr = centre(loadDoc(textured({{"metallicRoughnessTexture", {{"index", 0}}}}, "mr.png"), d, "mr"));
  near(mr, brdfAxis(1, 1, 0.6, 1), brdfAxis(0.5, 1, 0.6, 1), brdfAxis(0.25, 1, 0.6, 1));
  // A white dielectric lit along the normal: a flat normal map changes
  // nothing; one that tilts the normal 90 degrees away from the light
  // leaves it dark (a grazing diffuse lobe and a 4% specular one).
  const json white = pbrMaterial(1, 1, 1, 0, 0.5);
  const rast::float3 flat = centre(loadDoc(textured({{"normalTexture", {{"index", 0}}}}, "flat.png", white), d, "flat"));
  near(flat.x, brdfAxis(1, 0, 0.5, 1));
  const rast::float3 tilt = centre(loadDoc(textured({{"normalTexture", {{"index", 0}}}}, "tilt.png", white), d, "tilt"));
  CHECK(tilt.x < 0.01f);
  // scale 0 flattens any map back to the surface normal.
  const json flatten = {{"normalTexture", {{"index", 0}, {"scale", 0.0}}}};
  near(centre(loadDoc(textured(flatten, "tilt.png", white), d, "z")).x, brdfAxis(1, 0, 0.5, 1));
}

TEST_CASE("pbr: mipmaps average colour textures in linear light and data textures as stored", "[pbr]") {
  TempDir d;
  const json kNode = {{"translation", {0, 0, 5}}};
  // Checkers of one texel, 256 wide, about ten texels a pixel on the square:
  // the glTF samplers' filter (LINEAR_MIPMAP_LINEAR) reads levels 3 and 4,
  // where the checks have become their average.
  const int n = 256;
  std::vector<uint32_t> metal(size_t(n) * n), bw(size_t(n) * n);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const bool on = (x + y) & 1;
      metal[size_t(y) * n + x] = 0xff00ff00u | (on ? 0x00ff0000u : 0u);  // G 255: roughness 1; B 0 or 255: metal
      bw[size_t(y) * n + x] = on ? 0xffffffffu : 0xff000000u;
    }
  writePng(d.file("metal.png"), n, n, metal);
  writePng(d.file("bw.png"), n, n, bw);
  auto render = [&](const char* slot, const char* image, const json& base, const char* name) {
    json m = base;
    m["pbrMetallicRoughness"][slot] = {{"index", 0}};
    Doc doc = square(m, &kSun, kNode, true);
    doc.j["textures"] = json::array({{{"source", 0}}});
    doc.j["images"] = json::array({{{"uri", image}}});
    return centreLinear(axisFrame(loadDoc(doc, d, name), {0, 0, 3}, TexFilter::Auto)).x;
  };
  // Data (metallicRoughness, linear): metal 0 and 1 average to the byte 128,
  // not to sRGB's 188 (0.74), which averaging decoded values would give.
  near(render("metallicRoughnessTexture", "metal.png", pbrMaterial(1, 1, 1, 1, 1), "data"),
       brdfAxis(1, 128.0 / 255.0, 1, 1));
  // Colour (base colour, sRGB): black and white average to half the light (the byte 188).
  near(render("baseColorTexture", "bw.png", pbrMaterial(1, 1, 1, 0, 1), "colour"),
       brdfAxis(srgbDecode(188.0 / 255.0), 0, 1, 1));
}

TEST_CASE("pbr: normal maps take the file's TANGENT and its handedness, else generated tangents", "[pbr]") {
  TempDir d;
  writePng(d.file("tilt.png"), 1, 1, {0xff8080ffu});  // tangent space (1, 0, 0): the normal becomes T
  writePng(d.file("up.png"), 1, 1, {0xff80ff80u});    // (0, 1, 0): the normal becomes the bitangent
  // Directional lights 45 degrees off the axis, from +x and from +y.
  const double q = std::sin(kPi / 8), c = std::cos(kPi / 8);
  const json fromX = {{"rotation", {0, q, 0, c}}}, fromY = {{"rotation", {-q, 0, 0, c}}};
  auto each = [](float x, float y, float z, float w) {
    std::vector<float> t;
    for (int k = 0; k < 4; ++k) t.insert(t.end(), {x, y, z, w});
    return t;
  };
  auto render = [&](const char* image, const json& light, const std::vector<float>& tangent, const char* name,
                    bool mirror = false) {
    json m = pbrMaterial(1, 1, 1, 0, 1);
    m["normalTexture"] = {{"index", 0}};
    Doc doc = square(m, &kSun, light, true, tangent);
    doc.j["textures"] = json::array({{{"source", 0}}});
    doc.j["images"] = json::array({{{"uri", image}}});
    // x mirrored: the square still faces +z, its tangent turns to -x, its bitangent stays +y.
    if (mirror) doc.j["nodes"][0]["scale"] = {-1, 1, 1};
    return centre(loadDoc(doc, d, name)).x;
  };
  // The square's dP/du is +x: generated tangents (no TANGENT) turn the normal to the light from +x.
  const float generated = render("tilt.png", fromX, {}, "gen");
  CHECK(generated > 0.1f);
  near(render("tilt.png", fromX, each(1, 0, 0, 1), "tx"), generated);
  // A file's tangent rotated 90 degrees from dP/du turns it to +y instead:
  // dark under the light from +x, lit under the one from +y.
  CHECK(render("tilt.png", fromX, each(0, 1, 0, 1), "ty") < 0.005f);
  near(render("tilt.png", fromY, each(0, 1, 0, 1), "tyy"), generated);
  // Handedness: bitangent = w N x T, +y for w = 1, -y for w = -1.
  near(render("up.png", fromY, each(1, 0, 0, 1), "wpos"), generated);
  CHECK(render("up.png", fromY, each(1, 0, 0, -1), "wneg") < 0.005f);
  near(render("up.png", fromY, {}, "wgen"), generated);  // generated: w = +1 (v runs down the image)
  // A mirroring node keeps the file's bitangent (+y), not N x T of the mirrored tangent.
  near(render("up.png", fromY, each(1, 0, 0, 1), "mirror", true), generated);
}

TEST_CASE("pbr: each texture samples its own texCoord set and transform", "[pbr]") {
  TempDir d;
  const json kNode = {{"translation", {0, 0, 5}}};
  writePng(d.file("white.png"), 1, 1, {0xffffffffu});
  writePng(d.file("halves.png"), 2, 1, {0xff000000u, 0xff0000ffu});  // left black, right red
  // A black dielectric (its base colour texture white, on set 0) whose
  // emission is the halves texture: set 0 puts every vertex on the black
  // half, set 1 on the red one.
  auto doc = [&](const json& emissive, const json* occlusion = nullptr, bool withSet1 = true) {
    json m = pbrMaterial(0, 0, 0, 0, 1);
    m["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
    m["emissiveFactor"] = {1, 1, 1};
    m["emissiveTexture"] = emissive;
    if (occlusion) m["occlusionTexture"] = *occlusion;
    Doc doc = square(m, &kSun, kNode);
    const int set0 = doc.floats({0.25f, 0.5f, 0.25f, 0.5f, 0.25f, 0.5f, 0.25f, 0.5f}, "VEC2", 2);
    const int set1 = doc.floats({0.75f, 0.5f, 0.75f, 0.5f, 0.75f, 0.5f, 0.75f, 0.5f}, "VEC2", 2);
    doc.j["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = set0;
    if (withSet1) doc.j["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_1"] = set1;
    doc.j["textures"] = json::array({{{"source", 0}}, {{"source", 1}}});
    doc.j["images"] = json::array({{{"uri", "white.png"}}, {{"uri", "halves.png"}}});
    return doc;
  };
  const Scene one = loadDoc(doc({{"index", 1}}), d, "set0");
  CHECK(one.uvs1.empty());  // one set and transform: no second coordinates
  CHECK(centre(one).x < 0.1f);
  const Scene two = loadDoc(doc({{"index", 1}, {"texCoord", 1}}), d, "set1");
  CHECK(two.uvs1.size() == two.positions.size());
  CHECK(centre(two).x > 0.9f);
  // KHR_texture_transform's texCoord overrides the textureInfo's.
  const json pick = {{"index", 1}, {"texCoord", 0}, {"extensions", {{"KHR_texture_transform", {{"texCoord", 1}}}}}};
  CHECK(centre(loadDoc(doc(pick), d, "override")).x > 0.9f);
  // A transform of the emissive texture alone (the base colour has none): u 0.25 + 0.5.
  const json moved = {{"index", 1}, {"extensions", {{"KHR_texture_transform", {{"offset", {0.5, 0.0}}}}}}};
  CHECK(centre(loadDoc(doc(moved), d, "moved")).x > 0.9f);
  // Refused in one line: a set the primitive lacks, a third set or transform.
  CHECK_THAT(docError(doc({{"index", 1}, {"texCoord", 1}}, nullptr, false), d, "lacks"),
             Contains("material samples TEXCOORD_1 which the primitive lacks"));
  const json third = {{"index", 1}, {"extensions", {{"KHR_texture_transform", {{"offset", {0.25, 0.0}}}}}}};
  CHECK_THAT(docError(doc({{"index", 1}, {"texCoord", 1}}, &third), d, "third"),
             Contains("occlusionTexture: a third set of texture coordinates or transform"));
}

TEST_CASE("pbr: out-of-range material and light values are refused in one line", "[pbr]") {
  TempDir d;
  auto bad = [&](const json& m, const char* message) {
    INFO(m.dump());
    CHECK_THAT(docError(square(m), d, "bad"), Contains(message));
  };
  bad(pbrMaterial(1.5, 0, 0, 0, 1), "baseColorFactor must be a number in [0, 1]");
  bad(pbrMaterial(1, 1, 1, -0.5, 1), "metallicFactor");
  bad(pbrMaterial(1, 1, 1, 0, 2), "roughnessFactor");
  json m = pbrMaterial(1, 1, 1, 0, 1);
  m["alphaMode"] = "SOMETIMES";
  bad(m, "alphaMode must be OPAQUE, MASK or BLEND");
  m = pbrMaterial(1, 1, 1, 0, 1);
  m["emissiveFactor"] = {2, 0, 0};
  bad(m, "emissiveFactor");
  m["emissiveFactor"] = {1, 0, 0};
  m["extensions"] = {{"KHR_materials_emissive_strength", {{"emissiveStrength", -1}}}};
  bad(m, "emissiveStrength must not be negative");
  const json node = {{"translation", {0, 0, 5}}};
  const json spot = {{"type", "spot"}, {"spot", {{"innerConeAngle", 0.8}, {"outerConeAngle", 0.4}}}};
  CHECK_THAT(docError(square(pbrMaterial(1, 1, 1, 0, 1), &spot, node), d, "spot"), Contains("spot cone angles"));
  const json weird = {{"type", "laser"}};
  CHECK_THAT(docError(square(pbrMaterial(1, 1, 1, 0, 1), &weird, node), d, "laser"), Contains("type must be"));
  Doc missing = square(pbrMaterial(1, 1, 1, 0, 1), &kSun, node);
  missing.j["nodes"][1]["extensions"]["KHR_lights_punctual"]["light"] = 7;
  CHECK_THAT(docError(missing, d, "missing"), Contains("lights[7] does not exist"));
}
