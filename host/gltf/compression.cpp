// Compressed glTF geometry, decoded at load (docs/compression.md): Draco
// primitives (KHR_draco_mesh_compression, Debian's libdraco) and meshopt
// bufferViews (EXT_meshopt_compression, Debian's libmeshoptimizer). Each is
// decoded once, after tinygltf's parse and before the model walk, into a new
// buffer that the model's bufferViews and accessors are pointed at, so the
// rest of the loader reads plain accessors and checks them as it checks any.
// Decoded sizes come from the file's own counts and are charged to the memory
// budget before decoding; a stream that does not decode, or decodes to other
// counts than the file declares, is one Error. KHR_texture_basisu has no
// decoder in Debian: a texture that has a PNG/JPEG fallback source uses it
// (tinygltf's `source`); one without is refused naming the extension.
#include "host/gltf/gltf_internal.h"

#include <draco/compression/decode.h>
#include <meshoptimizer.h>

#include <algorithm>
#include <cstring>

namespace rast::gltf_detail {
namespace {

const tinygltf::Value* extObject(const tinygltf::ExtensionMap& ext, const char* name) {
  const auto it = ext.find(name);
  return it == ext.end() || !it->second.IsObject() ? nullptr : &it->second;
}

uint64_t intField(const tinygltf::Value& v, const char* key, const std::string& at, bool required, uint64_t dflt = 0) {
  if (!v.Has(key)) {
    if (required) throw Error(at + ": missing " + key);
    return dflt;
  }
  const tinygltf::Value& f = v.Get(key);
  if (!f.IsNumber() || f.GetNumberAsDouble() < 0 || f.GetNumberAsDouble() > 9.0e15 ||
      f.GetNumberAsDouble() != double(uint64_t(f.GetNumberAsDouble())))
    throw Error(at + ": " + key + " must be a non-negative integer");
  return uint64_t(f.GetNumberAsDouble());
}

// A new buffer holding `bytes`, and a bufferView over all of it.
int addView(tinygltf::Model& m, std::vector<unsigned char>&& bytes) {
  tinygltf::Buffer b;
  b.data = std::move(bytes);
  m.buffers.push_back(std::move(b));
  tinygltf::BufferView v;
  v.buffer = int(m.buffers.size() - 1);
  v.byteOffset = 0;
  v.byteLength = m.buffers.back().data.size();
  m.bufferViews.push_back(v);
  return int(m.bufferViews.size() - 1);
}

// The compressed bytes [offset, offset + length) of buffer `b`.
const unsigned char* sourceBytes(const tinygltf::Model& m, uint64_t b, uint64_t offset, uint64_t length, const std::string& at) {
  if (b >= m.buffers.size()) throw Error(at + ": buffer " + std::to_string(b) + " out of range");
  const std::vector<unsigned char>& d = m.buffers[b].data;
  if (offset > d.size() || length > d.size() - offset)
    throw Error(at + ": compressed bytes reach past the end of buffer " + std::to_string(b));
  return d.data() + offset;
}

// ---------------------------------------------------------------- EXT_meshopt_compression

void decodeMeshopt(tinygltf::Model& m, LoadContext& ctx) {
  for (size_t i = 0; i < m.bufferViews.size(); ++i) {
    const tinygltf::Value* x = extObject(m.bufferViews[i].extensions, "EXT_meshopt_compression");
    if (!x) continue;
    const std::string at = "bufferViews[" + std::to_string(i) + "] EXT_meshopt_compression";
    const uint64_t buffer = intField(*x, "buffer", at, true), offset = intField(*x, "byteOffset", at, false),
                   length = intField(*x, "byteLength", at, true), stride = intField(*x, "byteStride", at, true),
                   count = intField(*x, "count", at, true);
    const std::string mode = x->Has("mode") && x->Get("mode").IsString() ? x->Get("mode").Get<std::string>() : "";
    const std::string filter = x->Has("filter") && x->Get("filter").IsString() ? x->Get("filter").Get<std::string>() : "NONE";
    const unsigned char* src = sourceBytes(m, buffer, offset, length, at);
    const bool attributes = mode == "ATTRIBUTES";
    if (!attributes && mode != "TRIANGLES" && mode != "INDICES") throw Error(at + ": unknown mode '" + oneLine(mode) + "'");
    if (attributes ? (stride == 0 || stride > 256 || stride % 4) : (stride != 2 && stride != 4))
      throw Error(at + ": byteStride " + std::to_string(stride) + " is invalid for mode " + mode);
    if (mode == "TRIANGLES" && count % 3) throw Error(at + ": a TRIANGLES count must be a multiple of 3");
    const uint64_t bytes = mulSat(count, stride);
    ctx.ledger.charge(at + " (" + std::to_string(bytes) + " bytes decoded)", bytes);
    std::vector<unsigned char> out(static_cast<size_t>(bytes));
    int rc = 0;
    if (attributes) rc = meshopt_decodeVertexBuffer(out.data(), size_t(count), size_t(stride), src, size_t(length));
    else if (mode == "TRIANGLES") rc = meshopt_decodeIndexBuffer(out.data(), size_t(count), size_t(stride), src, size_t(length));
    else rc = meshopt_decodeIndexSequence(out.data(), size_t(count), size_t(stride), src, size_t(length));
    if (rc != 0) throw Error(at + ": the compressed stream is corrupt (meshopt error " + std::to_string(rc) + ")");
    if (filter == "OCTAHEDRAL") {
      if (!attributes || (stride != 4 && stride != 8)) throw Error(at + ": the OCTAHEDRAL filter needs a byteStride of 4 or 8");
      meshopt_decodeFilterOct(out.data(), size_t(count), size_t(stride));
    } else if (filter == "QUATERNION") {
      if (!attributes || stride != 8) throw Error(at + ": the QUATERNION filter needs a byteStride of 8");
      meshopt_decodeFilterQuat(out.data(), size_t(count), size_t(stride));
    } else if (filter == "EXPONENTIAL") {
      if (!attributes || stride % 4) throw Error(at + ": the EXPONENTIAL filter needs a byteStride multiple of 4");
      meshopt_decodeFilterExp(out.data(), size_t(count), size_t(stride));
    } else if (filter != "NONE") {
      throw Error(at + ": unknown filter '" + oneLine(filter) + "'");
    }
    // The view now reads the decoded bytes (its own byteStride, if any, still applies).
    tinygltf::BufferView& v = m.bufferViews[i];
    if (v.byteLength > bytes) throw Error(at + ": byteLength " + std::to_string(v.byteLength) + " exceeds the decoded " + std::to_string(bytes) + " bytes");
    tinygltf::Buffer b;
    b.data = std::move(out);
    m.buffers.push_back(std::move(b));
    v.buffer = int(m.buffers.size() - 1);
    v.byteOffset = 0;
    v.extensions.erase("EXT_meshopt_compression");
  }
}

// ---------------------------------------------------------------- KHR_draco_mesh_compression

void decodeDraco(tinygltf::Model& m, LoadContext& ctx) {
  for (size_t mi = 0; mi < m.meshes.size(); ++mi)
    for (size_t pi = 0; pi < m.meshes[mi].primitives.size(); ++pi) {
      tinygltf::Primitive& p = m.meshes[mi].primitives[pi];
      const tinygltf::Value* x = extObject(p.extensions, "KHR_draco_mesh_compression");
      if (!x) continue;
      const std::string at = "meshes[" + std::to_string(mi) + "].primitives[" + std::to_string(pi) + "] KHR_draco_mesh_compression";
      const uint64_t bv = intField(*x, "bufferView", at, true);
      if (bv >= m.bufferViews.size()) throw Error(at + ": bufferView " + std::to_string(bv) + " out of range");
      if (!x->Has("attributes") || !x->Get("attributes").IsObject()) throw Error(at + ": needs an attributes object");
      const tinygltf::BufferView& view = m.bufferViews[size_t(bv)];
      const unsigned char* src = sourceBytes(m, uint64_t(view.buffer), view.byteOffset, view.byteLength, at);
      // What the file says the decoded mesh holds, charged before decoding
      // (and once more for the decoder's own copy while it lives).
      uint64_t declared = 0;
      for (const auto& [name, a] : p.attributes)
        if (a >= 0 && size_t(a) < m.accessors.size()) declared = addSat(declared, mulSat(m.accessors[size_t(a)].count, 16));
      if (p.indices >= 0 && size_t(p.indices) < m.accessors.size()) declared = addSat(declared, mulSat(m.accessors[size_t(p.indices)].count, 4));
      ctx.ledger.check(at + " (decoded)", mulSat(declared, 2));
      ctx.ledger.charge(at + " (decoded)", declared);

      draco::DecoderBuffer in;
      in.Init(reinterpret_cast<const char*>(src), size_t(view.byteLength));
      draco::Decoder decoder;
      auto decoded = decoder.DecodeMeshFromBuffer(&in);
      if (!decoded.ok() || !decoded.value()) throw Error(at + ": the compressed stream is corrupt (" + oneLine(decoded.status().error_msg_string()) + ")");
      const draco::Mesh& mesh = *decoded.value();
      const uint64_t points = mesh.num_points(), faces = mesh.num_faces();
      if (mulSat(points, 16) > declared || mulSat(faces, 12) > addSat(declared, 12))
        throw Error(at + ": decodes to more than its accessors declare");

      if (p.indices >= 0) {
        if (size_t(p.indices) >= m.accessors.size()) throw Error(at + ": indices accessor out of range");
        tinygltf::Accessor& a = m.accessors[size_t(p.indices)];
        if (a.count != faces * 3) throw Error(at + ": decodes to " + std::to_string(faces) + " triangles, its indices accessor says " + std::to_string(a.count / 3));
        std::vector<unsigned char> idx(size_t(faces) * 12);
        for (uint32_t f = 0; f < faces; ++f)
          for (int k = 0; k < 3; ++k) {
            const uint32_t v = mesh.face(draco::FaceIndex(f))[k].value();
            std::memcpy(idx.data() + (size_t(f) * 3 + k) * 4, &v, 4);
          }
        a.bufferView = addView(m, std::move(idx));
        a.byteOffset = 0;
        a.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
        a.sparse.isSparse = false;
      }
      const tinygltf::Value& attrs = x->Get("attributes");
      for (const std::string& name : attrs.Keys()) {
        const auto pa = p.attributes.find(name);
        if (pa == p.attributes.end()) continue;  // only in the Draco stream: not an attribute of the primitive
        const tinygltf::Value& id = attrs.Get(name);
        if (!id.IsInt() || id.GetNumberAsInt() < 0) throw Error(at + ": attribute " + oneLine(name) + " must be a Draco id");
        const draco::PointAttribute* da = mesh.GetAttributeByUniqueId(uint32_t(id.GetNumberAsInt()));
        if (!da) throw Error(at + ": the stream has no attribute " + std::to_string(id.GetNumberAsInt()) + " (" + oneLine(name) + ")");
        if (pa->second < 0 || size_t(pa->second) >= m.accessors.size()) throw Error(at + ": " + oneLine(name) + " accessor out of range");
        tinygltf::Accessor& a = m.accessors[size_t(pa->second)];
        const int comps = tinygltf::GetNumComponentsInType(uint32_t(a.type));
        if (comps < 1 || comps > 4) throw Error(at + ": " + oneLine(name) + " has an unsupported type");
        if (a.count != points) throw Error(at + ": " + oneLine(name) + " decodes to " + std::to_string(points) + " values, its accessor says " + std::to_string(a.count));
        // Joints stay integers (the skin reads them as such); the rest become floats.
        const bool joints = name.rfind("JOINTS_", 0) == 0;
        std::vector<unsigned char> out(size_t(points) * comps * 4);
        for (uint32_t v = 0; v < points; ++v) {
          const draco::AttributeValueIndex ai = da->mapped_index(draco::PointIndex(v));
          bool ok;
          if (joints) {
            uint32_t j[4] = {0, 0, 0, 0};
            ok = da->ConvertValue<uint32_t>(ai, int8_t(comps), j);
            for (int k = 0; k < comps; ++k) {
              const uint16_t s = uint16_t(std::min<uint32_t>(j[k], 65535));
              std::memcpy(out.data() + (size_t(v) * comps + k) * 2, &s, 2);
            }
          } else {
            ok = da->ConvertValue<float>(ai, int8_t(comps), reinterpret_cast<float*>(out.data()) + size_t(v) * comps);
          }
          if (!ok) throw Error(at + ": " + oneLine(name) + " cannot be converted");
        }
        if (joints) out.resize(size_t(points) * comps * 2);
        a.bufferView = addView(m, std::move(out));
        a.byteOffset = 0;
        a.componentType = joints ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT : TINYGLTF_COMPONENT_TYPE_FLOAT;
        a.normalized = false;
        a.sparse.isSparse = false;
      }
      p.extensions.erase("KHR_draco_mesh_compression");
    }
}

// ---------------------------------------------------------------- KHR_texture_basisu

void checkBasisu(const tinygltf::Model& m, const LoadContext& ctx) {
  for (size_t i = 0; i < m.textures.size(); ++i) {
    const int src = m.textures[i].source;
    if (m.textures[i].extensions.count("KHR_texture_basisu") && src < 0)
      throw Error("textures[" + std::to_string(i) + "] is KHR_texture_basisu (KTX2) only, which rast cannot decode (no fallback image)");
    if (std::find(ctx.ktx2Images.begin(), ctx.ktx2Images.end(), src) != ctx.ktx2Images.end())
      throw Error("image " + std::to_string(src) + ": is KTX2 (KHR_texture_basisu, which rast does not support), not PNG or JPEG, "
                  "the image formats glTF allows");
  }
}

}  // namespace

bool stubForTinygltf(nlohmann::json& doc, bool binary, const std::vector<unsigned char>& file, const GlbLayout& glb,
                     std::vector<unsigned char>& out) {
  bool any = false;
  // Draco primitives' indices accessors have no bufferView, which tinygltf
  // refuses: they are pointed at the Draco stream's view until decodeDraco
  // points them at the decoded indices.
  auto meshes = doc.find("meshes");
  auto accessors = doc.find("accessors");
  if (meshes != doc.end() && meshes->is_array() && accessors != doc.end() && accessors->is_array())
    for (nlohmann::json& mesh : *meshes) {
      if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
      for (nlohmann::json& p : mesh["primitives"]) {
        const auto ext = p.find("extensions");
        if (ext == p.end() || !ext->is_object() || !ext->contains("KHR_draco_mesh_compression")) continue;
        const nlohmann::json& d = (*ext)["KHR_draco_mesh_compression"];
        if (!d.is_object() || !d.contains("bufferView") || !d["bufferView"].is_number_unsigned() || !p.contains("indices") ||
            !p["indices"].is_number_unsigned() || p["indices"].get<uint64_t>() >= accessors->size())
          continue;
        nlohmann::json& a = (*accessors)[p["indices"].get<size_t>()];
        if (a.is_object() && !a.contains("bufferView")) {
          a["bufferView"] = d["bufferView"];
          any = true;
        }
      }
    }
  // meshopt's fallback buffers (no uri, no data).
  auto buffers = doc.find("buffers");
  for (size_t i = 0; buffers != doc.end() && buffers->is_array() && i < buffers->size(); ++i) {
    nlohmann::json& b = (*buffers)[i];
    const auto ext = b.find("extensions");
    if (b.contains("uri") || ext == b.end() || !ext->is_object()) continue;
    const auto mo = ext->find("EXT_meshopt_compression");
    if (mo == ext->end() || !mo->is_object()) continue;
    const auto fallback = mo->find("fallback");
    if (fallback == mo->end()) continue;
    // Checked here because the schema check leaves extension contents alone
    // (json::value would throw its own exception type on a non-boolean).
    if (!fallback->is_boolean())
      throw Error("buffers[" + std::to_string(i) + "].extensions.EXT_meshopt_compression.fallback: expected a boolean, got " +
                  std::string(fallback->type_name()));
    if (!fallback->get<bool>()) continue;
    if (binary && i == 0) continue;  // the GLB's own BIN chunk
    b = {{"byteLength", 1}, {"uri", "data:application/octet-stream;base64,AA=="}};
    any = true;
  }
  if (!any) return false;
  const std::string text = doc.dump();
  if (!binary) {
    out.assign(text.begin(), text.end());
    return true;
  }
  // The same GLB with the new JSON chunk (padded with spaces) and the old BIN chunk.
  std::string js = text;
  while (js.size() % 4) js += ' ';
  const size_t binStart = glb.jsonOffset + glb.jsonLength + (4 - glb.jsonLength % 4) % 4;
  const size_t rest = glb.length > binStart ? glb.length - binStart : 0;  // the BIN chunk, header included
  const uint32_t total = uint32_t(12 + 8 + js.size() + rest), jsLen = uint32_t(js.size());
  out.assign(file.begin(), file.begin() + 12);
  std::memcpy(out.data() + 8, &total, 4);
  out.insert(out.end(), reinterpret_cast<const unsigned char*>(&jsLen), reinterpret_cast<const unsigned char*>(&jsLen) + 4);
  const char kJson[4] = {'J', 'S', 'O', 'N'};
  out.insert(out.end(), kJson, kJson + 4);
  out.insert(out.end(), js.begin(), js.end());
  out.insert(out.end(), file.begin() + std::min(binStart, glb.length), file.begin() + glb.length);
  return true;
}

void decodeCompressed(tinygltf::Model& m, LoadContext& ctx) {
  decodeMeshopt(m, ctx);
  decodeDraco(m, ctx);
  checkBasisu(m, ctx);
}

bool compressionSupported(const std::string& name) {
  return name == "KHR_draco_mesh_compression" || name == "EXT_meshopt_compression";
}

}  // namespace rast::gltf_detail
