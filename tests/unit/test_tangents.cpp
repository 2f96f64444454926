// Normal mapping's tangents (#37): the per-vertex generation where a file has
// none (host/scene/tangents.h) against frames worked out by hand, and the
// loader's rules: a file's TANGENT read with its handedness, tangents kept
// only for materials with a normal texture (other scenes carry no tangent
// stream), refused in one line when malformed. How they light a surface is
// tests/unit/test_pbr_shading.cpp's.
#include <catch2/catch.hpp>

#include "host/image/image_io.h"
#include "host/scene/tangents.h"
#include "tests/unit/loader_test_helpers.h"

#include <cmath>

using namespace rast;
using namespace rast::loader_test;
using Catch::Matchers::Contains;

namespace {

void same(const rast::float4& got, float x, float y, float z, float w) {
  INFO("got (" << got.x << ", " << got.y << ", " << got.z << ", " << got.w << ")");
  CHECK(std::abs(got.x - x) < 1e-5f);
  CHECK(std::abs(got.y - y) < 1e-5f);
  CHECK(std::abs(got.z - z) < 1e-5f);
  CHECK(got.w == w);
}

const std::vector<rast::float3> kSquare = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
const std::vector<rast::float3> kUp = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
const std::vector<uint32_t> kQuad = {0, 1, 2, 0, 2, 3};

std::vector<rast::float4> generated(const std::vector<rast::float3>& pos, const std::vector<rast::float3>& nrm,
                              const std::vector<rast::float2>& uv, std::vector<uint32_t> idx = kQuad) {
  return generateTangents(pos, nrm, uv, idx, false).tangents;
}

// The unit square facing +z with material 0, its texture coordinates
// running as glTF's do (u right, v down the image), and TANGENT when given.
Doc square(const json& material, const std::vector<float>& tangent = {}, bool withNormals = true) {
  Doc doc;
  json attrs = {{"POSITION", doc.vec3({-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0})},
                {"TEXCOORD_0", doc.floats({0, 1, 1, 1, 1, 0, 0, 0}, "VEC2", 2)}};
  if (withNormals) attrs["NORMAL"] = doc.vec3({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1});
  if (!tangent.empty()) attrs["TANGENT"] = doc.floats(tangent, "VEC4", 4);
  const std::vector<uint16_t> idx = {0, 1, 2, 0, 2, 3};
  doc.prim({{"attributes", attrs}, {"indices", doc.accessor(doc.view(idx), kU16, idx.size(), "SCALAR")}, {"material", 0}});
  doc.j["materials"] = json::array({material});
  doc.j["textures"] = json::array({{{"source", 0}}});
  doc.j["images"] = json::array({{{"uri", "n.png"}}});
  return doc;
}

const json kNormalMapped = {{"normalTexture", {{"index", 0}}}};

}  // namespace

TEST_CASE("tangents: generated per vertex from dP/du, handedness from dP/dv", "[tangents]") {
  // u to the right, v down the image: T = +x, and -dP/dv = +y = N x T, so w = +1.
  std::vector<rast::float2> uv = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
  for (const rast::float4& t : generated(kSquare, kUp, uv)) same(t, 1, 0, 0, 1);
  // u mirrored: T = -x, the bitangent still +y = -(N x T): w = -1.
  uv = {{1, 1}, {0, 1}, {0, 0}, {1, 0}};
  for (const rast::float4& t : generated(kSquare, kUp, uv)) same(t, -1, 0, 0, -1);
  // Coordinates rotated 90 degrees (u up the square): T = +y.
  uv = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
  for (const rast::float4& t : generated(kSquare, kUp, uv)) same(t, 0, 1, 0, 1);
}

TEST_CASE("tangents: summed over a vertex's triangles, orthogonal to its normal", "[tangents]") {
  // Two triangles sharing the edge 0-1 and folded along it (a roof over the
  // x axis): each triangle's dP/du is +x, and a shared vertex's normal leans
  // towards +y; its tangent stays +x (already orthogonal), w +1.
  const std::vector<rast::float3> pos = {{0, 0, 0}, {1, 0, 0}, {0, 1, -1}, {0, -1, -1}};
  const float s = 1.0f / std::sqrt(2.0f);
  const std::vector<rast::float3> nrm = {{0, 0, 1}, {0, 0, 1}, {0, s, s}, {0, -s, s}};
  const std::vector<rast::float2> uv = {{0, 0.5f}, {1, 0.5f}, {0, 0}, {0, 1}};
  const std::vector<rast::float4> t = generated(pos, nrm, uv, {0, 1, 2, 1, 0, 3});
  for (const rast::float4& v : t) same(v, 1, 0, 0, 1);
  // A normal not orthogonal to dP/du: the tangent is its part in the normal's plane.
  const std::vector<rast::float3> tilted = {{s, 0, s}, {s, 0, s}, {s, 0, s}, {s, 0, s}};
  const std::vector<rast::float2> flat = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
  for (const rast::float4& v : generated(kSquare, tilted, flat)) same(v, s, 0, -s, 1);
  // Degenerate coordinates (every vertex at one uv): no tangent, w 0.
  const std::vector<rast::float2> one(4, rast::float2{0.5f, 0.5f});
  for (const rast::float4& v : generated(kSquare, kUp, one)) same(v, 0, 0, 0, 0);
}

