// glTF 2.0 loading through tinygltf, with every index and range checked so that
// a malformed file ends in one clear Error, never in a crash, a hang or a
// partial scene.
//
// Before tinygltf sees a file, loadGltf reads it whole and checks it itself:
//  - the file is a regular, non-empty file (a FIFO would hang the reader);
//  - the GLB container: header, chunk bounds (tinygltf 2.7 lets the BIN chunk
//    reach 8 bytes past the end of the data);
//  - the JSON: nesting depth (tinygltf parses `extras` recursively), syntax;
//  - the type of every core glTF property: tinygltf silently ignores a property
//    of the wrong type (a string `scene`, an object `primitives`, index -1, ...)
//    where the glTF schema makes the file invalid;
//  - extensionsRequired: a file needing an extension rast lacks is refused;
//  - image bufferView ranges (tinygltf 2.7 reads an image's bufferView without
//    checking it against its buffer) and that external buffers exist.
// tinygltf then parses the same bytes; the Loader walks the model with every
// index, count and byte range checked again.
#include "gltf_loader.h"

#include <tiny_gltf.h>

#include <nlohmann/json.hpp>
#include <stb/stb_image.h>

#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>

namespace rast {
namespace {

using Json = nlohmann::json;

constexpr uint64_t kMaxFileBytes = 0xffffffffull;    // GLB lengths are 32-bit; so is tinygltf's API
constexpr size_t kMaxJsonDepth = 128;                // tinygltf recurses on nested JSON (extras)
constexpr int kMaxTextureSide = 16384;               // same limit as the image size
constexpr size_t kMaxAccessorCount = 0xffffffffull;  // vertex indices are 32-bit
constexpr size_t kMaxZeroAccessorCount = size_t(1) << 24;  // accessors without a bufferView (zeros + sparse)

// Makes a message printable on one line: control characters become spaces.
std::string oneLine(std::string s) {
  for (char& c : s)
    if ((unsigned char)c < 0x20 || c == 0x7f) c = ' ';
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

// ---------------------------------------------------------------- file and GLB container

std::vector<unsigned char> readWholeFile(const std::string& path) {
  struct stat st;
  if (::stat(path.c_str(), &st) != 0) throw Error("cannot open '" + path + "': " + std::strerror(errno));
  if (S_ISDIR(st.st_mode)) throw Error("'" + path + "' is a directory, not a glTF file");
  if (!S_ISREG(st.st_mode)) throw Error("'" + path + "' is not a regular file");
  if (st.st_size == 0) throw Error("'" + path + "' is empty, not a glTF file");
  if (uint64_t(st.st_size) > kMaxFileBytes) throw Error("'" + path + "' is larger than 4 GiB");
  std::ifstream f(path, std::ios::binary);
  if (!f) throw Error("cannot open '" + path + "': " + std::strerror(errno));
  std::vector<unsigned char> bytes(size_t(st.st_size));
  f.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size()));
  if (size_t(f.gcount()) != bytes.size()) throw Error("cannot read '" + path + "'");
  return bytes;
}

// tinygltf's file reader for external buffers and images, with the checks of
// readWholeFile: tinygltf's own sizes a directory as a huge file (bad_alloc).
bool readFileForTinygltf(std::vector<unsigned char>* out, std::string* err, const std::string& path, void*) {
  try {
    *out = readWholeFile(path);
    return true;
  } catch (const Error& e) {
    if (err) *err += std::string(e.what()) + "\n";
    return false;
  }
}

uint32_t u32le(const unsigned char* p) {
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

// Checks the GLB header and chunk layout; returns the container length (the
// bytes that belong to the GLB) and where the JSON chunk lies.
struct GlbLayout {
  size_t length = 0, jsonOffset = 0, jsonLength = 0;
};

GlbLayout checkGlb(const std::vector<unsigned char>& b) {
  if (b.size() < 20) throw Error("truncated GLB: " + std::to_string(b.size()) + " bytes, less than its 20-byte header");
  const uint32_t version = u32le(&b[4]), length = u32le(&b[8]), jsonLength = u32le(&b[12]), jsonType = u32le(&b[16]);
  if (version != 2) throw Error("GLB container version " + std::to_string(version) + " is not 2");
  if (length > b.size())
    throw Error("truncated GLB: the header says " + std::to_string(length) + " bytes, the file has " +
                std::to_string(b.size()));
  if (length < 20 || jsonType != 0x4E4F534Au) throw Error("invalid GLB: the first chunk is not JSON");
  if (20ull + jsonLength > length) throw Error("truncated GLB: the JSON chunk reaches past the end of the data");
  const uint64_t rest = length - 20ull - jsonLength;
  if (rest > 0) {
    if (rest < 8) throw Error("truncated GLB: incomplete chunk header after the JSON chunk");
    const uint32_t binLength = u32le(&b[20 + jsonLength]);
    if (8ull + binLength > rest) throw Error("truncated GLB: the BIN chunk reaches past the end of the data");
  }
  return {length, 20, jsonLength};
}

// ---------------------------------------------------------------- JSON and glTF schema

void checkJsonDepth(const char* s, size_t n) {
  size_t depth = 0;
  bool inString = false, escaped = false;
  for (size_t i = 0; i < n; ++i) {
    const char c = s[i];
    if (inString) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') inString = false;
    } else if (c == '"') {
      inString = true;
    } else if (c == '{' || c == '[') {
      if (++depth > kMaxJsonDepth) throw Error("JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
    } else if ((c == '}' || c == ']') && depth > 0) {
      --depth;
    }
  }
}

Json parseJson(const char* s, size_t n) {
  checkJsonDepth(s, n);
  Json j;
  try {
    j = Json::parse(s, s + n);
  } catch (const Json::parse_error& e) {
    throw Error("not a glTF file: invalid JSON (syntax error at byte " + std::to_string(e.byte) + ")");
  } catch (const Json::exception& e) {
    throw Error("not a glTF file: invalid JSON (" + oneLine(e.what()) + ")");
  }
  if (!j.is_object()) throw Error("not a glTF file: the JSON root is not an object");
  return j;
}

// The type of each property of the core glTF 2.0 schema (glTF.schema.json and
// what it references). Extension and extras contents are not checked, except
// that every value of an `extensions` object must be an object.
enum class Kind {
  Obj,       // object, checked against `sub`
  ObjArr,    // array of objects, each checked against `sub`
  Id,        // glTF id: integer in [0, 2^31)
  Int,       // other integer stored as an int by tinygltf: [0, 2^31)
  Uint,      // integer stored as a size_t by tinygltf: [0, 2^53]
  Num,       // any number
  Bool,
  Str,
  IdArr,     // array of glTF ids
  NumArr,    // array of numbers, `len` elements when len > 0
  StrArr,
  IdMap,     // object whose values are glTF ids (primitive attributes)
  IdMapArr,  // array of IdMap (morph targets)
};

struct ObjSchema;
struct Field {
  const char* name;
  Kind kind;
  bool required = false;
  const ObjSchema* sub = nullptr;
  int len = 0;
};
struct ObjSchema {
  std::vector<Field> fields;
};

const ObjSchema& gltfSchema() {
  using K = Kind;
  static const ObjSchema textureInfo{{{"index", K::Id, true}, {"texCoord", K::Int}}};
  static const ObjSchema normalTextureInfo{{{"index", K::Id, true}, {"texCoord", K::Int}, {"scale", K::Num}}};
  static const ObjSchema occlusionTextureInfo{{{"index", K::Id, true}, {"texCoord", K::Int}, {"strength", K::Num}}};
  static const ObjSchema pbr{{{"baseColorFactor", K::NumArr, false, nullptr, 4},
                              {"baseColorTexture", K::Obj, false, &textureInfo},
                              {"metallicFactor", K::Num},
                              {"roughnessFactor", K::Num},
                              {"metallicRoughnessTexture", K::Obj, false, &textureInfo}}};
  static const ObjSchema material{{{"pbrMetallicRoughness", K::Obj, false, &pbr},
                                   {"normalTexture", K::Obj, false, &normalTextureInfo},
                                   {"occlusionTexture", K::Obj, false, &occlusionTextureInfo},
                                   {"emissiveTexture", K::Obj, false, &textureInfo},
                                   {"emissiveFactor", K::NumArr, false, nullptr, 3},
                                   {"alphaMode", K::Str},
                                   {"alphaCutoff", K::Num},
                                   {"doubleSided", K::Bool}}};
  static const ObjSchema primitive{{{"attributes", K::IdMap, true},
                                    {"indices", K::Id},
                                    {"material", K::Id},
                                    {"mode", K::Int},
                                    {"targets", K::IdMapArr}}};
  static const ObjSchema mesh{{{"primitives", K::ObjArr, true, &primitive}, {"weights", K::NumArr}}};
  static const ObjSchema node{{{"camera", K::Id},
                               {"children", K::IdArr},
                               {"skin", K::Id},
                               {"matrix", K::NumArr, false, nullptr, 16},
                               {"mesh", K::Id},
                               {"rotation", K::NumArr, false, nullptr, 4},
                               {"scale", K::NumArr, false, nullptr, 3},
                               {"translation", K::NumArr, false, nullptr, 3},
                               {"weights", K::NumArr}}};
  static const ObjSchema scene{{{"nodes", K::IdArr}}};
  static const ObjSchema sparseIndices{{{"bufferView", K::Id, true}, {"byteOffset", K::Int}, {"componentType", K::Int, true}}};
  static const ObjSchema sparseValues{{{"bufferView", K::Id, true}, {"byteOffset", K::Int}}};
  static const ObjSchema sparse{{{"count", K::Int, true},
                                 {"indices", K::Obj, true, &sparseIndices},
                                 {"values", K::Obj, true, &sparseValues}}};
  static const ObjSchema accessor{{{"bufferView", K::Id},
                                   {"byteOffset", K::Uint},
                                   {"componentType", K::Int, true},
                                   {"normalized", K::Bool},
                                   {"count", K::Uint, true},
                                   {"type", K::Str, true},
                                   {"max", K::NumArr},
                                   {"min", K::NumArr},
                                   {"sparse", K::Obj, false, &sparse}}};
  static const ObjSchema bufferView{{{"buffer", K::Id, true},
                                     {"byteOffset", K::Uint},
                                     {"byteLength", K::Uint, true},
                                     {"byteStride", K::Uint},
                                     {"target", K::Int}}};
  static const ObjSchema buffer{{{"uri", K::Str}, {"byteLength", K::Uint, true}}};
  static const ObjSchema image{{{"uri", K::Str}, {"mimeType", K::Str}, {"bufferView", K::Id}}};
  static const ObjSchema texture{{{"sampler", K::Id}, {"source", K::Id}}};
  static const ObjSchema sampler{{{"magFilter", K::Int}, {"minFilter", K::Int}, {"wrapS", K::Int}, {"wrapT", K::Int}}};
  static const ObjSchema skin{{{"inverseBindMatrices", K::Id}, {"skeleton", K::Id}, {"joints", K::IdArr, true}}};
  static const ObjSchema perspective{{{"aspectRatio", K::Num}, {"yfov", K::Num, true}, {"zfar", K::Num}, {"znear", K::Num, true}}};
  static const ObjSchema orthographic{{{"xmag", K::Num, true}, {"ymag", K::Num, true}, {"zfar", K::Num, true}, {"znear", K::Num, true}}};
  static const ObjSchema camera{{{"type", K::Str, true},
                                 {"perspective", K::Obj, false, &perspective},
                                 {"orthographic", K::Obj, false, &orthographic}}};
  static const ObjSchema channelTarget{{{"node", K::Id}, {"path", K::Str, true}}};
  static const ObjSchema channel{{{"sampler", K::Id, true}, {"target", K::Obj, true, &channelTarget}}};
  static const ObjSchema animSampler{{{"input", K::Id, true}, {"interpolation", K::Str}, {"output", K::Id, true}}};
  static const ObjSchema animation{{{"channels", K::ObjArr, true, &channel}, {"samplers", K::ObjArr, true, &animSampler}}};
  static const ObjSchema asset{{{"copyright", K::Str}, {"generator", K::Str}, {"version", K::Str, true}, {"minVersion", K::Str}}};
  static const ObjSchema root{{{"asset", K::Obj, true, &asset},
                               {"extensionsUsed", K::StrArr},
                               {"extensionsRequired", K::StrArr},
                               {"scene", K::Id},
                               {"scenes", K::ObjArr, false, &scene},
                               {"nodes", K::ObjArr, false, &node},
                               {"meshes", K::ObjArr, false, &mesh},
                               {"accessors", K::ObjArr, false, &accessor},
                               {"bufferViews", K::ObjArr, false, &bufferView},
                               {"buffers", K::ObjArr, false, &buffer},
                               {"images", K::ObjArr, false, &image},
                               {"textures", K::ObjArr, false, &texture},
                               {"samplers", K::ObjArr, false, &sampler},
                               {"materials", K::ObjArr, false, &material},
                               {"skins", K::ObjArr, false, &skin},
                               {"cameras", K::ObjArr, false, &camera},
                               {"animations", K::ObjArr, false, &animation}}};
  return root;
}

class SchemaChecker {
 public:
  void object(const Json& v, const ObjSchema& s, const std::string& where) const {
    if (!v.is_object()) wrongType(where, "an object", v);
    for (const Field& f : s.fields)  // wrong types first: they say more than a missing property
      if (const auto it = v.find(f.name); it != v.end()) value(*it, f, join(where, f.name));
    for (const Field& f : s.fields)
      if (f.required && !v.contains(f.name)) throw Error(join(where, f.name) + ": required property is missing");
    if (const auto it = v.find("name"); it != v.end() && !it->is_string()) wrongType(join(where, "name"), "a string", *it);
    if (const auto it = v.find("extensions"); it != v.end()) {
      const std::string at = join(where, "extensions");
      if (!it->is_object()) wrongType(at, "an object", *it);
      for (auto e = it->begin(); e != it->end(); ++e)
        if (!e->is_object()) wrongType(at + "." + e.key(), "an object", *e);
    }
  }

 private:
  static std::string join(const std::string& where, const char* name) {
    return where.empty() ? std::string(name) : where + "." + name;
  }

  static std::string describe(const Json& v) {
    if (v.is_object()) return "an object";
    if (v.is_array()) return "an array";
    std::string s = v.dump(-1, ' ', true, Json::error_handler_t::replace);
    if (s.size() > 40) s = s.substr(0, 37) + "...";
    return s;
  }

  [[noreturn]] static void wrongType(const std::string& at, const char* expected, const Json& v) {
    throw Error(at + ": expected " + expected + ", got " + describe(v));
  }

  static void id(const Json& v, const std::string& at) {
    if (!v.is_number_unsigned() || v.get<uint64_t>() > uint64_t(std::numeric_limits<int32_t>::max()))
      wrongType(at, "an index (integer >= 0)", v);
  }

  static void int31(const Json& v, const std::string& at) {
    if (!v.is_number_unsigned() || v.get<uint64_t>() > uint64_t(std::numeric_limits<int32_t>::max()))
      wrongType(at, "an integer in 0..2147483647", v);
  }

  static void uint(const Json& v, const std::string& at) {
    if (!v.is_number_unsigned() || v.get<uint64_t>() > (uint64_t(1) << 53))
      wrongType(at, "an unsigned integer", v);
  }

  static void array(const Json& v, const std::string& at, int len) {
    if (!v.is_array()) wrongType(at, "an array", v);
    if (len > 0 && v.size() != size_t(len))
      throw Error(at + ": expected " + std::to_string(len) + " elements, got " + std::to_string(v.size()));
  }

  static std::string item(const std::string& at, size_t i) { return at + "[" + std::to_string(i) + "]"; }

  static void idMap(const Json& v, const std::string& at) {
    if (!v.is_object()) wrongType(at, "an object", v);
    for (auto e = v.begin(); e != v.end(); ++e) id(*e, at + "." + e.key());
  }

  void value(const Json& v, const Field& f, const std::string& at) const {
    switch (f.kind) {
      case Kind::Obj: object(v, *f.sub, at); break;
      case Kind::ObjArr:
        array(v, at, f.len);
        for (size_t i = 0; i < v.size(); ++i) object(v[i], *f.sub, item(at, i));
        break;
      case Kind::Id: id(v, at); break;
      case Kind::Int: int31(v, at); break;
      case Kind::Uint: uint(v, at); break;
      case Kind::Num:
        if (!v.is_number()) wrongType(at, "a number", v);
        break;
      case Kind::Bool:
        if (!v.is_boolean()) wrongType(at, "a boolean", v);
        break;
      case Kind::Str:
        if (!v.is_string()) wrongType(at, "a string", v);
        break;
      case Kind::IdArr:
        array(v, at, f.len);
        for (size_t i = 0; i < v.size(); ++i) id(v[i], item(at, i));
        break;
      case Kind::NumArr:
        array(v, at, f.len);
        for (size_t i = 0; i < v.size(); ++i)
          if (!v[i].is_number()) wrongType(item(at, i), "a number", v[i]);
        break;
      case Kind::StrArr:
        array(v, at, f.len);
        for (size_t i = 0; i < v.size(); ++i)
          if (!v[i].is_string()) wrongType(item(at, i), "a string", v[i]);
        break;
      case Kind::IdMap: idMap(v, at); break;
      case Kind::IdMapArr:
        array(v, at, f.len);
        for (size_t i = 0; i < v.size(); ++i) idMap(v[i], item(at, i));
        break;
    }
  }
};

// Extensions rast honours when a file requires them. KHR_mesh_quantization only
// widens the accessor component types allowed for attributes, which the
// AccessorReader reads anyway.
bool extensionSupported(const std::string& name) { return name == "KHR_mesh_quantization"; }

std::string urlDecode(const std::string& s) {
  std::string out;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '%' && i + 2 < s.size() && std::isxdigit((unsigned char)s[i + 1]) && std::isxdigit((unsigned char)s[i + 2])) {
      out += char(std::stoi(s.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += s[i];
    }
  }
  return out;
}

// What tinygltf leaves unchecked or reports unclearly, checked on the JSON.
void checkDocument(const Json& j, const std::string& baseDir) {
  SchemaChecker().object(j, gltfSchema(), "");

  if (const auto it = j.find("extensionsRequired"); it != j.end()) {
    std::string missing;
    for (const Json& e : *it)
      if (!extensionSupported(e.get<std::string>())) missing += (missing.empty() ? "" : ", ") + e.get<std::string>();
    if (!missing.empty()) throw Error("requires extension " + missing + ", which rast does not support");
  }

  // Images first: tinygltf 2.7 decodes an image's bufferView without checking
  // its range. Other bufferViews are checked where an accessor reads them.
  const Json none = Json::array();
  const Json& buffers = j.contains("buffers") ? j["buffers"] : none;
  const Json& views = j.contains("bufferViews") ? j["bufferViews"] : none;
  const Json& images = j.contains("images") ? j["images"] : none;
  for (size_t i = 0; i < images.size(); ++i) {
    const auto bv = images[i].find("bufferView");
    if (bv == images[i].end()) continue;
    const std::string at = "images[" + std::to_string(i) + "].bufferView";
    const uint64_t vi = bv->get<uint64_t>();
    if (vi >= views.size()) throw Error(at + ": index " + std::to_string(vi) + " out of range");
    const Json& v = views[vi];
    const uint64_t b = v["buffer"].get<uint64_t>();
    if (b >= buffers.size()) throw Error(at + ": buffer index " + std::to_string(b) + " out of range");
    const uint64_t off = v.value("byteOffset", uint64_t(0)), len = v["byteLength"].get<uint64_t>();
    const uint64_t bufLen = buffers[b]["byteLength"].get<uint64_t>();
    if (off + len > bufLen || len > uint64_t(std::numeric_limits<int>::max()))
      throw Error(at + ": bufferView " + std::to_string(vi) + " reaches past the end of buffer " + std::to_string(b) +
                  " (" + std::to_string(off) + " + " + std::to_string(len) + " > " + std::to_string(bufLen) + " bytes)");
  }
  for (size_t i = 0; i < buffers.size(); ++i) {
    const auto u = buffers[i].find("uri");
    if (u == buffers[i].end()) continue;
    const std::string uri = u->get<std::string>();
    if (uri.rfind("data:", 0) == 0) continue;
    const std::string decoded = urlDecode(uri);
    const std::string file = (decoded.empty() || decoded[0] == '/' || baseDir.empty()) ? decoded : baseDir + "/" + decoded;
    struct stat st;
    if (::stat(file.c_str(), &st) != 0)
      throw Error("buffers[" + std::to_string(i) + "]: file '" + uri + "' is missing (" + std::strerror(errno) + ")");
    if (!S_ISREG(st.st_mode)) throw Error("buffers[" + std::to_string(i) + "]: '" + uri + "' is not a regular file");
  }
}

// tinygltf's image decoder (stb_image), after a look at the header so that an
// absurd image size is refused before anything is allocated for it.
bool loadImageChecked(tinygltf::Image* image, const int index, std::string* err, std::string* warn, int reqWidth,
                      int reqHeight, const unsigned char* bytes, int size, void* user) {
  int w = 0, h = 0, comp = 0;
  if (size > 0 && stbi_info_from_memory(bytes, size, &w, &h, &comp) && (w > kMaxTextureSide || h > kMaxTextureSide)) {
    if (err)
      *err += "image " + std::to_string(index) + " is " + std::to_string(w) + "x" + std::to_string(h) +
              " texels, more than " + std::to_string(kMaxTextureSide) + " per side";
    return false;
  }
  return tinygltf::LoadImageData(image, index, err, warn, reqWidth, reqHeight, bytes, size, user);
}

// ---------------------------------------------------------------- model walk

// Reads accessor `index` as `count` rows of `comps` floats (normalized integers
// mapped to [0,1] or [-1,1] as the spec says), honouring byteStride and sparse
// substitution. Every byte range is checked before anything is allocated or read.
class AccessorReader {
 public:
  explicit AccessorReader(const tinygltf::Model& m) : m_(m) {}

  std::vector<float> floats(int index, int comps, const char* what) const {
    const tinygltf::Accessor& a = accessor(index, what);
    if (tinygltf::GetNumComponentsInType(a.type) != comps)
      throw Error(std::string(what) + ": accessor " + std::to_string(index) + " has the wrong type");
    checkCount(a, index, what);
    const Span sp = a.bufferView >= 0 ? span(a, comps, what) : Span{nullptr, 0, 0};
    std::vector<float> out(a.count * comps, 0.0f);
    if (sp.data) {
      for (size_t i = 0; i < a.count; ++i)
        for (int c = 0; c < comps; ++c)
          out[i * comps + c] = component(sp.data + i * sp.stride + c * sp.compSize, a.componentType, a.normalized, what);
    }
    applySparse(a, comps, what, [&](size_t row, const unsigned char* p, size_t compSize) {
      for (int c = 0; c < comps; ++c)
        out[row * comps + c] = component(p + c * compSize, a.componentType, a.normalized, what);
    });
    return out;
  }

  std::vector<uint32_t> indices(int index) const {
    const char* what = "indices";
    const tinygltf::Accessor& a = accessor(index, what);
    if (a.type != TINYGLTF_TYPE_SCALAR) throw Error("indices accessor is not SCALAR");
    if (a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
        a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
      throw Error("indices accessor has a component type other than u8/u16/u32");
    checkCount(a, index, what);
    const Span sp = a.bufferView >= 0 ? span(a, 1, what) : Span{nullptr, 0, 0};
    std::vector<uint32_t> out(a.count, 0);
    if (sp.data)
      for (size_t i = 0; i < a.count; ++i) out[i] = uintAt(sp.data + i * sp.stride, a.componentType);
    applySparse(a, 1, what, [&](size_t row, const unsigned char* p, size_t) { out[row] = uintAt(p, a.componentType); });
    return out;
  }

  // The number of components of the accessor's type (-1 when the type is unknown).
  int components(int index, const char* what) const {
    return tinygltf::GetNumComponentsInType(accessor(index, what).type);
  }

 private:
  struct Span {
    const unsigned char* data;
    size_t stride, compSize;
  };

  const tinygltf::Accessor& accessor(int index, const char* what) const {
    if (index < 0 || size_t(index) >= m_.accessors.size())
      throw Error(std::string(what) + ": accessor index " + std::to_string(index) + " out of range");
    return m_.accessors[index];
  }

  static void checkCount(const tinygltf::Accessor& a, int index, const char* what) {
    const size_t limit = a.bufferView >= 0 ? kMaxAccessorCount : kMaxZeroAccessorCount;
    if (a.count > limit)
      throw Error(std::string(what) + ": accessor " + std::to_string(index) + " count " + std::to_string(a.count) +
                  " is too large");
  }

  static size_t compSizeOf(int componentType, const char* what) {
    const int s = tinygltf::GetComponentSizeInBytes(componentType);
    if (s <= 0) throw Error(std::string(what) + ": unknown component type " + std::to_string(componentType));
    return size_t(s);
  }

  // Bytes [offset, offset+len) of buffer view `bv`, checked against the buffer.
  const unsigned char* viewBytes(int bv, size_t offset, size_t len, const char* what) const {
    if (bv < 0 || size_t(bv) >= m_.bufferViews.size())
      throw Error(std::string(what) + ": bufferView index " + std::to_string(bv) + " out of range");
    const tinygltf::BufferView& v = m_.bufferViews[bv];
    if (v.buffer < 0 || size_t(v.buffer) >= m_.buffers.size())
      throw Error(std::string(what) + ": buffer index out of range");
    const tinygltf::Buffer& b = m_.buffers[v.buffer];
    if (v.byteOffset > b.data.size() || v.byteLength > b.data.size() - v.byteOffset)
      throw Error(std::string(what) + ": bufferView " + std::to_string(bv) + " reaches past the end of its buffer");
    if (offset > v.byteLength || len > v.byteLength - offset)
      throw Error(std::string(what) + ": accessor reaches past the end of bufferView " + std::to_string(bv));
    return b.data.data() + v.byteOffset + offset;
  }

  Span span(const tinygltf::Accessor& a, int comps, const char* what) const {
    const size_t cs = compSizeOf(a.componentType, what);
    const size_t elem = cs * size_t(comps);
    if (a.bufferView < 0 || size_t(a.bufferView) >= m_.bufferViews.size())
      throw Error(std::string(what) + ": bufferView index " + std::to_string(a.bufferView) + " out of range");
    const tinygltf::BufferView& bv = m_.bufferViews[a.bufferView];
    const size_t stride = bv.byteStride ? bv.byteStride : elem;
    if (stride < elem || stride > 256)
      throw Error(std::string(what) + ": byteStride " + std::to_string(stride) + " does not fit the element size");
    // count < 2^32 and stride <= 256: no overflow in 64 bits.
    const size_t len = a.count ? stride * (a.count - 1) + elem : 0;
    return {viewBytes(a.bufferView, a.byteOffset, len, what), stride, cs};
  }

  template <class F>
  void applySparse(const tinygltf::Accessor& a, int comps, const char* what, F&& put) const {
    if (!a.sparse.isSparse) return;
    if (a.sparse.count < 0 || size_t(a.sparse.count) > a.count)
      throw Error(std::string(what) + ": sparse count " + std::to_string(a.sparse.count) + " exceeds the accessor count");
    const size_t n = size_t(a.sparse.count);
    const int it = a.sparse.indices.componentType;
    if (it != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && it != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        it != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
      throw Error(std::string(what) + ": sparse indices have a component type other than u8/u16/u32");
    const size_t is = compSizeOf(it, what);
    const unsigned char* ip = viewBytes(a.sparse.indices.bufferView, a.sparse.indices.byteOffset, n * is, what);
    const size_t cs = compSizeOf(a.componentType, what);
    const unsigned char* vp = viewBytes(a.sparse.values.bufferView, a.sparse.values.byteOffset, n * cs * comps, what);
    for (size_t k = 0; k < n; ++k) {
      const uint32_t row = uintAt(ip + k * is, it);
      if (row >= a.count) throw Error(std::string(what) + ": sparse index " + std::to_string(row) + " out of range");
      put(row, vp + k * cs * comps, cs);
    }
  }

  static uint32_t uintAt(const unsigned char* p, int type) {
    switch (type) {
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return *p;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t v; memcpy(&v, p, 2); return v; }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { uint32_t v; memcpy(&v, p, 4); return v; }
      default: throw Error("index component type is not unsigned");
    }
  }

  static float component(const unsigned char* p, int type, bool normalized, const char* what) {
    switch (type) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT: { float v; memcpy(&v, p, 4); return v; }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? *p / 255.0f : float(*p);
      case TINYGLTF_COMPONENT_TYPE_BYTE: { int8_t v; memcpy(&v, p, 1); return normalized ? std::max(v / 127.0f, -1.0f) : float(v); }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t v; memcpy(&v, p, 2); return normalized ? v / 65535.0f : float(v); }
      case TINYGLTF_COMPONENT_TYPE_SHORT: { int16_t v; memcpy(&v, p, 2); return normalized ? std::max(v / 32767.0f, -1.0f) : float(v); }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { uint32_t v; memcpy(&v, p, 4); return float(v); }
      default: throw Error(std::string(what) + ": unsupported component type " + std::to_string(type));
    }
  }

  const tinygltf::Model& m_;
};

bool allFinite(const std::vector<float>& v) {
  return std::all_of(v.begin(), v.end(), [](float x) { return std::isfinite(x); });
}

glm::dmat4 nodeMatrix(const tinygltf::Node& n) {
  if (n.matrix.size() == 16) return glm::make_mat4(n.matrix.data());
  glm::dmat4 t(1.0), r(1.0), s(1.0);
  if (n.translation.size() == 3) t = glm::translate(glm::dmat4(1.0), glm::make_vec3(n.translation.data()));
  // glTF rotations are unit quaternions; files store them rounded, so normalise
  // (as glref and OpenGL viewers do) rather than scale the mesh slightly.
  if (n.rotation.size() == 4)
    r = glm::mat4_cast(glm::normalize(glm::dquat(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2])));
  if (n.scale.size() == 3) s = glm::scale(glm::dmat4(1.0), glm::make_vec3(n.scale.data()));
  return t * r * s;
}

