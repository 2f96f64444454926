// What the files of the glTF loader share, and nothing more: the loader is
// split by job (file_gate.cpp, schema_check.cpp, image_decode.cpp,
// accessors.cpp, model_walk.cpp) so that each file stays readable, and this
// header is the seam between them. It is private to host/gltf/: the public
// API is host/gltf/gltf_loader.h. Helpers used by a single file stay in that
// file's anonymous namespace.
#pragma once

#include "host/gltf/gltf_loader.h"
#include "host/gltf/uri_resolver.h"
#include "host/scene/memory_budget.h"

#include <tiny_gltf.h>

#include <glm/glm.hpp>

#include <nlohmann/json.hpp>

#include <cstddef>
#include <functional>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace rast::gltf_detail {

// Elements that accessors without a bufferView may add up to, relative to the
// file: such data is not in the file (zeros plus sparse entries), so a few
// hundred bytes could otherwise claim gigabytes.
constexpr uint64_t kMinZeroElements = uint64_t(1) << 20;
constexpr uint64_t kZeroElementsPerFileByte = 16;

// What one load shares between tinygltf's callbacks and the model walk.
struct LoadContext {
  LoadContext(const std::string& path, const LoadOptions& o)
      : resolver(path, o.allowExternalFiles), ledger(o.maxMemory ? o.maxMemory : defaultMemoryBudget()) {}
  UriResolver resolver;
  MemoryLedger ledger;
  uint64_t zeroElementsLeft = kMinZeroElements;
  // The first refusal (outside the folder, over the budget) met inside a
  // tinygltf callback: tinygltf only warns when an image cannot be read.
  std::string fatal;
  // The resolved path of every external file read (Scene::sourceFiles).
  std::vector<std::string> filesRead;
  // Images left undecoded because they are KTX2 (image_decode.cpp, compression.cpp).
  std::vector<int> ktx2Images;
};

// Makes a message printable on one line: control characters become spaces.
std::string oneLine(std::string s);

// ---------------------------------------------------------------- file_gate.cpp

// The scene file, whole; refused before reading when it is larger than
// `budget` or does not start like a glTF file.
std::vector<unsigned char> readWholeFile(const std::string& path, uint64_t budget);

// tinygltf's file callbacks for external buffers and images (`user` is the
// LoadContext): every path goes through the scene's UriResolver.
bool fileExistsForTinygltf(const std::string&, void*);
std::string expandPathForTinygltf(const std::string& path, void*);
bool readFileForTinygltf(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user);
bool writeFileForTinygltf(std::string* err, const std::string&, const std::vector<unsigned char>&, void*);

// Checks the GLB header and chunk layout; returns the container length (the
// bytes that belong to the GLB) and where the JSON chunk lies.
struct GlbLayout {
  size_t length = 0, jsonOffset = 0, jsonLength = 0;
};

GlbLayout checkGlb(const std::vector<unsigned char>& b);

// ---------------------------------------------------------------- schema_check.cpp

// The JSON text of the file, its nesting depth checked first; throws Error for
// invalid JSON or a root that is not an object.
// Its parsed size (256 bytes a value) is charged to `ledger` first.
nlohmann::json parseJson(const char* s, size_t n, MemoryLedger& ledger);

// What tinygltf leaves unchecked or reports unclearly, checked on the JSON.
void checkDocument(const nlohmann::json& j, LoadContext& ctx);

// ---------------------------------------------------------------- image_decode.cpp

// tinygltf's image loader callback (`user` is the LoadContext).
bool loadImageChecked(tinygltf::Image* image, const int index, std::string* err, std::string* warn, int reqWidth,
                      int reqHeight, const unsigned char* bytes, int size, void* user);

// Texture `texIndex` of the model as RGBA8, charged to `ledger`.
Texture decodeTexture(const tinygltf::Model& m, int texIndex, MemoryLedger& ledger);

// ---------------------------------------------------------------- accessors.cpp

// Reads accessor `index` as `count` rows of `comps` floats (normalized integers
// mapped to [0,1] or [-1,1] as the spec says), honouring byteStride and sparse
// substitution. Every byte range is checked before anything is allocated or read.
class AccessorReader {
 public:
  AccessorReader(const tinygltf::Model& m, LoadContext& ctx) : m_(m), ctx_(ctx) {}

  std::vector<float> floats(int index, int comps, const char* what) const;
  std::vector<uint32_t> indices(int index) const;
  // The number of components of the accessor's type (-1 when the type is unknown).
  int components(int index, const char* what) const;

