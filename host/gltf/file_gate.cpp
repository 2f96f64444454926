// The glTF loader's gate to the file system: everything the loader reads from
// disk comes through here. The scene file is read whole after a stat (a FIFO
// would hang the reader, a directory or an empty file would give an obscure
// message, a file over 4 GiB cannot be a GLB), and the GLB container's header
// and chunk bounds are checked before tinygltf sees them (tinygltf 2.7 lets the
// BIN chunk reach 8 bytes past the end of the data). tinygltf's own file
// callbacks for external buffers and images go through the scene's
// UriResolver, so that a URI cannot reach outside the scene's folder (unless
// allowed) and every byte read is charged to the load's memory budget.
#include "host/gltf/gltf_internal.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <fstream>

namespace rast::gltf_detail {
namespace {

constexpr uint64_t kMaxFileBytes = 0xffffffffull;  // GLB lengths are 32-bit; so is tinygltf's API

uint32_t u32le(const unsigned char* p) {
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

}  // namespace

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

// tinygltf's file callbacks for external buffers and images: every path goes
// through the scene's UriResolver (tinygltf hands back base + "/" + decoded URI).
// "Exists" is always true so that tinygltf never falls back to looking in the
// current directory; the read says why a file cannot be had.
bool fileExistsForTinygltf(const std::string&, void*) { return true; }
std::string expandPathForTinygltf(const std::string& path, void*) { return path; }
bool readFileForTinygltf(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
  LoadContext& ctx = *static_cast<LoadContext*>(user);
  try {
    *out = UriResolver::read(ctx.resolver.resolveJoined(path), &ctx.ledger);
    return true;
  } catch (const Error& e) {
    if (ctx.fatal.empty() && (dynamic_cast<const ExternalFileRefused*>(&e) || dynamic_cast<const BudgetExceeded*>(&e)))
      ctx.fatal = e.what();
    if (err) *err += std::string(e.what()) + "\n";
    return false;
  }
}
bool writeFileForTinygltf(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err += "rast does not write files while loading\n";
  return false;
}

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

}  // namespace rast::gltf_detail