Texture decodeTexture(const tinygltf::Model& m, int texIndex) {
  if (texIndex < 0 || size_t(texIndex) >= m.textures.size()) throw Error("texture index out of range");
  const tinygltf::Texture& t = m.textures[texIndex];
  if (t.source < 0 || size_t(t.source) >= m.images.size()) throw Error("texture has no valid image source");
  const tinygltf::Image& im = m.images[t.source];
  if (im.width <= 0 || im.height <= 0 || im.image.empty()) {
    if (!im.uri.empty() && im.uri.rfind("data:", 0) != 0)
      throw Error("texture image " + std::to_string(t.source) + ": cannot read '" + im.uri + "'");
    throw Error("texture image " + std::to_string(t.source) + " could not be decoded");
  }
  const int comps = im.component, bytes = im.bits / 8;
  if (comps < 1 || comps > 4 || (bytes != 1 && bytes != 2) ||
      im.image.size() < size_t(im.width) * im.height * comps * bytes)
    throw Error("texture image " + std::to_string(t.source) + " has an unsupported layout");
  Texture out;
  out.width = im.width;
  out.height = im.height;
  out.rgba.resize(size_t(im.width) * im.height);
  for (size_t i = 0; i < out.rgba.size(); ++i) {
    uint8_t c[4] = {0, 0, 0, 255};
    for (int k = 0; k < comps; ++k) {
      const unsigned char* p = &im.image[(i * comps + k) * bytes];
      c[k] = bytes == 1 ? p[0] : p[1];  // 16-bit little endian: keep the high byte
    }
    if (comps == 1 || comps == 2) {  // grey (+alpha)
      c[3] = comps == 2 ? c[1] : 255;
      c[1] = c[2] = c[0];
    }
    out.rgba[i] = uint32_t(c[0]) | uint32_t(c[1]) << 8 | uint32_t(c[2]) << 16 | uint32_t(c[3]) << 24;
  }
  if (t.sampler >= 0) {
    if (size_t(t.sampler) >= m.samplers.size()) throw Error("texture sampler index out of range");
    out.wrapS = m.samplers[t.sampler].wrapS;
    out.wrapT = m.samplers[t.sampler].wrapT;
  }
  for (int32_t w : {out.wrapS, out.wrapT})
    if (w != WrapRepeat && w != WrapClamp && w != WrapMirror) throw Error("sampler has an invalid wrap mode");
  return out;
}

