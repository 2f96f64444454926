// glTF loading of malformed and hostile input: missing, empty, garbage,
// truncated and damaged files, FIFOs, accessor and bufferView ranges, external
// files outside the scene's folder, image errors and the memory budget. Each
// must end in one clear one-line Error (naming the file) before anything is
// read out of range, outside the folder or over the budget; never in a crash,
// a hang or a partial scene. Well-formed loading is tested in test_loader.cpp.
#include <catch2/catch.hpp>

#include "host/gltf/gltf_loader.h"
#include "host/image/image_io.h"
#include "tests/support/test_support.h"
#include "tests/unit/loader_test_helpers.h"

#include <sys/stat.h>

#include <cstring>
#include <fstream>
#include <string>

using namespace rast;
using namespace rast::loader_test;
using Catch::Matchers::Contains;

TEST_CASE("loader: missing, empty, garbage and non-glTF files", "[loader]") {
  TempDir d;
  CHECK_THAT(loadError(d.file("nope.gltf")), Contains("cannot open") && Contains("No such file"));
  fs::create_directories(d.file("adir.gltf"));
  CHECK_THAT(loadError(d.file("adir.gltf")), Contains("is a directory"));
  CHECK_THAT(loadError(d.write("empty.gltf", "")), Contains("is empty"));
  CHECK_THAT(loadError(d.write("garbage.gltf", std::string("\x01\x02garbage\n\xff", 11))), Contains("invalid JSON"));
  CHECK_THAT(loadError(d.write("array.gltf", "[1,2]")), Contains("JSON root is not an object"));
  CHECK_THAT(loadError(d.write("noasset.gltf", "{}")), Contains("asset: required property is missing"));
  CHECK_THAT(loadError(d.write("v1.gltf", R"({"asset":{"version":"1.0"}})")), Contains("is not 2.x"));
  // Deep nesting is refused before tinygltf, which recurses on extras.
  const std::string deep = R"({"asset":{"version":"2.0"},"extras":)" + std::string(100000, '[') +
                           std::string(100000, ']') + "}";
  CHECK_THAT(loadError(d.write("deep.gltf", deep)), Contains("nested deeper than"));
  // Every message is one line.
  for (const char* f : {"nope.gltf", "adir.gltf", "empty.gltf", "garbage.gltf", "deep.gltf"})
    CHECK(loadError(d.file(f)).find('\n') == std::string::npos);
}

