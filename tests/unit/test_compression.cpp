// Compressed glTF geometry (host/gltf/compression.cpp): meshopt streams and
// Draco meshes written here with the same Debian libraries' encoders must
// load as the very triangles they were made from (meshopt without filters is
// exact; Draco without quantization too); a meshopt fallback buffer (no uri)
// is accepted; Debian's 2CylinderEngine loads the same with Draco as without;
// corrupt streams and over-budget decodes end in one line.
#include <catch2/catch.hpp>

#include "host/image/image_io.h"
#include "tests/unit/loader_test_helpers.h"

#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>
#include <meshoptimizer.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>

using namespace rast;
using namespace rast::loader_test;
using Catch::Matchers::Contains;

namespace {

// A small grid of triangles with distinct positions.
struct Mesh {
  std::vector<float> pos;
  std::vector<uint32_t> idx;
};
Mesh grid(int n) {
  Mesh m;
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x) m.pos.insert(m.pos.end(), {float(x) * 0.5f, float(y) * 0.25f, float((x * y) % 3) * 0.125f});
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const uint32_t a = uint32_t(y * (n + 1) + x), b = a + 1, c = a + uint32_t(n + 1), d = c + 1;
      m.idx.insert(m.idx.end(), {a, b, d, a, d, c});
    }
  return m;
}