class Loader {
 public:
  Loader(const tinygltf::Model& m, Scene& s) : m_(m), s_(s), acc_(m) {}

  void run() {
    std::vector<int> roots;
    if (!m_.scenes.empty()) {
      const int si = m_.defaultScene >= 0 ? m_.defaultScene : 0;
      if (size_t(si) >= m_.scenes.size()) throw Error("default scene index " + std::to_string(si) + " out of range");
      roots = m_.scenes[si].nodes;
    } else {
      // No scene: draw every root node (a node nobody lists as a child).
      std::vector<char> isChild(m_.nodes.size(), 0);
      for (const auto& n : m_.nodes)
        for (int c : n.children)
          if (c >= 0 && size_t(c) < m_.nodes.size()) isChild[c] = 1;
      for (size_t i = 0; i < m_.nodes.size(); ++i)
        if (!isChild[i]) roots.push_back(int(i));
    }
    state_.assign(m_.nodes.size(), 0);
    for (int r : roots) traverse(r);
    if (s_.draws.empty()) throw Error("the scene has no triangles, lines or points to draw");
  }

 private:
  // Depth-first walk without recursion (a file may chain millions of nodes).
  // glTF nodes form disjoint trees: a node met twice is a cycle (still on the
  // path) or a second parent; both are errors (the latter could otherwise
  // blow up exponentially).
  void traverse(int root) {
    struct Frame {
      int node;
      glm::dmat4 world;
      size_t nextChild;
    };
    std::vector<Frame> stack;
    auto enter = [&](int ni, const glm::dmat4& parent) {
      if (ni < 0 || size_t(ni) >= m_.nodes.size()) throw Error("node index " + std::to_string(ni) + " out of range");
      if (state_[ni] == 1) throw Error("node hierarchy has a cycle through node " + std::to_string(ni));
      if (state_[ni] == 2)
        throw Error("node " + std::to_string(ni) + " appears twice in the scene hierarchy (glTF nodes form disjoint trees)");
      state_[ni] = 1;
      const tinygltf::Node& n = m_.nodes[ni];
      const glm::dmat4 world = parent * nodeMatrix(n);
      for (int k = 0; k < 16; ++k)
        if (!std::isfinite(glm::value_ptr(world)[k]))
          throw Error("node " + std::to_string(ni) + " has a non-finite transform");
      if (n.mesh >= 0) {
        if (size_t(n.mesh) >= m_.meshes.size()) throw Error("mesh index " + std::to_string(n.mesh) + " out of range");
        for (uint32_t p : meshPrims(n.mesh)) s_.draws.push_back(Draw{p, world});
      } else if (n.mesh < -1) {
        throw Error("mesh index " + std::to_string(n.mesh) + " out of range");
      }
      stack.push_back(Frame{ni, world, 0});
    };
    enter(root, glm::dmat4(1.0));
    while (!stack.empty()) {
      Frame& f = stack.back();
      const std::vector<int>& children = m_.nodes[f.node].children;
      if (f.nextChild < children.size()) {
        const int c = children[f.nextChild++];
        const glm::dmat4 world = f.world;  // enter() may reallocate the stack
        enter(c, world);
      } else {
        state_[f.node] = 2;
        stack.pop_back();
      }
    }
  }

