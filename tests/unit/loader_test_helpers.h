// What both halves of the loader's tests (test_loader.cpp: well-formed files
// load right; test_loader_input.cpp: malformed and hostile input fails
// cleanly) build their inputs with: a scratch folder, a small glTF document
// assembled in code (Doc), a textured triangle, a PNG header of any claimed
// size, and loadError, which turns loadGltf's Error into a string to match.
// Shared here so that the two files write their glTF files the same way.
#pragma once

#include "host/gltf/gltf_loader.h"

#include <nlohmann/json.hpp>

#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace rast::loader_test {

using json = nlohmann::json;
namespace fs = std::filesystem;

// The message of the Error loadGltf throws, or "<loaded>".
inline std::string loadError(const std::string& path) {
  try {
    loadGltf(path);
  } catch (const Error& e) {
    return e.what();
  }
  return "<loaded>";
}

constexpr int kU8 = 5121, kU16 = 5123, kU32 = 5125, kF32 = 5126;

class TempDir {
 public:
  TempDir() {
    path_ = fs::temp_directory_path() / ("rast_test_loader_" + std::to_string(::getpid()));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  std::string write(const std::string& name, const std::string& bytes) const {
    std::ofstream f(file(name), std::ios::binary);
    f.write(bytes.data(), std::streamsize(bytes.size()));
    return file(name);
  }

 private:
  fs::path path_;
};

// A glTF document with one buffer (written beside it as NAME.bin), one scene,
// one node drawing mesh 0. Helpers append bufferViews and accessors.
struct Doc {
  json j;
  std::string bin;

  Doc() {
    j = {{"asset", {{"version", "2.0"}}},
         {"scene", 0},
         {"scenes", json::array({{{"nodes", {0}}}})},
         {"nodes", json::array({{{"mesh", 0}}})},
         {"meshes", json::array({{{"primitives", json::array()}}})},
         {"accessors", json::array()},
         {"bufferViews", json::array()}};
  }

  // Raw bytes as a new bufferView (4-byte aligned); returns its index.
  int view(const void* p, size_t n, int stride = 0) {
    while (bin.size() % 4) bin.push_back('\0');
    json v = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", n}};
    if (stride) v["byteStride"] = stride;
    bin.append(static_cast<const char*>(p), n);
    j["bufferViews"].push_back(v);
    return int(j["bufferViews"].size() - 1);
  }
  template <class T>
  int view(const std::vector<T>& v, int stride = 0) {
    return view(v.data(), v.size() * sizeof(T), stride);
  }

  int accessor(int bufferView, int componentType, size_t count, const char* type, size_t byteOffset = 0) {
    json a = {{"componentType", componentType}, {"count", count}, {"type", type}};
    if (bufferView >= 0) a["bufferView"] = bufferView;
    if (byteOffset) a["byteOffset"] = byteOffset;
    j["accessors"].push_back(a);
    return int(j["accessors"].size() - 1);
  }
  int floats(const std::vector<float>& v, const char* type, int comps) {
    return accessor(view(v), kF32, v.size() / comps, type);
  }
  int vec3(const std::vector<float>& v) { return floats(v, "VEC3", 3); }

  void prim(const json& p) { j["meshes"][0]["primitives"].push_back(p); }

  std::string write(const TempDir& d, const std::string& name) const {
    json out = j;
    if (!bin.empty()) out["buffers"] = json::array({{{"uri", name + ".bin"}, {"byteLength", bin.size()}}});
    d.write(name + ".bin", bin);
    return d.write(name + ".gltf", out.dump());
  }
};

// One triangle in the xy plane, counter-clockwise seen from +z.
inline const std::vector<float> kTriangle = {0, 0, 0, 1, 0, 0, 0, 1, 0};

inline Scene loadDoc(const Doc& doc, const TempDir& d, const std::string& name) { return loadGltf(doc.write(d, name)); }
inline std::string docError(const Doc& doc, const TempDir& d, const std::string& name) {
  return loadError(doc.write(d, name));
}

// A PNG signature and IHDR chunk claiming w x h RGBA8 (stb does not check CRCs).
inline std::string pngHeader(uint32_t w, uint32_t h) {
  auto be32 = [](uint32_t v) {
    return std::string{char(v >> 24), char((v >> 16) & 0xff), char((v >> 8) & 0xff), char(v & 0xff)};
  };
  std::string s = "\x89PNG\r\n\x1a\n";
  s += be32(13) + "IHDR" + be32(w) + be32(h) + std::string{8, 6, 0, 0, 0} + be32(0);
  return s;
}

// A textured triangle whose image is the file `imageUri`.
inline Doc texturedTriangle(const std::string& imageUri) {
  Doc doc;
  const int pos = doc.vec3(kTriangle);
  const int uv = doc.floats({0, 0, 1, 0, 0, 1}, "VEC2", 2);
  doc.prim({{"attributes", {{"POSITION", pos}, {"TEXCOORD_0", uv}}}, {"material", 0}});
  doc.j["materials"] = json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
  doc.j["textures"] = json::array({{{"source", 0}}});
  doc.j["images"] = json::array({{{"uri", imageUri}}});
  return doc;
}

}  // namespace rast::loader_test