TEST_CASE("loader: truncated and damaged GLB files fail cleanly", "[loader]") {
  const std::string dir = test::assimpDir();
  if (dir.empty()) {
    test::skipTest("assimp-testmodels is not installed");
    return;
  }
  std::ifstream f(dir + "/BoxTextured-glTF-Binary/BoxTextured.glb", std::ios::binary);
  const std::string glb((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  REQUIRE(glb.size() > 1000);
  TempDir d;
  CHECK_NOTHROW(loadGltf(d.write("whole.glb", glb)));
  // Every cut loses data that the file needs (the BIN chunk ends the file).
  for (size_t cut = 1; cut < glb.size(); cut += (cut < 64 ? 1 : 97)) {
    INFO("cut at " << cut);
    const std::string msg = loadError(d.write("cut.glb", glb.substr(0, cut)));
    CHECK(msg != "<loaded>");
    CHECK(msg.find('\n') == std::string::npos);
  }
  CHECK_THAT(loadError(d.write("cut.glb", glb.substr(0, glb.size() / 2))), Contains("truncated GLB"));
  // A header whose lengths lie (BIN chunk longer than the file says).
  std::string bad = glb;
  uint32_t jsonLen;
  std::memcpy(&jsonLen, &bad[12], 4);
  const uint32_t huge = 0x7fffff00u;
  std::memcpy(&bad[20 + jsonLen], &huge, 4);
  CHECK_THAT(loadError(d.write("bad.glb", bad)), Contains("BIN chunk reaches past the end"));
  std::string v1 = glb;
  v1[4] = 1;
  CHECK_THAT(loadError(d.write("v1.glb", v1)), Contains("GLB container version 1"));
}

TEST_CASE("loader: a BIN chunk header 8 bytes short of its data is refused", "[loader]") {
  // tinygltf 2.7 only checks jsonEnd + binLength <= length, forgetting the
  // 8-byte chunk header: it would copy 4 bytes past the end of the file here.
  TempDir d;
  std::string js = R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":8}]})";
  while (js.size() % 4) js += ' ';
  auto le32 = [](uint32_t v) { return std::string{char(v & 0xff), char((v >> 8) & 0xff), char((v >> 16) & 0xff), char(v >> 24)}; };
  const std::string body = le32(uint32_t(js.size())) + "JSON" + js + le32(8) + std::string("BIN\0", 4) + "\1\2\3\4";
  const std::string glb = "glTF" + le32(2) + le32(uint32_t(12 + body.size())) + body;
  CHECK_THAT(loadError(d.write("short.glb", glb)), Contains("BIN chunk reaches past the end"));
}

TEST_CASE("loader: a FIFO is refused instead of blocking", "[loader]") {
  TempDir d;
  REQUIRE(::mkfifo(d.file("fifo.gltf").c_str(), 0600) == 0);
  CHECK_THAT(loadError(d.file("fifo.gltf")), Contains("is not a regular file"));
}

TEST_CASE("loader: accessor and bufferView ranges", "[loader]") {
  TempDir d;
  SECTION("accessor reaching past its bufferView") {
    Doc doc;
    const int v = doc.view(kTriangle);
    doc.prim({{"attributes", {{"POSITION", doc.accessor(v, kF32, 3, "VEC3", 4)}}}});
    CHECK_THAT(docError(doc, d, "acc"), Contains("POSITION: accessor reaches past the end of bufferView 0"));
  }
  SECTION("bufferView reaching past its buffer") {
    Doc doc;
    const int v = doc.view(kTriangle);
    doc.j["bufferViews"][v]["byteLength"] = 40;
    doc.prim({{"attributes", {{"POSITION", doc.accessor(v, kF32, 3, "VEC3")}}}});
    CHECK_THAT(docError(doc, d, "bv"), Contains("bufferView 0 reaches past the end of its buffer"));
  }
  SECTION("counts whose byte size overflows are refused, not wrapped") {
    Doc doc;
    const int v = doc.view(kTriangle);
    // 0x5555555555555556 * 12 wraps to 8 in 64 bits.
    doc.prim({{"attributes", {{"POSITION", doc.accessor(v, kF32, size_t(1) << 40, "VEC3")}}}});
    CHECK_THAT(docError(doc, d, "huge"), Contains("count 1099511627776 is too large"));
    doc.j["accessors"][0]["count"] = 0x5555555555555556ull;
    CHECK_THAT(docError(doc, d, "huge2"), Contains("accessors[0].count: expected an unsigned integer"));
    doc.j["accessors"][0]["count"] = 1431655766;  // * 12 > 2^32
    CHECK_THAT(docError(doc, d, "huge3"), Contains("accessor reaches past the end of bufferView"));
  }
  SECTION("index accessor out of range and wrong types") {
    Doc doc;
    const int pos = doc.vec3(kTriangle);
    doc.prim({{"attributes", {{"POSITION", pos}}}, {"indices", 7}});
    CHECK_THAT(docError(doc, d, "idx"), Contains("indices accessor out of bounds"));  // tinygltf checks this one
    doc.j["meshes"][0]["primitives"][0]["indices"] = pos;
    CHECK_THAT(docError(doc, d, "idx2"), Contains("indices accessor is not SCALAR"));
    doc.j["meshes"][0]["primitives"][0].erase("indices");
    doc.j["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = doc.floats({0, 0, 1, 0, 0, 1}, "VEC2", 2);
    CHECK_THAT(docError(doc, d, "idx3"), Contains("POSITION: accessor 1 has the wrong type"));
  }
  SECTION("an image bufferView past its buffer is refused before decoding") {
    Doc doc = texturedTriangle("unused.png");
    const int v = doc.view(kTriangle);
    doc.j["images"][0] = {{"bufferView", v}, {"mimeType", "image/png"}};
    doc.j["bufferViews"][v]["byteLength"] = 1000000;
    CHECK_THAT(docError(doc, d, "imgbv"), Contains("images[0].bufferView: bufferView 2 reaches past the end of buffer 0"));
  }
}

// ---------------------------------------------------------------- security and resource limits

namespace {

std::string base64(const std::string& in) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const uint32_t v = uint32_t(uint8_t(in[i])) << 16 | uint32_t(uint8_t(in[i + 1])) << 8 | uint8_t(in[i + 2]);
    out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], t[v & 63]};
  }
  if (i + 1 == in.size()) {
    const uint32_t v = uint32_t(uint8_t(in[i])) << 16;
    out += {t[v >> 18], t[(v >> 12) & 63], '=', '='};
  } else if (i + 2 == in.size()) {
    const uint32_t v = uint32_t(uint8_t(in[i])) << 16 | uint32_t(uint8_t(in[i + 1])) << 8;
    out += {t[v >> 18], t[(v >> 12) & 63], t[(v >> 6) & 63], '='};
  }
  return out;
}

