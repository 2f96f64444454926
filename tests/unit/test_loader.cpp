// glTF loading of well-formed files: every file of assimp-testmodels' glTF2
// folder gives its expected success (with the right triangle count, draws,
// textures and world bounds) or its expected one-line Error; small synthetic
// files check the accessor reader (strides, sparse, index types), strip/fan
// winding, node transforms, textures, flat normals and required extensions.
// Malformed and hostile input (damaged files, ranges, external files, the
// memory budget) is tested in test_loader_input.cpp.
//
// The expected counts and bounds of the assimp files were computed separately
// from their JSON and buffers (a Python reading of accessors and node
// transforms), not by this loader.
#include <catch2/catch.hpp>

#include "host/gltf/gltf_loader.h"
#include "tests/support/test_support.h"
#include "tests/unit/loader_test_helpers.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

using namespace rast;
using namespace rast::loader_test;
using Catch::Matchers::Contains;

namespace {

// ---------------------------------------------------------------- assimp-testmodels table

struct Expect {
  // Success: exact triangle count (instances counted), draws, textures, bounds.
  uint32_t tris = 0, draws = 0, textures = 0;
  glm::dvec3 lo{0.0}, hi{0.0};
  // Failure: a substring of the Error message.
  const char* error = nullptr;
};

Expect loads(uint32_t tris, uint32_t draws, uint32_t textures, glm::dvec3 lo, glm::dvec3 hi) {
  Expect e;
  e.tris = tris;
  e.draws = draws;
  e.textures = textures;
  e.lo = lo;
  e.hi = hi;
  return e;
}

Expect fails(const char* substring) {
  Expect e;
  e.error = substring;
  return e;
}

// Every .gltf/.glb below /usr/share/assimp/models/glTF2 (assimp-testmodels 5.x).
const std::map<std::string, Expect>& assimpTable() {
  const glm::dvec3 h(0.5), one(1.0);
  const std::string pm = "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_";
  static const std::map<std::string, Expect> t = {
      // Good files.
      {"2CylinderEngine-glTF-Binary/2CylinderEngine.glb",
       loads(121496, 115, 0, {-371.692, -180.972, -140.0}, {371.692, 92.0416, 128.0})},
      // Draco (docs/compression.md): the degenerate triangles dropped by its encoder, bounds within quantization.
      {"draco/2CylinderEngine.gltf", loads(110336, 115, 0, {-371.692, -180.972, -140.0}, {371.691, 92.017, 128.0})},
      {"BoxBadNormals-glTF-Binary/BoxBadNormals.glb", loads(12, 1, 0, -h, h)},  // odd normals, still finite
      {"BoxTexcoords-glTF/boxTexcoords.gltf", loads(12, 1, 1, -one, one)},
      {"BoxTextured-glTF-Binary/BoxTextured.glb", loads(12, 1, 1, -h, h)},
      {"BoxTextured-glTF-Embedded/BoxTextured.gltf", loads(12, 1, 1, -h, h)},
      {"BoxTextured-glTF/BoxTextured.gltf", loads(12, 1, 1, -h, h)},
      // KHR_materials_pbrSpecularGlossiness is only used, not required: the
      // metallic-roughness fallback is drawn.
      {"BoxTextured-glTF-pbrSpecularGlossiness/BoxTextured.gltf", loads(12, 1, 1, -h, h)},
      // All 6 of its images: the core material slots' (base colour, normal maps, the
      // emissive labels) and KHR_materials_clearcoat's clearcoatTexture (PartialCoating).
      {"ClearCoat-glTF/ClearCoatTest.gltf", loads(37116, 27, 6, {-7.3578, -6.25, -0.06}, {3.1, 6.85452, 1.05})},
      // Vertex counts that are not multiples of 3 lose the incomplete triangle
      // (12 + 11 + 12 + 11; the four LINES meshes add segments and draws), as
      // assimp does. Its unused accessors 2-4 point past the buffer: only data
      // read is checked.
      {"IncorrectVertexArrays/Cube.gltf", loads(46, 8, 0, {-3.5, -1.0, -3.5}, {3.5, 1.0, 3.5})},
      {"cameras/Cameras.gltf", loads(2, 1, 0, {0.0, 0.0, -0.707592}, {1.0, 0.706622, 0.0})},
      {"glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf", loads(12, 1, 0, -one, one)},
      // Skinned at rest: its joints' matrices move it by -0.5 in x (docs/animation.md).
      {"simple_skin/simple_skin.gltf", loads(8, 1, 0, {-0.5, 0.0, 0.0}, {0.5, 2.0, 0.0})},
      {"textureTransform/TextureTransformTest.gltf", loads(24, 12, 5, {-1.6, -1.14127, 0.0}, {1.6, 1.05, 0.01})},
      // Primitive modes: 0-3 and 7-10 are points/lines (no triangles; see
      // test_lines_points.cpp), 4/11 strips, 5/12 fans, 6/13-15 lists; 4
      // vertices make n-2 = 2 triangles.
      {pm + "00.gltf", loads(0, 1, 0, {-0.5, -0.5, 0.0}, {0.5, 0.5, 0.0})},
      {pm + "01.gltf", loads(0, 1, 0, {-0.5, -0.5, 0.0}, {0.5, 0.5, 0.0})},
      {pm + "02.gltf", loads(0, 1, 0, {-0.5, -0.5, 0.0}, {0.5, 0.5, 0.0})},
      {pm + "03.gltf", loads(0, 1, 0, {-0.5, -0.5, 0.0}, {0.5, 0.5, 0.0})},
      {pm + "04.gltf", loads(2, 1, 0, {-0.5, -0.5, 0.0}, {0.5, 0.5, 0.0})},
      {pm + "05.gltf", loads(2, 1, 0, {-0.5, -0.5, 0.0}, {0.5, 0.5, 0.0})},
      {pm + "06.gltf", loads(2, 1, 0, {-0.5, -0.5, 0.0}, {0.5, 0.5, 0.0})},
      {pm + "07.gltf", loads(0, 1, 0, {-0.5, -0.5, 0.0}, {0.5, 0.5, 0.0})},
      {pm + "08.gltf", loads(0, 1, 0, {-0.5, -0.5, 0.0}, {0.5, 0.5, 0.0})},
      {pm + "09.gltf", loads(0, 1, 0, {-0.5, -0.5, 0.0}, {0.5, 0.5, 0.0})},
      {pm + "10.gltf", loads(0, 1, 0, {-0.5, -0.5, 0.0}, {0.5, 0.5, 0.0})},
      {pm + "11.gltf", loads(2, 1, 0, {-0.5, -0.5, 0.0}, {0.5, 0.5, 0.0})},
      {pm + "12.gltf", loads(2, 1, 0, {-0.5, -0.5, 0.0}, {0.5, 0.5, 0.0})},
      {pm + "13.gltf", loads(2, 1, 0, {-0.5, -0.5, 0.0}, {0.5, 0.5, 0.0})},
      {pm + "14.gltf", loads(2, 1, 0, {-0.5, -0.5, 0.0}, {0.5, 0.5, 0.0})},
      {pm + "15.gltf", loads(2, 1, 0, {-0.5, -0.5, 0.0}, {0.5, 0.5, 0.0})},
      // Malformed or unsupported files.
      {"BoxTextured-glTF-techniqueWebGL/BoxTextured.gltf", fails("requires extension KHR_technique_webgl")},
      {"BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb", fails("POSITION accessor 2 has non-finite values")},
      {"IndexOutOfRange/IndexOutOfRange.gltf", fails("index 255 out of range")},
      {"IndexOutOfRange/AllIndicesOutOfRange.gltf", fails("index 65535 out of range")},
      {"MissingBin/BoxTextured.gltf", fails("buffers[0]: file 'BoxTextured0.bin' is missing")},
      {"RecursiveNodes/RecursiveNodes.gltf", fails("node hierarchy has a cycle through node 0")},
      // "scene": "hello" (its buffer is missing too; the type is reported first).
      {"SchemaFailures/sceneWrongType.gltf", fails("scene: expected an index")},
      {"TestNoRootNode/NoScene.gltf", fails("the scene has no triangles, lines or points to draw")},
      {"TestNoRootNode/SceneWithoutNodes.gltf", fails("the scene has no triangles, lines or points to draw")},
      // The material samples TEXCOORD_0; the primitive only has TEXCOORD_1.
      {"issue_3269/texcoord_crash.gltf", fails("material samples TEXCOORD_0 which the primitive lacks")},
      {"wrongTypes/badArray.gltf", fails("meshes[0].primitives: expected an array, got an object")},
      {"wrongTypes/badExtension.gltf",
       fails("baseColorTexture.extensions.KHR_texture_transform: expected an object, got \"Not an object\"")},
      {"wrongTypes/badNumber.gltf", fails("materials[0].normalTexture.scale: expected a number")},
      {"wrongTypes/badObject.gltf", fails("materials[0].pbrMetallicRoughness: expected an object, got an array")},
      {"wrongTypes/badString.gltf", fails("scenes[0].name: expected a string, got 42")},
      {"wrongTypes/badUint.gltf", fails("materials[0].pbrMetallicRoughness.baseColorTexture.index: expected an index")},
  };
  return t;
}

bool near(double a, double b) { return std::abs(a - b) <= 1e-4 * std::max(1.0, std::abs(b)); }

bool sameVec(const rast::float3& a, float x, float y, float z) {
  return std::abs(a.x - x) < 1e-6f && std::abs(a.y - y) < 1e-6f && std::abs(a.z - z) < 1e-6f;
}

}  // namespace

