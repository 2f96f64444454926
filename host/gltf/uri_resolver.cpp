#include "host/gltf/uri_resolver.h"

#include "host/scene/memory_budget.h"
#include "host/scene/scene.h"

#include <sys/stat.h>

#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <fstream>

namespace rast {
namespace {

std::string realPath(const std::string& p, int* err) {
  char buf[PATH_MAX];
  if (!::realpath(p.c_str(), buf)) {
    *err = errno;
    return std::string();
  }
  *err = 0;
  return buf;
}

int hexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return 0;  // as tinygltf's from_hex
}

}  // namespace

UriResolver::UriResolver(const std::string& sceneFile, bool allowExternalFiles) : allowExternal_(allowExternalFiles) {
  const auto slash = sceneFile.find_last_of('/');
  base_ = slash == std::string::npos ? std::string(".") : slash == 0 ? std::string("/") : sceneFile.substr(0, slash);
  int e = 0;
  root_ = realPath(base_, &e);
  if (root_.empty()) throw Error("cannot resolve the folder of '" + sceneFile + "': " + std::strerror(e));
}

std::string UriResolver::percentDecode(const std::string& s) {
  std::string out;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '+') {
      out += ' ';
    } else if (s[i] == '%' && s.size() > i + 2) {
      out += char(hexValue(s[i + 1]) << 4 | hexValue(s[i + 2]));
      i += 2;
    } else {
      out += s[i];
    }
  }
  return out;
}

std::string UriResolver::resolveUri(const std::string& uri) const { return resolveDecoded(percentDecode(uri), uri); }

std::string UriResolver::resolveJoined(const std::string& path) const {
  // tinygltf joins base + "/" + decoded (base + decoded when base ends in '/').
  const std::string prefix = base_.back() == '/' ? base_ : base_ + "/";
  if (path.compare(0, prefix.size(), prefix) != 0)
    throw Error("external file '" + path + "' is not relative to the scene's folder");
  return resolveDecoded(path.substr(prefix.size()), path.substr(prefix.size()));
}

std::string UriResolver::resolveDecoded(const std::string& decoded, const std::string& shown) const {
  if (decoded.empty()) throw Error("external file URI is empty");
  if (decoded.find('\0') != std::string::npos) throw Error("external file URI contains a NUL byte");
  const bool absolute = decoded[0] == '/';
  if (absolute && !allowExternal_)
    throw ExternalFileRefused("refusing to read '" + decoded + "': an absolute path, outside the scene's folder '" +
                              root_ + "' (--allow-external-files allows it)");
  const std::string joined = absolute ? decoded : (root_ == "/" ? "/" : root_ + "/") + decoded;
  int e = 0;
  const std::string resolved = realPath(joined, &e);
  if (resolved.empty()) {
    if (e == ENOENT) throw Error("file '" + shown + "' is missing ('" + joined + "': " + std::strerror(e) + ")");
    throw Error("file '" + shown + "': cannot resolve '" + joined + "': " + std::strerror(e));
  }
  if (!allowExternal_) {
    const bool inside = root_ == "/" || resolved.compare(0, root_.size() + 1, root_ + "/") == 0;
    if (!inside)
      throw ExternalFileRefused("refusing to read '" + resolved + "': it is outside the scene's folder '" + root_ +
                  "' (--allow-external-files allows it)");
  }
  struct stat st;
  if (::stat(resolved.c_str(), &st) != 0) throw Error("external file '" + resolved + "': " + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) throw Error("file '" + shown + "' ('" + resolved + "') is not a regular file");
  return resolved;
}

std::vector<unsigned char> UriResolver::read(const std::string& resolved, MemoryLedger* ledger) {
  struct stat st;
  if (::stat(resolved.c_str(), &st) != 0) throw Error("cannot open '" + resolved + "': " + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) throw Error("'" + resolved + "' is not a regular file");
  if (ledger) ledger->charge("external file '" + resolved + "'", uint64_t(st.st_size));
  std::ifstream f(resolved, std::ios::binary);
  if (!f) throw Error("cannot open '" + resolved + "': " + std::strerror(errno));
  std::vector<unsigned char> bytes(size_t(st.st_size));
  f.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size()));
  if (size_t(f.gcount()) != bytes.size()) throw Error("cannot read '" + resolved + "'");
  return bytes;
}

}  // namespace rast