// Writes `doc` as FOLDER/NAME.gltf with its buffer embedded as a data: URI.
std::string writeEmbedded(const Doc& doc, const TempDir& d, const std::string& folder, const std::string& name) {
  json out = doc.j;
  out["buffers"] = json::array(
      {{{"uri", "data:application/octet-stream;base64," + base64(doc.bin)}, {"byteLength", doc.bin.size()}}});
  fs::create_directories(d.file(folder));
  return d.write(folder + "/" + name + ".gltf", out.dump());
}

std::string readAll(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), {});
}

}  // namespace

TEST_CASE("loader: external files stay inside the scene's folder", "[loader][security]") {
  TempDir d;
  // A readable image beside (not inside) the scene's folder, and one inside.
  writePng(d.file("secret.png"), 2, 2, {0xff0000ffu, 0xff00ff00u, 0xffff0000u, 0xffffffffu});
  fs::create_directories(d.file("scene/tex"));
  fs::copy_file(d.file("secret.png"), d.file("scene/tex/inside.png"));
  const std::string secret = fs::canonical(d.file("secret.png")).string();
  const auto refused = [&](const std::string& uri, const std::string& name) {
    return loadError(writeEmbedded(texturedTriangle(uri), d, "scene", name));
  };
  const std::string outside = "refusing to read '" + secret + "': it is outside the scene's folder";
  CHECK_THAT(refused("../secret.png", "dotdot"), Contains(outside));
  CHECK_THAT(refused("%2e%2e/secret.png", "encoded"), Contains(outside));
  CHECK_THAT(refused("tex/../../secret.png", "deeper"), Contains(outside));
  CHECK_THAT(refused(secret, "absolute"), Contains("refusing to read '" + secret + "': an absolute path"));
  CHECK_THAT(refused("%2F" + secret.substr(1), "absenc"), Contains("an absolute path"));
  fs::create_symlink(secret, d.file("scene/link.png"));
  CHECK_THAT(refused("link.png", "symlink"), Contains(outside));
  // One line, naming the file given on the command line.
  CHECK(refused("../secret.png", "oneline").find('\n') == std::string::npos);

  SECTION("a buffer outside the folder is refused by the same resolver") {
    Doc doc;
    doc.prim({{"attributes", {{"POSITION", doc.vec3(kTriangle)}}}});
    d.write("outside.bin", doc.bin);
    json j = doc.j;
    j["buffers"] = json::array({{{"uri", "../outside.bin"}, {"byteLength", doc.bin.size()}}});
    const std::string p = d.write("scene/buf.gltf", j.dump());
    const std::string resolved = fs::canonical(d.file("outside.bin")).string();
    CHECK_THAT(loadError(p), Contains("buffers[0]: refusing to read '" + resolved + "'"));
    LoadOptions allow;
    allow.allowExternalFiles = true;
    CHECK(loadGltf(p, allow).triangleCount() == 1);
  }
  SECTION("inside the folder, data: URIs, and --allow-external-files still load") {
    CHECK(loadGltf(writeEmbedded(texturedTriangle("tex/inside.png"), d, "scene", "ok")).textures.at(0).width == 2);
    CHECK(loadGltf(writeEmbedded(texturedTriangle("tex%2Finside.png"), d, "scene", "okenc")).textures.size() == 1);
    const std::string uri = "data:image/png;base64," + base64(readAll(d.file("secret.png")));
    CHECK(loadGltf(writeEmbedded(texturedTriangle(uri), d, "scene", "datauri")).textures.at(0).height == 2);
    LoadOptions allow;
    allow.allowExternalFiles = true;
    CHECK(loadGltf(writeEmbedded(texturedTriangle("../secret.png"), d, "scene", "allowed"), allow).textures.size() == 1);
    CHECK(loadGltf(writeEmbedded(texturedTriangle(secret), d, "scene", "allowedabs"), allow).textures.size() == 1);
  }
}