TEST_CASE("every glTF2 file of assimp-testmodels loads or fails as expected", "[loader]") {
  const std::string dir = test::assimpDir();
  if (dir.empty()) {
    test::skipTest("assimp-testmodels (/usr/share/assimp/models/glTF2) is not installed");
    return;
  }
  const auto& table = assimpTable();
  std::set<std::string> seen;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    const std::string ext = entry.path().extension().string();
    if (!entry.is_regular_file() || (ext != ".gltf" && ext != ".glb")) continue;
    const std::string rel = fs::relative(entry.path(), dir).generic_string();
    seen.insert(rel);
    INFO("file: " << rel);
    const auto it = table.find(rel);
    if (it == table.end()) {
      FAIL_CHECK("not in the expected-outcome table of test_loader.cpp: decide and add it");
      continue;
    }
    const Expect& x = it->second;
    if (x.error) {
      const std::string msg = loadError(entry.path().string());
      CHECK_THAT(msg, Contains(x.error));
      CHECK(msg.find('\n') == std::string::npos);
      CHECK_THAT(msg, Contains(entry.path().string()));  // names the file
      continue;
    }
    Scene s;
    REQUIRE_NOTHROW(s = loadGltf(entry.path().string()));
    CHECK(s.triangleCount() == x.tris);
    CHECK(s.draws.size() == x.draws);
    CHECK(s.textures.size() == x.textures);
    glm::dvec3 lo, hi;
    s.worldBounds(lo, hi);
    for (int k = 0; k < 3; ++k) {
      CHECK(near(lo[k], x.lo[k]));
      CHECK(near(hi[k], x.hi[k]));
    }
    CHECK(std::all_of(s.normals.begin(), s.normals.end(),
                      [](const rast::float3& n) { return std::isfinite(n.x) && std::isfinite(n.y) && std::isfinite(n.z); }));
    CHECK_NOTHROW(s.validate());
  }
  for (const auto& [rel, x] : table) {
    INFO("table entry: " << rel);
    CHECK(seen.count(rel) == 1);
  }
}