// Every drawn triangle as its three corner positions, rotated to start at the
// smallest corner (winding kept), sorted: the same set whatever the order.
using Tri = std::array<float, 9>;
std::vector<Tri> triangles(const Scene& s) {
  std::vector<Tri> out;
  for (const Draw& d : s.draws) {
    const MeshPrim& p = s.prims[d.prim];
    for (uint32_t t = 0; t < p.triCount; ++t) {
      std::array<std::array<float, 3>, 3> c;
      for (int k = 0; k < 3; ++k) {
        const rast::float3 v = s.positions[p.firstVertex + s.indices[3 * size_t(p.firstTri + t) + k]];
        c[k] = {v.x, v.y, v.z};
      }
      const int r = int(std::min_element(c.begin(), c.end()) - c.begin());
      Tri tri;
      for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j) tri[3 * k + j] = c[(r + k) % 3][j];
      out.push_back(tri);
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

Scene plain(const Mesh& m, const TempDir& d) {
  Doc doc;
  const int ia = doc.accessor(doc.view(m.idx), kU32, m.idx.size(), "SCALAR");
  doc.prim({{"attributes", {{"POSITION", doc.vec3(m.pos)}}}, {"indices", ia}});
  return loadDoc(doc, d, "plain");
}

// The grid with its positions and indices meshopt-encoded in buffer 0, read
// through views of a fallback buffer 1 that holds no data.
std::string meshoptFile(const Mesh& m, const TempDir& d, bool corrupt, bool glb = false, const json& fallback = true) {
  const size_t nv = m.pos.size() / 3;
  std::vector<unsigned char> vb(meshopt_encodeVertexBufferBound(nv, 12));
  vb.resize(meshopt_encodeVertexBuffer(vb.data(), vb.size(), m.pos.data(), nv, 12));
  std::vector<unsigned char> ib(meshopt_encodeIndexBufferBound(m.idx.size(), nv));
  ib.resize(meshopt_encodeIndexBuffer(ib.data(), ib.size(), m.idx.data(), m.idx.size()));
  if (corrupt) std::fill(vb.begin() + 1, vb.end(), 0xff);
  Doc doc;
  doc.view(vb);
  const size_t ibOffset = (vb.size() + 3) / 4 * 4;
  doc.view(ib);
  auto ext = [](size_t off, size_t len, size_t stride, size_t count, const char* mode) {
    return json{{"EXT_meshopt_compression",
                 {{"buffer", 0}, {"byteOffset", off}, {"byteLength", len}, {"byteStride", stride}, {"count", count}, {"mode", mode}}}};
  };
  doc.j["bufferViews"] = json::array(
      {{{"buffer", 1}, {"byteLength", nv * 12}, {"byteStride", 12}, {"extensions", ext(0, vb.size(), 12, nv, "ATTRIBUTES")}},
       {{"buffer", 1}, {"byteOffset", nv * 12}, {"byteLength", m.idx.size() * 4},
        {"extensions", ext(ibOffset, ib.size(), 4, m.idx.size(), "TRIANGLES")}}});
  const int pa = doc.accessor(0, kF32, nv, "VEC3");
  const int ia = doc.accessor(1, kU32, m.idx.size(), "SCALAR");
  doc.prim({{"attributes", {{"POSITION", pa}}}, {"indices", ia}});
  doc.j["extensionsUsed"] = {"EXT_meshopt_compression"};
  doc.j["extensionsRequired"] = {"EXT_meshopt_compression"};
  json out = doc.j;
  json own = {{"byteLength", doc.bin.size()}};
  if (!glb) own["uri"] = "mo.bin";
  out["buffers"] = json::array({own, {{"byteLength", nv * 12 + m.idx.size() * 4},
                                      {"extensions", {{"EXT_meshopt_compression", {{"fallback", fallback}}}}}}});
  if (!glb) {
    d.write("mo.bin", doc.bin);
    return d.write("mo.gltf", out.dump());
  }
  // A GLB: the compressed bytes in its BIN chunk (buffer 0), the fallback buffer without data.
  std::string js = out.dump(), bin = doc.bin;
  while (js.size() % 4) js += ' ';
  while (bin.size() % 4) bin += '\0';
  auto u32 = [](uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
  const std::string file = "glTF" + u32(2) + u32(uint32_t(12 + 8 + js.size() + 8 + bin.size())) + u32(uint32_t(js.size())) +
                           "JSON" + js + u32(uint32_t(bin.size())) + std::string("BIN\0", 4) + bin;
  return d.write("mo.glb", file);
}

std::string dracoFile(const Mesh& m, const TempDir& d, bool corrupt) {
  draco::TriangleSoupMeshBuilder b;
  const int faces = int(m.idx.size() / 3);
  b.Start(faces);
  const int att = b.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
  for (int f = 0; f < faces; ++f)
    b.SetAttributeValuesForFace(att, draco::FaceIndex(f), &m.pos[3 * m.idx[3 * f]], &m.pos[3 * m.idx[3 * f + 1]],
                                &m.pos[3 * m.idx[3 * f + 2]]);
  std::unique_ptr<draco::Mesh> mesh = b.Finalize();
  draco::Encoder enc;
  draco::EncoderBuffer eb;
  REQUIRE(enc.EncodeMeshToBuffer(*mesh, &eb).ok());
  std::vector<unsigned char> bytes(eb.data(), eb.data() + eb.size());
  // The decoded counts the accessors must declare.
  draco::DecoderBuffer db;
  db.Init(eb.data(), eb.size());
  draco::Decoder dec;
  auto back = dec.DecodeMeshFromBuffer(&db);
  REQUIRE(back.ok());
  const size_t points = back.value()->num_points(), tris = back.value()->num_faces();
  if (corrupt) bytes.resize(bytes.size() / 2);  // cut: the decoder runs out of stream
  Doc doc;
  const int bv = doc.view(bytes);
  const int pa = doc.accessor(-1, kF32, points, "VEC3");
  const int ia = doc.accessor(-1, kU32, tris * 3, "SCALAR");
  doc.prim({{"attributes", {{"POSITION", pa}}},
            {"indices", ia},
            {"extensions", {{"KHR_draco_mesh_compression", {{"bufferView", bv}, {"attributes", {{"POSITION", mesh->attribute(att)->unique_id()}}}}}}}});
  doc.j["extensionsUsed"] = {"KHR_draco_mesh_compression"};
  doc.j["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  return doc.write(d, "draco");
}

}  // namespace

TEST_CASE("compression: meshopt decodes to exactly the source's triangles", "[compression]") {
  TempDir d;
  const Mesh m = grid(6);
  const Scene ref = plain(m, d);
  const Scene s = loadGltf(meshoptFile(m, d, false));
  CHECK(s.triangleCount() == ref.triangleCount());
  CHECK(triangles(s) == triangles(ref));
  CHECK(triangles(loadGltf(meshoptFile(m, d, false, /*glb=*/true))) == triangles(ref));
  CHECK_THAT(loadError(meshoptFile(m, d, true)), Contains("EXT_meshopt_compression: the compressed stream is corrupt"));
  // A fallback flag that is not a boolean (found by fuzz_loader: it ended the
  // process with nlohmann's type_error) is named, in a text and a binary file.
  for (const bool glb : {false, true})
    CHECK_THAT(loadError(meshoptFile(m, d, false, glb, 1)),
               Contains("buffers[1].extensions.EXT_meshopt_compression.fallback: expected a boolean, got number"));
}

TEST_CASE("compression: Draco decodes to the source's triangles", "[compression]") {
  TempDir d;
  const Mesh m = grid(5);
  const Scene ref = plain(m, d);
  const Scene s = loadGltf(dracoFile(m, d, false));
  CHECK(triangles(s) == triangles(ref));
  CHECK_THAT(loadError(dracoFile(m, d, true)), Contains("KHR_draco_mesh_compression"));
}

TEST_CASE("compression: decoded sizes are checked against the budget first", "[compression]") {
  TempDir d;
  const Mesh m = grid(40);
  LoadOptions tight;
  tight.maxMemory = 60000;  // the file fits, its decoded draco mesh does not
  try {
    loadGltf(dracoFile(m, d, false), tight);
    FAIL("loaded over budget");
  } catch (const Error& e) {
    CHECK_THAT(std::string(e.what()), Contains("memory budget"));
  }
}

TEST_CASE("compression: Debian's 2CylinderEngine with Draco matches the uncompressed file", "[compression]") {
  const std::string draco = std::string(RAST_ASSIMP_GLTF_DIR) + "/draco/2CylinderEngine.gltf";
  const std::string glb = std::string(RAST_ASSIMP_GLTF_DIR) + "/2CylinderEngine-glTF-Binary/2CylinderEngine.glb";
  if (!std::filesystem::exists(draco) || !std::filesystem::exists(glb)) {
    WARN("SKIPPED: assimp-testmodels' 2CylinderEngine not installed");
    return;
  }
  const Scene a = loadGltf(draco), b = loadGltf(glb);
  // Draco's encoder drops degenerate triangles (about 14% of this model's
  // 75,730, which cover no pixel): the triangles with area are the same.
  auto withArea = [](const Scene& s) {
    uint64_t n = 0;
    for (const Draw& d : s.draws) {
      const MeshPrim& p = s.prims[d.prim];
      for (uint32_t t = 0; t < p.triCount; ++t) {
        const uint32_t* ix = s.indices.data() + 3 * size_t(p.firstTri + t);
        const rast::float3 u = s.positions[p.firstVertex + ix[0]], v = s.positions[p.firstVertex + ix[1]], w = s.positions[p.firstVertex + ix[2]];
        const rast::float3 c = cross(v - u, w - u);
        n += dot(c, c) > 0.0f ? 1 : 0;
      }
    }
    return n;
  };
  CHECK(a.triangleCount() < b.triangleCount());
  const double ra = double(withArea(a)), rb = double(withArea(b));
  CHECK(std::abs(ra - rb) < 0.01 * rb);
  CHECK(a.draws.size() == b.draws.size());
  glm::dvec3 alo, ahi, blo, bhi;
  a.worldBounds(alo, ahi);
  b.worldBounds(blo, bhi);
  const double size = glm::length(bhi - blo);
  CHECK(glm::length(alo - blo) < 1e-3 * size);  // within the 14-bit position quantization
  CHECK(glm::length(ahi - bhi) < 1e-3 * size);
}

TEST_CASE("compression: KHR_texture_basisu uses the fallback image, or is refused by name", "[compression]") {
  TempDir d;
  writePng(d.file("fallback.png"), 2, 2, std::vector<uint32_t>(4, 0xff00ff00u));
  d.write("texture.ktx2", std::string("\xABKTX 20\xBB\r\n\x1A\n", 12) + std::string(64, '\0'));  // a KTX2 header
  Doc doc = texturedTriangle("fallback.png");
  doc.j["images"].push_back({{"uri", "texture.ktx2"}});
  doc.j["textures"][0]["extensions"] = {{"KHR_texture_basisu", {{"source", 1}}}};
  doc.j["extensionsUsed"] = {"KHR_texture_basisu"};
  const Scene s = loadDoc(doc, d, "basisu");  // the KTX2 image is not decoded: the PNG is used
  REQUIRE(s.textures.size() == 1);
  CHECK(s.textures[0].rgba[0] == 0xff00ff00u);
  doc.j["textures"][0].erase("source");
  CHECK_THAT(docError(doc, d, "basisu_only"), Contains("KHR_texture_basisu"));
  doc.j["extensionsRequired"] = {"KHR_texture_basisu"};
  CHECK_THAT(docError(doc, d, "basisu_required"), Contains("requires extension KHR_texture_basisu"));
}