TEST_CASE("loader: stb_image's own reason in image errors", "[loader][security]") {
  TempDir d;
  d.write("huge.png", pngHeader(100000, 100000));
  CHECK_THAT(docError(texturedTriangle("huge.png"), d, "huge"), Contains("image 0: cannot decode (stb_image: too large)"));
  d.write("gif.png", "GIF89a\x01\x00\x01\x00\x80\x00\x00");
  const std::string gif = docError(texturedTriangle("gif.png"), d, "gif");
  CHECK_THAT(gif, Contains("image 0: is GIF, not PNG or JPEG, the image formats glTF allows"));  // issue 38
  CHECK_THAT(gif, !Contains("Unknown image format"));
}

TEST_CASE("loader: memory budget and counts out of proportion to the file", "[loader][security]") {
  TempDir d;
  SECTION("a few hundred bytes claiming 2^24 zero-filled vertices") {
    Doc doc;
    const int a = doc.accessor(-1, kF32, size_t(1) << 24, "VEC3");
    for (int k = 0; k < 4; ++k) doc.prim({{"attributes", {{"POSITION", a}}}, {"mode", 5}});
    CHECK_THAT(docError(doc, d, "zeros"), Contains("has no bufferView and a count of 16777216, out of proportion"));
  }
  SECTION("zero-filled accessors in proportion to the file still load") {
    Doc doc;
    const int a = doc.accessor(-1, kF32, 30000, "VEC3");  // degenerate, but legal
    doc.prim({{"attributes", {{"POSITION", a}}}});
    doc.prim({{"attributes", {{"POSITION", doc.vec3(kTriangle)}}}});
    CHECK(loadDoc(doc, d, "fewzeros").triangleCount() == 10001);
  }
  SECTION("a strip of many indices over the budget is refused before it is read") {
    Doc doc;
    std::vector<uint8_t> idx(300000, 0);
    idx[1] = 1;
    idx[2] = 2;
    doc.prim({{"attributes", {{"POSITION", doc.vec3(kTriangle)}}},
              {"indices", doc.accessor(doc.view(idx), kU8, idx.size(), "SCALAR")},
              {"mode", 5}});
    LoadOptions small;
    small.maxMemory = 8 << 20;
    const std::string msg = [&] {
      try {
        loadGltf(doc.write(d, "strip"), small);
      } catch (const Error& e) {
        return std::string(e.what());
      }
      return std::string("<loaded>");
    }();
    CHECK_THAT(msg, Contains("mesh primitive (3 vertices, 299998 triangles) needs"));
    CHECK_THAT(msg, Contains("over the memory budget of 8.00 MiB by"));
    CHECK(loadDoc(doc, d, "strip2").triangleCount() == 299998);  // the default budget takes it
  }
  SECTION("decoded image size against the budget, before decoding") {
    d.write("big.png", pngHeader(16384, 16384));
    LoadOptions small;
    small.maxMemory = 512 << 20;
    try {
      loadGltf(texturedTriangle("big.png").write(d, "bigimg"), small);
      FAIL("loaded");
    } catch (const Error& e) {
      CHECK_THAT(std::string(e.what()), Contains("image 0 (16384x16384 texels, decoded) needs 3.00 GiB"));
    }
  }
  SECTION("declared buffer sizes against the budget") {
    Doc doc;
    doc.prim({{"attributes", {{"POSITION", doc.vec3(kTriangle)}}}});
    json j = doc.j;
    j["buffers"] = json::array({{{"byteLength", uint64_t(1) << 40}}});
    CHECK_THAT(loadError(d.write("bigbuf.gltf", j.dump())), Contains("buffers[0] (byteLength 1099511627776) needs 1.00 TiB"));
  }
}