TEST_CASE("loader: byteStride interleaving reads the right values", "[loader]") {
  TempDir d;
  Doc doc;
  // position xyz, normal xyz, then 8 bytes of padding: stride 32.
  const std::vector<float> inter = {0, 0, 0, 0.f, 0.f, 1.f, -7, -7,  //
                                    2, 0, 0, 0.f, 1.f, 0.f, -7, -7,  //
                                    0, 3, 0, 1.f, 0.f, 0.f, -7, -7};
  const int v = doc.view(inter, 32);
  const int pos = doc.accessor(v, kF32, 3, "VEC3", 0);
  const int nrm = doc.accessor(v, kF32, 3, "VEC3", 12);
  doc.prim({{"attributes", {{"POSITION", pos}, {"NORMAL", nrm}}}});
  const Scene s = loadDoc(doc, d, "stride");
  REQUIRE(s.positions.size() == 3);
  CHECK(sameVec(s.positions[0], 0, 0, 0));
  CHECK(sameVec(s.positions[1], 2, 0, 0));
  CHECK(sameVec(s.positions[2], 0, 3, 0));
  CHECK(sameVec(s.normals[0], 0, 0, 1));
  CHECK(sameVec(s.normals[1], 0, 1, 0));
  CHECK(sameVec(s.normals[2], 1, 0, 0));
  CHECK(s.indices == std::vector<uint32_t>{0, 1, 2});
  // A stride smaller than the element is an error.
  doc.j["bufferViews"][v]["byteStride"] = 8;
  CHECK_THAT(docError(doc, d, "stride2"), Contains("byteStride 8 does not fit the element size"));
}