  // Loads the primitives of a mesh once, however many nodes use it.
  const std::vector<uint32_t>& meshPrims(int mi) {
    auto it = meshCache_.find(mi);
    if (it != meshCache_.end()) return it->second;
    std::vector<uint32_t>& out = meshCache_[mi];
    const tinygltf::Mesh& mesh = m_.meshes[mi];
    for (const tinygltf::Primitive& p : mesh.primitives) {
      const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
      if (mode < 0 || mode > 6) throw Error("primitive mode " + std::to_string(mode) + " is invalid");
      out.push_back(loadPrim(p, mode));
    }
    return out;
  }

  uint32_t loadPrim(const tinygltf::Primitive& p, int mode) {
    auto attr = [&](const char* name) {
      auto it = p.attributes.find(name);
      return it == p.attributes.end() ? -1 : it->second;
    };
    const int posA = attr("POSITION");
    if (posA < 0) throw Error("mesh primitive has no POSITION attribute");
    const std::vector<float> pf = acc_.floats(posA, 3, "POSITION");
    const size_t nv = pf.size() / 3;
    std::vector<float3> pos(nv);
    for (size_t i = 0; i < nv; ++i) {
      pos[i] = {pf[3 * i], pf[3 * i + 1], pf[3 * i + 2]};
      if (!std::isfinite(pf[3 * i]) || !std::isfinite(pf[3 * i + 1]) || !std::isfinite(pf[3 * i + 2]))
        throw Error("POSITION accessor " + std::to_string(posA) + " has non-finite values (vertex " + std::to_string(i) + ")");
    }

    std::vector<float3> nrm;
    const int nA = attr("NORMAL");
    if (nA >= 0) {
      const std::vector<float> nf = acc_.floats(nA, 3, "NORMAL");
      if (nf.size() != pf.size()) throw Error("NORMAL count differs from POSITION count");
      if (!allFinite(nf)) throw Error("NORMAL accessor " + std::to_string(nA) + " has non-finite values");
      nrm.resize(nv);
      for (size_t i = 0; i < nv; ++i) nrm[i] = {nf[3 * i], nf[3 * i + 1], nf[3 * i + 2]};
    }

    int32_t matIndex = -1;
    int texCoordSet = -1;
    if (p.material >= 0) {
      if (size_t(p.material) >= m_.materials.size()) throw Error("material index " + std::to_string(p.material) + " out of range");
      matIndex = material(p.material, &texCoordSet);
    } else if (p.material < -1) {
      throw Error("material index out of range");
    }

    std::vector<float2> uv;
    if (texCoordSet >= 0 && mode >= TINYGLTF_MODE_TRIANGLES) {  // points and lines are not textured
      const int uvA = attr(("TEXCOORD_" + std::to_string(texCoordSet)).c_str());
      if (uvA < 0) throw Error("material samples TEXCOORD_" + std::to_string(texCoordSet) + " which the primitive lacks");
      const std::vector<float> uf = acc_.floats(uvA, 2, "TEXCOORD");
      if (uf.size() / 2 != nv) throw Error("TEXCOORD count differs from POSITION count");
      if (!allFinite(uf)) throw Error("TEXCOORD accessor " + std::to_string(uvA) + " has non-finite values");
      uv.resize(nv);
      for (size_t i = 0; i < nv; ++i) uv[i] = {uf[2 * i], uf[2 * i + 1]};
    }

    std::vector<float4> col;
    const int cA = attr("COLOR_0");
    if (cA >= 0) {
      const int comps = acc_.components(cA, "COLOR_0");
      if (comps != 3 && comps != 4) throw Error("COLOR_0 must be VEC3 or VEC4");
      const std::vector<float> cf = acc_.floats(cA, comps, "COLOR_0");
      if (cf.size() / comps != nv) throw Error("COLOR_0 count differs from POSITION count");
      if (!allFinite(cf)) throw Error("COLOR_0 accessor " + std::to_string(cA) + " has non-finite values");
      col.resize(nv);
      for (size_t i = 0; i < nv; ++i)
        col[i] = {cf[comps * i], cf[comps * i + 1], cf[comps * i + 2], comps == 4 ? cf[comps * i + 3] : 1.0f};
    }

    std::vector<uint32_t> seq;
    if (p.indices >= 0) {
      seq = acc_.indices(p.indices);
    } else if (p.indices < -1) {
      throw Error("indices accessor out of range");
    } else {
      seq.resize(nv);
      for (size_t i = 0; i < nv; ++i) seq[i] = uint32_t(i);
    }
    for (uint32_t i : seq)
      if (i >= nv)
        throw Error("index " + std::to_string(i) + " out of range: the primitive has " + std::to_string(nv) + " vertices");

    if (mode <= TINYGLTF_MODE_LINE_STRIP) {
      // Points and lines (docs/points-lines.md): loops and strips become
      // segment lists here (glTF 2.0 section 3.7.2.1), so the pipeline sees
      // only points and independent segments. A loop closes with the segment
      // from its last vertex back to its first; a LINES list of odd length
      // loses its incomplete last segment; a strip or loop of one vertex draws
      // nothing.
      std::vector<uint32_t> seg, pts;
      if (mode == TINYGLTF_MODE_POINTS) {
        pts = seq;
      } else if (mode == TINYGLTF_MODE_LINE) {
        seg.assign(seq.begin(), seq.end() - seq.size() % 2);
      } else {
        for (size_t i = 0; i + 1 < seq.size(); ++i) {
          seg.push_back(seq[i]);
          seg.push_back(seq[i + 1]);
        }
        if (mode == TINYGLTF_MODE_LINE_LOOP && seq.size() >= 2) {
          seg.push_back(seq.back());
          seg.push_back(seq.front());
        }
      }
      return addLinePrim(s_, pos, cA >= 0 ? &col : nullptr, seg, pts, matIndex);
    }

    // Strips and fans become lists (glTF 2.0 section 3.7.2.1). A list whose
    // length is not a multiple of 3 loses its incomplete last triangle.
    std::vector<uint32_t> idx;
    if (mode == TINYGLTF_MODE_TRIANGLES) {
      idx.assign(seq.begin(), seq.end() - seq.size() % 3);
    } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
      for (size_t i = 0; i + 2 < seq.size(); ++i) {
        idx.push_back(seq[i]);
        idx.push_back(seq[i + 1 + i % 2]);
        idx.push_back(seq[i + 2 - i % 2]);
      }
    } else {
      for (size_t i = 0; i + 2 < seq.size(); ++i) {
        idx.push_back(seq[i + 1]);
        idx.push_back(seq[i + 2]);
        idx.push_back(seq[0]);
      }
    }
    return addPrim(s_, pos, nA >= 0 ? &nrm : nullptr, texCoordSet >= 0 ? &uv : nullptr, cA >= 0 ? &col : nullptr, idx,
                   matIndex);
  }

  int32_t material(int mi, int* texCoordSet) {
    auto it = matCache_.find(mi);
    if (it == matCache_.end()) {
      const tinygltf::Material& gm = m_.materials[mi];
      Material mat;
      const auto& f = gm.pbrMetallicRoughness.baseColorFactor;
      if (f.size() == 4) mat.baseColorFactor = {float(f[0]), float(f[1]), float(f[2]), float(f[3])};
      const auto& bt = gm.pbrMetallicRoughness.baseColorTexture;
      int set = -1;
      if (bt.index >= 0) {
        mat.texture = texture(bt.index);
        set = bt.texCoord;
        if (set < 0) throw Error("material texCoord set is negative");
      }
      s_.materials.push_back(mat);
      it = matCache_.emplace(mi, std::make_pair(int32_t(s_.materials.size() - 1), set)).first;
    }
    *texCoordSet = it->second.second;
    return it->second.first;
  }

  // Decodes a texture once, however many materials use it.
  int32_t texture(int ti) {
    auto it = texCache_.find(ti);
    if (it != texCache_.end()) return it->second;
    s_.textures.push_back(decodeTexture(m_, ti));
    return texCache_[ti] = int32_t(s_.textures.size() - 1);
  }

  const tinygltf::Model& m_;
  Scene& s_;
  AccessorReader acc_;
  std::vector<char> state_;  // per node: 0 not seen, 1 on the current path, 2 done
  std::map<int, std::vector<uint32_t>> meshCache_;
  std::map<int, std::pair<int32_t, int>> matCache_;
  std::map<int, int32_t> texCache_;
};

