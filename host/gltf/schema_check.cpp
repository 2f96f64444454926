// The glTF loader's check of the JSON document, before tinygltf parses it.
// tinygltf silently ignores a core property of the wrong type (a string
// `scene`, an object `primitives`, index -1, ...) where the glTF schema makes
// the file invalid, recurses on nested JSON (`extras`) without a depth limit,
// and reads an image's bufferView without checking it against its buffer. So
// the JSON is parsed here first, its nesting depth bounded, every core
// property's type checked against the glTF 2.0 schema, extensionsRequired
// compared with what rast supports, image bufferView ranges checked, external
// buffers resolved through the UriResolver, and the bytes every buffer and
// data: image will hold charged to the memory budget, all before anything is
// read or decoded; each problem is one Error naming the property's path.
#include "host/gltf/gltf_internal.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <limits>

namespace rast::gltf_detail {
namespace {

using Json = nlohmann::json;

constexpr size_t kMaxJsonDepth = 128;  // tinygltf recurses on nested JSON (extras)
constexpr uint64_t kJsonValueBytes = 256;  // resident bytes per JSON value, parsed (see parseJson)

// ---------------------------------------------------------------- JSON and glTF schema

// Checks the nesting depth; returns the number of JSON values (at most: one
// more than the separators and openings outside strings).
uint64_t checkJsonDepth(const char* s, size_t n) {
  size_t depth = 0;
  uint64_t values = 1;
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
      ++values;
      if (++depth > kMaxJsonDepth) throw Error("JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
    } else if ((c == '}' || c == ']') && depth > 0) {
      --depth;
    } else if (c == ',' || c == ':') {
      ++values;
    }
  }
  return values;
}

}  // namespace

Json parseJson(const char* s, size_t n, MemoryLedger& ledger) {
  // The parsed document costs far more than its text: this one's tree, then
  // tinygltf's (its own JSON tree and, for extras and extensions, its Values),
  // which stays for the rest of the load. About 200 bytes a value measured
  // (a 40 MB array of 20M numbers: 3.7 GiB resident); 256 charged.
  const uint64_t values = checkJsonDepth(s, n);
  ledger.charge("the JSON document (" + std::to_string(values) + " values, parsed)", mulSat(values, kJsonValueBytes));
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

namespace {

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
// What a file may require: the loader reads quantized attributes
// (accessors.cpp) and applies the base-colour texture's transform
// (model_walk.cpp); the lights and material extensions are read by
// materials.cpp and shaded under `--shading pbr` (pipeline/shade/pbr_shading.h).
// app/scene_info.cpp reports the same list.
bool extensionSupported(const std::string& name) {
  return name == "KHR_mesh_quantization" || name == "KHR_texture_transform" || name == "KHR_lights_punctual" ||
         name == "KHR_materials_unlit" || name == "KHR_materials_emissive_strength" || name == "EXT_mesh_gpu_instancing" ||
         name == "KHR_materials_clearcoat" || compressionSupported(name);
}

}  // namespace

// What tinygltf leaves unchecked or reports unclearly, checked on the JSON.
namespace {

// A buffer's data: URI as tinygltf decodes it (its media types, base64 up to
// the first character outside the alphabet), so that a wrong byteLength is
// named as such instead of tinygltf's "Failed to decode 'uri'" with the whole
// URI echoed.
void checkBufferDataUri(const std::string& at, const std::string& uri, uint64_t byteLength) {
  static const char* kHeaders[] = {"data:application/octet-stream;base64,", "data:application/gltf-buffer;base64,",
                                   "data:image/jpeg;base64,", "data:image/png;base64,", "data:image/bmp;base64,",
                                   "data:image/gif;base64,", "data:text/plain;base64,"};
  size_t header = 0;
  for (const char* h : kHeaders)
    if (uri.rfind(h, 0) == 0) header = std::strlen(h);
  if (header == 0) {
    const std::string media = uri.substr(5, std::min(uri.find_first_of(";,"), size_t(64)) - 5);
    throw Error(at + ": a data: URI of media type '" + printable(media, 60) +
                "' or not base64 (buffers are data:application/octet-stream;base64,...)");
  }
  size_t n = 0;
  while (header + n < uri.size()) {
    const unsigned char c = uri[header + n];
    if (!std::isalnum(c) && c != '+' && c != '/') break;
    ++n;
  }
  const uint64_t decoded = n / 4 * 3 + (n % 4 ? n % 4 - 1 : 0);
  if (decoded == 0) throw Error(at + ": its data: URI holds no base64 data");
  if (decoded != byteLength)
    throw Error(at + ": its data: URI decodes to " + std::to_string(decoded) + " bytes, but its byteLength says " +
                std::to_string(byteLength));
}

}  // namespace

void checkDocument(const Json& j, LoadContext& ctx) {
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
  // Buffers: where external ones resolve (the same resolver tinygltf's reads
  // use), and the bytes every buffer will hold, before any is read or decoded.
  for (size_t i = 0; i < buffers.size(); ++i) {
    const std::string at = "buffers[" + std::to_string(i) + "]";
    ctx.ledger.charge(at + " (byteLength " + std::to_string(buffers[i]["byteLength"].get<uint64_t>()) + ")",
                      buffers[i]["byteLength"].get<uint64_t>());
    const auto u = buffers[i].find("uri");
    if (u == buffers[i].end()) continue;
    const std::string uri = u->get<std::string>();
    if (uri.rfind("data:", 0) == 0) {
      checkBufferDataUri(at, uri, buffers[i]["byteLength"].get<uint64_t>());
      continue;
    }
    try {
      ctx.resolver.resolveUri(uri);
    } catch (const Error& e) {
      throw Error(at + ": " + e.what());
    }
  }
  // data: images are decoded from base64 in memory (3 bytes per 4 characters).
  for (size_t i = 0; i < images.size(); ++i) {
    const auto u = images[i].find("uri");
    if (u == images[i].end()) continue;
    const std::string uri = u->get<std::string>();
    if (uri.rfind("data:", 0) == 0) {
      ctx.ledger.charge("images[" + std::to_string(i) + "] data: URI", uri.size() / 4 * 3);
      continue;
    }
    try {
      UriResolver::checkEscapes(uri);
    } catch (const Error& e) {
      throw Error("images[" + std::to_string(i) + "]: " + e.what());
    }
  }
}

}  // namespace rast::gltf_detail