TEST_CASE("loader: sparse accessors", "[loader]") {
  TempDir d;
  SECTION("on top of a bufferView") {
    Doc doc;
    const int pos = doc.vec3({0, 0, 0, 9, 9, 9, 0, 1, 0});
    const std::vector<uint16_t> idx = {1};
    const std::vector<float> val = {1, 0, 0};
    doc.j["accessors"][pos]["sparse"] = {{"count", 1},
                                         {"indices", {{"bufferView", doc.view(idx)}, {"componentType", kU16}}},
                                         {"values", {{"bufferView", doc.view(val)}}}};
    doc.prim({{"attributes", {{"POSITION", pos}, {"NORMAL", doc.vec3({0, 0, 1, 0, 0, 1, 0, 0, 1})}}}});
    const Scene s = loadDoc(doc, d, "sparse");
    REQUIRE(s.positions.size() == 3);
    CHECK(sameVec(s.positions[0], 0, 0, 0));
    CHECK(sameVec(s.positions[1], 1, 0, 0));  // substituted
    CHECK(sameVec(s.positions[2], 0, 1, 0));
  }
  SECTION("without a bufferView: zeros plus substitutions") {
    Doc doc;
    const int pos = doc.accessor(-1, kF32, 3, "VEC3");
    const std::vector<uint8_t> idx = {2, 1, 0, 0};  // 3 u8 indices + padding
    const std::vector<float> val = {0, 5, 0, 5, 0, 0};
    doc.j["accessors"][pos]["sparse"] = {{"count", 2},
                                         {"indices", {{"bufferView", doc.view(idx.data(), 2)}, {"componentType", kU8}}},
                                         {"values", {{"bufferView", doc.view(val)}}}};
    doc.prim({{"attributes", {{"POSITION", pos}, {"NORMAL", doc.vec3({0, 0, 1, 0, 0, 1, 0, 0, 1})}}}});
    const Scene s = loadDoc(doc, d, "sparse0");
    REQUIRE(s.positions.size() == 3);
    CHECK(sameVec(s.positions[0], 0, 0, 0));
    CHECK(sameVec(s.positions[1], 5, 0, 0));
    CHECK(sameVec(s.positions[2], 0, 5, 0));
    // A sparse index past the accessor's count.
    doc.bin[doc.j["bufferViews"][0]["byteOffset"].get<size_t>()] = 3;
    CHECK_THAT(docError(doc, d, "sparse1"), Contains("sparse index 3 out of range"));
  }
}