 private:
  struct Span {
    const unsigned char* data;
    size_t stride, compSize;
  };

  const tinygltf::Accessor& accessor(int index, const char* what) const;
  void checkCount(const tinygltf::Accessor& a, int index, const char* what) const;
  static size_t compSizeOf(int componentType, const char* what);
  // Bytes [offset, offset+len) of buffer view `bv`, checked against the buffer.
  const unsigned char* viewBytes(int bv, size_t offset, size_t len, const char* what) const;
  Span span(const tinygltf::Accessor& a, int comps, const char* what) const;
  template <class F>
  void applySparse(const tinygltf::Accessor& a, int comps, const char* what, F&& put) const;
  static uint32_t uintAt(const unsigned char* p, int type);
  static float component(const unsigned char* p, int type, bool normalized, const char* what);

  const tinygltf::Model& m_;
  LoadContext& ctx_;
};

// ---------------------------------------------------------------- materials.cpp

// Material `mi` of the model, its values checked against glTF 2.0's ranges.
// texture(index, slot) loads texture `index` of the model for the named slot
// and returns its index in Scene::textures.
Material readMaterial(const tinygltf::Model& m, int mi, const std::function<int32_t(int, const char*)>& texture);

// A texture reference inside a material extension's JSON (tinygltf parses
// only the core's): its index (-1: absent; one that does not exist is an
// Error), texCoord, scale (normal textures) and its own extensions
// (KHR_texture_transform). `at` names the extension for the message.
struct ExtTexture {
  int index = -1, texCoord = 0;
  double scale = 1.0;
  tinygltf::ExtensionMap extensions;
};
ExtTexture extTexture(const tinygltf::Model& m, const tinygltf::Value& ext, const char* key, const std::string& at);
// The material's KHR_materials_clearcoat object, or null.
const tinygltf::Value* clearcoatOf(const tinygltf::Material& gm, const std::string& at);

// KHR_lights_punctual light `li`, placed by a node at `world`.
PunctualLight readLight(const tinygltf::Model& m, int li, const std::string& nodeName, const glm::dmat4& world);

// ---------------------------------------------------------------- animation_load.cpp

// What the model walk (model_walk.cpp) hands to the rig: the node that placed
// each draw, the scene primitives of each mesh, and for each primitive drawn
// flat-shaded (no NORMAL: a vertex per triangle corner) its source vertex per
// corner.
struct WalkRecord {
  std::vector<int32_t> drawNode;
  std::vector<glm::dmat4> drawInstance;  // per draw: its instance's matrix under its node (EXT_mesh_gpu_instancing)
  std::map<int, std::vector<uint32_t>> meshPrims;
  std::map<uint32_t, std::vector<uint32_t>> flatCorners;
};

// Reads the node hierarchy, skins, animations and morph targets into
// s.rig (host/scene/animation.h; left null when nothing moves) and poses the
// scene at rest: skins and default morph weights applied.
void buildRig(const tinygltf::Model& m, LoadContext& ctx, Scene& s, const WalkRecord& w);

// ---------------------------------------------------------------- compression.cpp

// Whether rast decodes this compression extension (a file may require it).
bool compressionSupported(const std::string& name);
// What tinygltf refuses in compressed files, stubbed in a copy of the file
// (`out`: JSON text, or a GLB with the new JSON chunk): a buffer without a uri
// (meshopt's fallback buffers, which hold no data) becomes a 1-byte data:
// buffer; a Draco primitive's indices accessor without a bufferView reads the
// Draco stream's view until it is decoded. False: no change.
bool stubForTinygltf(nlohmann::json& doc, bool binary, const std::vector<unsigned char>& file, const GlbLayout& glb,
                     std::vector<unsigned char>& out);
// Decodes EXT_meshopt_compression bufferViews and KHR_draco_mesh_compression
// primitives into new buffers the model then reads, within the budget; refuses
// a KHR_texture_basisu texture without a fallback image.
void decodeCompressed(tinygltf::Model& m, LoadContext& ctx);

// ---------------------------------------------------------------- instancing.cpp

// EXT_mesh_gpu_instancing: the node's instances, each as the matrix
// T(TRANSLATION) R(ROTATION) S(SCALE) under the node; empty when the node has
// none. Every accessor is checked (type, count, finite values) and the draws
// they will make charged to the budget first.
std::vector<glm::dmat4> instanceMatrices(const tinygltf::Model& m, LoadContext& ctx, int nodeIndex, size_t primsPerInstance);

}  // namespace rast::gltf_detail