TEST_CASE("tangents: a vertex shared across a mirrored seam is split, as MikkTSpace splits it", "[tangents]") {
  // Triangle (0, 1, 2) is mapped with u to the right, (0, 2, 3) mirrored:
  // vertices 0 and 2 belong to both handednesses.
  const std::vector<rast::float2> uv = {{0, 1}, {1, 1}, {1, 0}, {2, 0}};
  std::vector<uint32_t> idx = kQuad;
  const GeneratedTangents kept = generateTangents(kSquare, kUp, uv, idx, false);
  CHECK(kept.copies.empty());
  CHECK(idx == kQuad);
  const GeneratedTangents g = generateTangents(kSquare, kUp, uv, idx, true);
  REQUIRE(g.copies.size() == 2);
  REQUIRE(g.tangents.size() == 6);
  CHECK(idx != kQuad);
  for (int t = 0; t < 2; ++t) {  // each triangle's corners agree in handedness; the two triangles differ
    const float w = g.tangents[idx[3 * t]].w;
    CHECK(w != 0.0f);
    CHECK(g.tangents[idx[3 * t + 1]].w == w);
    CHECK(g.tangents[idx[3 * t + 2]].w == w);
  }
  CHECK(g.tangents[idx[0]].w == -g.tangents[idx[3]].w);
  same(g.tangents[idx[0]], 1, 0, 0, 1);  // the first triangle: u right, v down
  for (size_t k = 0; k < g.copies.size(); ++k) CHECK((g.copies[k] == 0 || g.copies[k] == 2));
}

TEST_CASE("tangents: the loader keeps them only for normal-mapped materials", "[tangents]") {
  TempDir d;
  writePng(d.file("n.png"), 1, 1, {0xffff8080u});
  // No normal texture: no tangent stream, even when the file has TANGENT.
  const std::vector<float> file = {0, 1, 0, -1, 0, 1, 0, -1, 0, 1, 0, -1, 0, 1, 0, -1};
  CHECK(loadDoc(square(json::object(), file), d, "plain").tangents.empty());
  // A normal texture without TANGENT: generated.
  const Scene gen = loadDoc(square(kNormalMapped), d, "gen");
  REQUIRE(gen.tangents.size() == gen.positions.size());
  for (const rast::float4& t : gen.tangents) same(t, 1, 0, 0, 1);
  // With TANGENT: the file's, w as the sign it carries.
  const Scene fromFile = loadDoc(square(kNormalMapped, {0, 1, 0, -0.5f, 0, 1, 0, -1, 0, 1, 0, -1, 0, 1, 0, 2}), d, "file");
  REQUIRE(fromFile.tangents.size() == 4);
  same(fromFile.tangents[0], 0, 1, 0, -1);
  same(fromFile.tangents[3], 0, 1, 0, 1);
  // Without NORMAL the file's tangents are ignored (flat normals; glTF 2.0 3.7.2.1).
  CHECK(loadDoc(square(kNormalMapped, file, false), d, "flat").tangents.empty());
}

TEST_CASE("tangents: a malformed TANGENT is refused in one line", "[tangents]") {
  TempDir d;
  writePng(d.file("n.png"), 1, 1, {0xffff8080u});
  CHECK_THAT(docError(square(kNormalMapped, {1, 0, 0, 1, 1, 0, 0, 1}), d, "short"), Contains("TANGENT"));
  const float nan = std::nanf("");
  CHECK_THAT(docError(square(kNormalMapped, {1, 0, 0, 1, 1, 0, 0, 1, 1, 0, nan, 1, 1, 0, 0, 1}), d, "nan"),
             Contains("non-finite"));
  Doc vec3 = square(kNormalMapped);
  vec3.j["meshes"][0]["primitives"][0]["attributes"]["TANGENT"] = vec3.vec3({1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0});
  CHECK_THAT(docError(vec3, d, "vec3"), Contains("TANGENT"));
}