TEST_CASE("loader: u8, u16 and u32 indices", "[loader]") {
  TempDir d;
  const std::vector<uint32_t> want = {0, 1, 2, 2, 1, 3};
  for (int type : {kU8, kU16, kU32}) {
    INFO("componentType " << type);
    Doc doc;
    const int pos = doc.vec3({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0});
    const int nrm = doc.vec3({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1});
    int v = -1;
    if (type == kU8) v = doc.view(std::vector<uint8_t>(want.begin(), want.end()));
    if (type == kU16) v = doc.view(std::vector<uint16_t>(want.begin(), want.end()));
    if (type == kU32) v = doc.view(want);
    doc.prim({{"attributes", {{"POSITION", pos}, {"NORMAL", nrm}}}, {"indices", doc.accessor(v, type, 6, "SCALAR")}});
    const Scene s = loadDoc(doc, d, "idx" + std::to_string(type));
    CHECK(s.indices == want);
    CHECK(s.triangleCount() == 2);
  }
  Doc doc;
  const int pos = doc.vec3(kTriangle);
  doc.prim({{"attributes", {{"POSITION", pos}}}, {"indices", doc.accessor(doc.view(kTriangle), kF32, 3, "SCALAR")}});
  CHECK_THAT(docError(doc, d, "idxf"), Contains("component type other than u8/u16/u32"));
}

TEST_CASE("loader: triangle strips and fans follow the glTF index formulas", "[loader]") {
  TempDir d;
  const std::vector<float> nrm5(15, 0.0f);
  const std::vector<uint16_t> seq = {3, 0, 4, 1, 2};
  SECTION("strip: triangle i = (v_i, v_{i+1+i%2}, v_{i+2-i%2})") {
    Doc doc;
    const int pos = doc.vec3({0, 0, 0, 1, 0, 0, 2, 0, 0, 3, 0, 0, 4, 0, 0});
    doc.prim({{"attributes", {{"POSITION", pos}, {"NORMAL", doc.vec3(nrm5)}}},
              {"indices", doc.accessor(doc.view(seq), kU16, 5, "SCALAR")},
              {"mode", 5}});
    const Scene s = loadDoc(doc, d, "strip");
    CHECK(s.indices == std::vector<uint32_t>{3, 0, 4, /**/ 0, 1, 4, /**/ 4, 1, 2});
  }
  SECTION("fan: triangle i = (v_{i+1}, v_{i+2}, v_0)") {
    Doc doc;
    const int pos = doc.vec3({0, 0, 0, 1, 0, 0, 2, 0, 0, 3, 0, 0, 4, 0, 0});
    doc.prim({{"attributes", {{"POSITION", pos}, {"NORMAL", doc.vec3(nrm5)}}},
              {"indices", doc.accessor(doc.view(seq), kU16, 5, "SCALAR")},
              {"mode", 6}});
    const Scene s = loadDoc(doc, d, "fan");
    CHECK(s.indices == std::vector<uint32_t>{0, 4, 3, /**/ 4, 1, 3, /**/ 1, 2, 3});
  }
  SECTION("a zigzag strip and a convex fan keep one winding (flat normals all alike)") {
    Doc strip;
    // v0 (0,0) v1 (0,1) v2 (1,0) v3 (1,1) v4 (2,0): every triangle is clockwise from +z.
    strip.prim({{"attributes", {{"POSITION", strip.vec3({0, 0, 0, 0, 1, 0, 1, 0, 0, 1, 1, 0, 2, 0, 0})}}}, {"mode", 5}});
    const Scene s = loadDoc(strip, d, "zigzag");
    CHECK(s.triangleCount() == 3);  // n - 2
    for (const rast::float3& n : s.normals) CHECK(sameVec(n, 0, 0, -1));
    Doc fan;
    // Centre (0,0) then (1,0) (1,1) (0,1) (-1,1): counter-clockwise from +z.
    fan.prim({{"attributes", {{"POSITION", fan.vec3({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, -1, 1, 0})}}}, {"mode", 6}});
    const Scene f = loadDoc(fan, d, "convexfan");
    CHECK(f.triangleCount() == 3);
    for (const rast::float3& n : f.normals) CHECK(sameVec(n, 0, 0, 1));
  }
}

