// KHR_texture_transform on the base-colour texture (#37): the loader bakes
// uv' = T(offset) R(rotation) S(scale) uv into each primitive's coordinates
// (host/gltf/model_walk.cpp), so a quad whose material carries a transform
// must render exactly as the same quad with the coordinates transformed in
// its file; the extension's texCoord overrides the textureInfo's set; a
// malformed transform is refused in one line; and a file may require it.
#include <catch2/catch.hpp>

#include "host/image/image_io.h"
#include "host/scene/camera.h"
#include "tests/support/test_support.h"
#include "tests/unit/loader_test_helpers.h"

#include <cmath>

using namespace rast;
using namespace rast::loader_test;
using Catch::Matchers::Contains;

namespace {

// An 8x8 image of distinct colours (so that any shift of the coordinates shows).
void writeTestImage(const std::string& path) {
  std::vector<uint32_t> px(64);
  for (uint32_t i = 0; i < 64; ++i) px[i] = 0xff000000u | (i * 4) << 16 | (255 - i * 4) << 8 | (i % 8) * 32;
  writePng(path, 8, 8, px);
}

const std::vector<float> kQuad = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
const std::vector<float> kQuadUv = {0, 0, 1, 0, 1, 1, 0, 1};

// A textured quad: TEXCOORD_0 = uv0, optionally TEXCOORD_1 = uv1; the material's
// baseColorTexture gets `info` (index 0 plus whatever the caller adds).
Doc texturedQuad(const std::vector<float>& uv0, const json& info, const std::vector<float>* uv1 = nullptr) {
  Doc doc;
  const std::vector<uint16_t> idx = {0, 1, 2, 0, 2, 3};
  json attrs = {{"POSITION", doc.vec3(kQuad)}, {"TEXCOORD_0", doc.floats(uv0, "VEC2", 2)}};
  if (uv1) attrs["TEXCOORD_1"] = doc.floats(*uv1, "VEC2", 2);
  const int ia = doc.accessor(doc.view(idx), kU16, idx.size(), "SCALAR");
  doc.prim({{"attributes", attrs}, {"indices", ia}, {"material", 0}});
  doc.j["materials"] = json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", info}}}}});
  doc.j["textures"] = json::array({{{"source", 0}, {"sampler", 0}}});
  doc.j["samplers"] = json::array({{{"magFilter", 9728}, {"minFilter", 9728}}});  // nearest
  doc.j["images"] = json::array({{{"uri", "tex.png"}}});
  return doc;
}

std::vector<uint32_t> render(const Scene& s) {
  Camera cam;
  cam.eye = {0, 0, 3};
  cam.target = {0, 0, 0};
  RenderSettings rs;
  rs.width = 96;
  rs.height = 96;
  rs.filter = TexFilter::Nearest;
  return test::renderFrame(s, cam, rs).color;
}

}  // namespace

TEST_CASE("KHR_texture_transform: the transform equals coordinates transformed in the file", "[texture-transform]") {
  TempDir d;
  writeTestImage(d.file("tex.png"));
  const double ox = 0.25, oy = -0.5, rot = 0.3, sx = 1.5, sy = 0.75;
  const json xf = {{"offset", {ox, oy}}, {"rotation", rot}, {"scale", {sx, sy}}};
  const json info = {{"index", 0}, {"extensions", {{"KHR_texture_transform", xf}}}};
  std::vector<float> moved(kQuadUv.size());
  for (size_t i = 0; i < kQuadUv.size(); i += 2) {
    const double u = kQuadUv[i], v = kQuadUv[i + 1];
    moved[i] = float(std::cos(rot) * sx * u + std::sin(rot) * sy * v + ox);
    moved[i + 1] = float(-std::sin(rot) * sx * u + std::cos(rot) * sy * v + oy);
  }
  const std::vector<uint32_t> withExtension = render(loadDoc(texturedQuad(kQuadUv, info), d, "xf"));
  const std::vector<uint32_t> inFile = render(loadDoc(texturedQuad(moved, {{"index", 0}}), d, "moved"));
  const std::vector<uint32_t> plain = render(loadDoc(texturedQuad(kQuadUv, {{"index", 0}}), d, "plain"));
  CHECK(withExtension == inFile);
  CHECK(withExtension != plain);  // the transform changes the picture

  // The extension's texCoord picks TEXCOORD_1 over the textureInfo's set 0.
  const std::vector<float> junk = {0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f, 0.9f};
  const json pick = {{"texCoord", 1}};
  const json override = {{"index", 0}, {"texCoord", 0}, {"extensions", {{"KHR_texture_transform", pick}}}};
  CHECK(render(loadDoc(texturedQuad(junk, override, &kQuadUv), d, "set1")) == plain);

  // Required: loads (it is honoured), and appears in the file's facts.
  Doc required = texturedQuad(kQuadUv, info);
  required.j["extensionsUsed"] = {"KHR_texture_transform"};
  required.j["extensionsRequired"] = {"KHR_texture_transform"};
  const Scene s = loadDoc(required, d, "required");
  CHECK(s.facts.extensionsRequired == std::vector<std::string>{"KHR_texture_transform"});
  CHECK(s.facts.materialUses[9] == 1);
}

TEST_CASE("KHR_texture_transform: malformed values are refused in one line", "[texture-transform]") {
  TempDir d;
  writeTestImage(d.file("tex.png"));
  auto fails = [&](const json& xf, const char* message) {
    const json info = {{"index", 0}, {"extensions", {{"KHR_texture_transform", xf}}}};
    INFO(xf.dump());
    CHECK_THAT(docError(texturedQuad(kQuadUv, info), d, "bad"), Contains(message));
  };
  fails({{"offset", {1.0}}}, "offset must be an array of 2 numbers");
  fails({{"scale", {1.0, "x"}}}, "scale must be an array of 2 numbers");
  fails({{"scale", {1.0, nullptr}}}, "scale must be an array of 2 numbers");
  fails({{"rotation", "half"}}, "rotation must be a finite number");
  fails({{"texCoord", -1}}, "texCoord must be a non-negative integer");
  fails({{"texCoord", 1}}, "material samples TEXCOORD_1 which the primitive lacks");
}