Scene loadChecked(const std::string& path) {
  const std::vector<unsigned char> bytes = readWholeFile(path);
  const auto slash = path.find_last_of('/');
  const std::string baseDir = slash == std::string::npos ? std::string() : path.substr(0, slash);

  // Sniff the GLB magic instead of trusting the extension.
  const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  GlbLayout glb;
  if (binary) glb = checkGlb(bytes);
  const char* json = reinterpret_cast<const char*>(bytes.data()) + (binary ? glb.jsonOffset : 0);
  const size_t jsonLength = binary ? glb.jsonLength : bytes.size();
  checkDocument(parseJson(json, jsonLength), baseDir);

  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(loadImageChecked, nullptr);
  loader.SetFsCallbacks({&tinygltf::FileExists, &tinygltf::ExpandFilePath, &readFileForTinygltf,
                         &tinygltf::WriteWholeFile, nullptr});
  tinygltf::Model model;
  std::string err, warn;
  bool ok = false;
  try {
    ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(), unsigned(glb.length), baseDir)
                : loader.LoadASCIIFromString(&model, &err, &warn, json, unsigned(jsonLength), baseDir);
  } catch (const std::exception& e) {
    // nlohmann::json throws on some type mismatches inside tinygltf.
    throw Error("malformed glTF: " + oneLine(e.what()));
  }
  if (!ok || !err.empty()) {
    std::string why = oneLine(err.empty() ? warn : err);
    throw Error(why.empty() ? std::string("not a valid glTF file") : why);
  }
  if (model.asset.version.rfind("2.", 0) != 0)
    throw Error("glTF version '" + model.asset.version + "' is not 2.x");
  Scene s;
  s.name = path;
  Loader(model, s).run();
  s.validate();
  return s;
}

}  // namespace

Scene loadGltf(const std::string& path) {
  try {
    return loadChecked(path);
  } catch (const Error& e) {
    const std::string what = oneLine(e.what());
    // Messages about the file as a whole already name it.
    if (what.find("'" + path + "'") != std::string::npos) throw Error(what);
    throw Error("'" + oneLine(path) + "': " + what);
  }
}

}  // namespace rast