TEST_CASE("loader: node hierarchy transforms place the mesh in the world", "[loader]") {
  TempDir d;
  Doc doc;
  doc.prim({{"attributes", {{"POSITION", doc.vec3(kTriangle)}}}});
  const double s = std::sqrt(0.5);
  doc.j["nodes"] = json::array({
      {{"children", {1}}, {"translation", {10, 0, 0}}, {"scale", {2, 2, 2}}},
      {{"children", {2}}, {"mesh", 0}, {"translation", {0, 1, 0}}, {"rotation", {0, 0, s, s}}},  // 90 deg about z
      {{"mesh", 0}, {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 5, 1}}},            // column-major: +5 z
  });
  const Scene sc = loadDoc(doc, d, "nodes");
  REQUIRE(sc.draws.size() == 2);
  CHECK(sc.triangleCount() == 2);
  CHECK(sc.prims.size() == 1);  // one mesh, drawn twice
  // Node 1: (x,y,z) -> rotate (-y,x,z) -> +(0,1,0) -> *2 -> +(10,0,0).
  // (0,0,0)->(10,2,0), (1,0,0)->(10,4,0), (0,1,0)->(8,2,0); node 2 adds z+5 before, so z=10.
  glm::dvec3 lo, hi;
  sc.worldBounds(lo, hi);
  CHECK(near(lo.x, 8));
  CHECK(near(lo.y, 2));
  CHECK(near(lo.z, 0));
  CHECK(near(hi.x, 10));
  CHECK(near(hi.y, 4));
  CHECK(near(hi.z, 10));
  const glm::dvec4 p = sc.draws[0].model * glm::dvec4(1, 0, 0, 1);
  CHECK(near(p.x, 10));
  CHECK(near(p.y, 4));
  CHECK(near(p.z, 0));

  SECTION("a node with two parents is refused (disjoint trees; no exponential walk)") {
    Doc dag;
    dag.prim({{"attributes", {{"POSITION", dag.vec3(kTriangle)}}}});
    json nodes = json::array();
    for (int i = 0; i < 64; ++i) nodes.push_back({{"children", {i + 1, i + 1}}});
    nodes.push_back({{"mesh", 0}});
    dag.j["nodes"] = nodes;
    CHECK_THAT(docError(dag, d, "dag"), Contains("node 64 appears twice"));
  }
  SECTION("a node listed twice in the scene") {
    doc.j["scenes"][0]["nodes"] = {2, 2};
    CHECK_THAT(docError(doc, d, "twice"), Contains("node 2 appears twice"));
  }
  SECTION("a long chain of nodes is walked without recursion") {
    Doc chain;
    chain.prim({{"attributes", {{"POSITION", chain.vec3(kTriangle)}}}});
    json nodes = json::array();
    const int n = 60000;  // a recursive walk would need tens of MB of stack
    for (int i = 0; i < n; ++i) nodes.push_back({{"children", {i + 1}}});
    nodes.push_back({{"mesh", 0}, {"translation", {0, 0, 1}}});
    chain.j["nodes"] = nodes;
    const Scene c = loadDoc(chain, d, "chain");
    CHECK(c.triangleCount() == 1);
  }
  SECTION("non-finite transform") {
    doc.j["nodes"][0]["scale"] = {1e308, 1e308, 1e308};
    doc.j["nodes"][1]["translation"] = {1e308, 0, 0};
    CHECK_THAT(docError(doc, d, "inf"), Contains("non-finite transform"));
  }
  SECTION("a transform array of the wrong length") {
    doc.j["nodes"][2]["matrix"] = {1, 0, 0};
    CHECK_THAT(docError(doc, d, "mat3"), Contains("nodes[2].matrix: expected 16 elements, got 3"));
  }
}

