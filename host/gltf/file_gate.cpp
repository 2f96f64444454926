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

#include <algorithm>
#include <cerrno>
#include <cstdio>
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

std::vector<unsigned char> readWholeFile(const std::string& path, uint64_t budget) {
  const std::string shown = printable(path);
  struct stat st;
  if (::stat(path.c_str(), &st) != 0) throw Error("cannot open '" + shown + "': " + std::strerror(errno));
  if (S_ISDIR(st.st_mode)) throw Error("'" + shown + "' is a directory, not a glTF file");
  if (!S_ISREG(st.st_mode)) throw Error("'" + shown + "' is not a regular file");
  if (st.st_size == 0) throw Error("'" + shown + "' is empty, not a glTF file");
  if (uint64_t(st.st_size) > kMaxFileBytes) throw Error("'" + shown + "' is larger than 4 GiB");
  // Over the budget: refused before a byte is read.
  MemoryLedger(budget).check("the file '" + shown + "'", uint64_t(st.st_size));
  std::ifstream f(path, std::ios::binary);
  if (!f) throw Error("cannot open '" + shown + "': " + std::strerror(errno));
  // A glTF file is a GLB container or JSON: a look at its first bytes refuses
  // what is neither (a gigabyte of zeros) before the rest is read.
  unsigned char head[64];
  f.read(reinterpret_cast<char*>(head), std::streamsize(std::min<uint64_t>(sizeof head, uint64_t(st.st_size))));
  const size_t got = size_t(f.gcount());
  const bool glb = got >= 4 && std::memcmp(head, "glTF", 4) == 0;
  if (!glb) {
    size_t i = got >= 3 && head[0] == 0xEF && head[1] == 0xBB && head[2] == 0xBF ? 3 : 0;  // UTF-8 BOM
    while (i < got && (head[i] == ' ' || head[i] == '\t' || head[i] == '\n' || head[i] == '\r')) ++i;
    if (i < got && (head[i] == 0 || !std::strchr("{[\"-0123456789tfn", head[i]))) {  // no JSON value starts so
      char hex[8];
      std::snprintf(hex, sizeof hex, "0x%02x", unsigned(head[i]));
      throw Error("invalid JSON at byte " + std::to_string(i + 1) + ": a glTF file is a JSON object or a GLB container, "
                  "and no JSON value starts with byte " + hex);
    }
  }
  std::vector<unsigned char> bytes(size_t(st.st_size));
  std::memcpy(bytes.data(), head, got);
  f.read(reinterpret_cast<char*>(bytes.data() + got), std::streamsize(bytes.size() - got));
  if (got + size_t(f.gcount()) != bytes.size()) throw Error("cannot read '" + shown + "': shorter than its size");
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
    const std::string resolved = ctx.resolver.resolveJoined(path);
    *out = UriResolver::read(resolved, &ctx.ledger);
    ctx.filesRead.push_back(resolved);
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
