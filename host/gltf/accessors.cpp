// The glTF loader's reading of vertex and index data: accessors, the
// bufferViews and buffers under them, byteStride, sparse substitution, the
// component types and the normalisation of integer components. This is where
// a file's numbers become byte offsets, so every index, count and byte range
// is checked here before anything is allocated or read (a count whose byte
// size would wrap, a stride smaller than the element, a view past its buffer,
// a sparse index past the accessor), and accessors without a bufferView
// (zeros plus sparse entries, not stored in the file) may only claim elements
// in proportion to the file's size, so a few hundred bytes cannot claim
// gigabytes.
#include "host/gltf/gltf_internal.h"

#include <algorithm>
#include <cstring>

namespace rast::gltf_detail {
namespace {

constexpr size_t kMaxAccessorCount = 0xffffffffull;  // vertex indices are 32-bit
constexpr size_t kMaxZeroAccessorCount = size_t(1) << 24;  // accessors without a bufferView (zeros + sparse)

}  // namespace

std::vector<float> AccessorReader::floats(int index, int comps, const char* what) const {
  const tinygltf::Accessor& a = accessor(index, what);
  if (tinygltf::GetNumComponentsInType(a.type) != comps)
    throw Error(std::string(what) + ": accessor " + std::to_string(index) + " has the wrong type");
  checkCount(a, index, what);
  const Span sp = a.bufferView >= 0 ? span(a, comps, what) : Span{nullptr, 0, 0};
  ctx_.ledger.check(std::string(what) + " accessor " + std::to_string(index) + " (" + std::to_string(a.count) + " elements)",
                    mulSat(a.count, uint64_t(comps) * 4));
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

std::vector<uint32_t> AccessorReader::indices(int index) const {
  const char* what = "indices";
  const tinygltf::Accessor& a = accessor(index, what);
  if (a.type != TINYGLTF_TYPE_SCALAR) throw Error("indices accessor is not SCALAR");
  if (a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
      a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
      a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
    throw Error("indices accessor has a component type other than u8/u16/u32");
  checkCount(a, index, what);
  const Span sp = a.bufferView >= 0 ? span(a, 1, what) : Span{nullptr, 0, 0};
  ctx_.ledger.check("indices accessor " + std::to_string(index) + " (" + std::to_string(a.count) + " elements)",
                    mulSat(a.count, 4));
  std::vector<uint32_t> out(a.count, 0);
  if (sp.data)
    for (size_t i = 0; i < a.count; ++i) out[i] = uintAt(sp.data + i * sp.stride, a.componentType);
  applySparse(a, 1, what, [&](size_t row, const unsigned char* p, size_t) { out[row] = uintAt(p, a.componentType); });
  return out;
}

int AccessorReader::components(int index, const char* what) const {
  return tinygltf::GetNumComponentsInType(accessor(index, what).type);
}

const tinygltf::Accessor& AccessorReader::accessor(int index, const char* what) const {
  if (index < 0 || size_t(index) >= m_.accessors.size())
    throw Error(std::string(what) + ": accessor index " + std::to_string(index) + " out of range");
  return m_.accessors[index];
}

void AccessorReader::checkCount(const tinygltf::Accessor& a, int index, const char* what) const {
  const size_t limit = a.bufferView >= 0 ? kMaxAccessorCount : kMaxZeroAccessorCount;
  if (a.count > limit)
    throw Error(std::string(what) + ": accessor " + std::to_string(index) + " count " + std::to_string(a.count) +
                " is too large");
  if (a.bufferView < 0) {
    if (a.count > ctx_.zeroElementsLeft)
      throw Error(std::string(what) + ": accessor " + std::to_string(index) + " has no bufferView and a count of " +
                  std::to_string(a.count) + ", out of proportion to the file (" +
                  std::to_string(ctx_.zeroElementsLeft) + " such elements left for its size)");
    ctx_.zeroElementsLeft -= a.count;
  }
}

size_t AccessorReader::compSizeOf(int componentType, const char* what) {
  const int s = tinygltf::GetComponentSizeInBytes(componentType);
  if (s <= 0) throw Error(std::string(what) + ": unknown component type " + std::to_string(componentType));
  return size_t(s);
}

const unsigned char* AccessorReader::viewBytes(int bv, size_t offset, size_t len, const char* what) const {
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

AccessorReader::Span AccessorReader::span(const tinygltf::Accessor& a, int comps, const char* what) const {
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
void AccessorReader::applySparse(const tinygltf::Accessor& a, int comps, const char* what, F&& put) const {
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

uint32_t AccessorReader::uintAt(const unsigned char* p, int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return *p;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t v; memcpy(&v, p, 2); return v; }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { uint32_t v; memcpy(&v, p, 4); return v; }
    default: throw Error("index component type is not unsigned");
  }
}

float AccessorReader::component(const unsigned char* p, int type, bool normalized, const char* what) {
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

}  // namespace rast::gltf_detail