TEST_CASE("loader: textures", "[loader]") {
  TempDir d;
  SECTION("a corrupt PNG is an Error") {
    d.write("corrupt.png", "\x89PNG\r\n\x1a\nthis is not a png at all");
    const std::string msg = docError(texturedTriangle("corrupt.png"), d, "corrupt");
    CHECK_THAT(msg, Contains("image"));
    CHECK(msg.find('\n') == std::string::npos);
  }
  SECTION("a missing image file is an Error") {
    CHECK_THAT(docError(texturedTriangle("missing.png"), d, "missingimg"),
               Contains("texture image 0: cannot read 'missing.png'"));
  }
  SECTION("an absurd image size is refused before decoding") {
    d.write("wide.png", pngHeader(20000, 10000));
    CHECK_THAT(docError(texturedTriangle("wide.png"), d, "wideimg"), Contains("20000x10000 texels, more than 16384"));
    d.write("huge.png", pngHeader(100000, 100000));  // stb_image refuses this one itself
    CHECK_THAT(docError(texturedTriangle("huge.png"), d, "hugeimg"), Contains("image 0: cannot decode"));
  }
  SECTION("a good PNG is decoded, once for two materials") {
    const std::string dir = test::assimpDir();
    if (dir.empty()) return;
    fs::copy_file(dir + "/BoxTextured-glTF/CesiumLogoFlat.png", d.file("logo.png"));
    Doc doc = texturedTriangle("logo.png");
    doc.j["materials"].push_back(doc.j["materials"][0]);
    doc.j["meshes"][0]["primitives"].push_back(doc.j["meshes"][0]["primitives"][0]);
    doc.j["meshes"][0]["primitives"][1]["material"] = 1;
    const Scene s = loadDoc(doc, d, "good");
    REQUIRE(s.textures.size() == 1);
    CHECK(s.textures[0].width == 211);
    CHECK(s.textures[0].height == 211);  // CesiumLogoFlat.png is 211x211
    CHECK(s.materials.size() == 2);
    CHECK(s.uvs.size() == s.positions.size());
  }
}

TEST_CASE("loader: missing NORMAL gives flat normals", "[loader]") {
  TempDir d;
  Doc doc;
  // Counter-clockwise seen from +z: normalize(cross(b-a, c-a)) = (0,0,1).
  doc.prim({{"attributes", {{"POSITION", doc.vec3({1, 1, 2, 3, 1, 2, 1, 4, 2})}}}});
  const Scene s = loadDoc(doc, d, "flat");
  REQUIRE(s.normals.size() == 3);
  for (const rast::float3& n : s.normals) CHECK(sameVec(n, 0, 0, 1));
  // A clockwise triangle in the xz plane.
  Doc doc2;
  doc2.prim({{"attributes", {{"POSITION", doc2.vec3({0, 0, 0, 1, 0, 0, 0, 0, 1})}}}});
  const Scene s2 = loadDoc(doc2, d, "flat2");
  REQUIRE(s2.normals.size() == 3);
  CHECK(sameVec(s2.normals[0], 0, -1, 0));
}

TEST_CASE("loader: required extensions and non-finite attributes", "[loader]") {
  TempDir d;
  Doc doc;
  doc.prim({{"attributes", {{"POSITION", doc.vec3(kTriangle)}}}});
  doc.j["extensionsUsed"] = {"EXT_foo", "KHR_mesh_quantization"};
  doc.j["extensionsRequired"] = {"EXT_foo"};
  CHECK_THAT(docError(doc, d, "ext"), Contains("requires extension EXT_foo, which rast does not support"));
  // KHR_mesh_quantization is honoured: u16 positions are read as integers.
  doc.j["extensionsRequired"] = {"KHR_mesh_quantization"};
  const std::vector<uint16_t> q = {0, 0, 0, 300, 0, 0, 0, 300, 0, 0};
  doc.j["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = doc.accessor(doc.view(q), kU16, 3, "VEC3");
  const Scene s = loadDoc(doc, d, "quant");
  glm::dvec3 lo, hi;
  s.worldBounds(lo, hi);
  CHECK(near(hi.x, 300));
  CHECK(near(hi.y, 300));

  Doc nan;
  const float qnan = std::nanf("");
  nan.prim({{"attributes", {{"POSITION", nan.vec3(kTriangle)}, {"COLOR_0", nan.vec3({1, 1, 1, qnan, 0, 0, 1, 1, 1})}}}});
  CHECK_THAT(docError(nan, d, "nancolor"), Contains("COLOR_0 accessor 1 has non-finite values"));
  nan.j["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = 9;
  CHECK_THAT(docError(nan, d, "badcolor"), Contains("COLOR_0: accessor index 9 out of range"));
}
