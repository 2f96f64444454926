#include "host/gltf/uri_resolver.h"

#include "host/scene/memory_budget.h"
#include "host/scene/scene.h"

#include <sys/stat.h>

#include <cctype>
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
  if (root_.empty()) throw Error("cannot resolve the folder of '" + printable(sceneFile) + "': " + std::strerror(e));
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

void UriResolver::checkEscapes(const std::string& uri) {
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] != '%') continue;
    const bool ok =
        i + 2 < uri.size() && std::isxdigit((unsigned char)uri[i + 1]) && std::isxdigit((unsigned char)uri[i + 2]);
    if (!ok)
      throw Error("URI '" + printable(uri, 120) + "' has an invalid percent escape '" + printable(uri.substr(i, 3)) +
                  "' (a '%' must be followed by two hex digits)");
    if (uri[i + 1] == '0' && uri[i + 2] == '0') throw Error("URI '" + printable(uri, 120) + "' contains %00, a NUL byte");
  }
}

std::string UriResolver::resolveUri(const std::string& uri) const {
  checkEscapes(uri);
  return resolveDecoded(percentDecode(uri), uri);
}

std::string UriResolver::resolveJoined(const std::string& path) const {
  // tinygltf joins base + "/" + decoded (base + decoded when base ends in '/').
  const std::string prefix = base_.back() == '/' ? base_ : base_ + "/";
  if (path.compare(0, prefix.size(), prefix) != 0)
    throw Error("external file '" + printable(path) + "' is not relative to the scene's folder");
  return resolveDecoded(path.substr(prefix.size()), path.substr(prefix.size()));
}

std::string UriResolver::resolveDecoded(const std::string& decoded, const std::string& shownRaw) const {
  const std::string shown = printable(shownRaw), dec = printable(decoded);
  if (decoded.empty()) throw Error("external file URI is empty");
  if (decoded.find('\0') != std::string::npos) throw Error("external file URI '" + shown + "' contains a NUL byte");
  const bool absolute = decoded[0] == '/';
  if (absolute && !allowExternal_)
    throw ExternalFileRefused("refusing to read '" + dec + "': an absolute path, outside the scene's folder '" +
                              printable(root_) + "' (--allow-external-files allows it)");
  const std::string joined = absolute ? decoded : (root_ == "/" ? "/" : root_ + "/") + decoded;
  int e = 0;
  const std::string resolved = realPath(joined, &e);
  if (resolved.empty()) {
    if (e == ENOENT)
      throw Error("file '" + shown + "' is missing ('" + printable(joined) + "': " + std::strerror(e) + ")");
    throw Error("file '" + shown + "': cannot resolve '" + printable(joined) + "': " + std::strerror(e));
  }
  if (resolved == root_) throw Error("file '" + shown + "' names the scene's folder itself, not a file");
  if (!allowExternal_) {
    const bool inside = root_ == "/" || resolved.compare(0, root_.size() + 1, root_ + "/") == 0;
    if (!inside)
      throw ExternalFileRefused("refusing to read '" + printable(resolved) + "': it is outside the scene's folder '" +
                                printable(root_) + "' (--allow-external-files allows it)");
  }
  struct stat st;
  if (::stat(resolved.c_str(), &st) != 0)
    throw Error("external file '" + printable(resolved) + "': " + std::strerror(errno));
  if (S_ISDIR(st.st_mode)) throw Error("file '" + shown + "' ('" + printable(resolved) + "') is a folder, not a file");
  if (!S_ISREG(st.st_mode)) throw Error("file '" + shown + "' ('" + printable(resolved) + "') is not a regular file");
  return resolved;
}

std::vector<unsigned char> UriResolver::read(const std::string& resolved, MemoryLedger* ledger) {
  const std::string shown = printable(resolved);
  struct stat st;
  if (::stat(resolved.c_str(), &st) != 0) throw Error("cannot open '" + shown + "': " + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) throw Error("'" + shown + "' is not a regular file");
  // /proc and /sys files are "regular" with a size of 0 and content made up
  // as they are read: not data a scene can hold.
  if (st.st_size == 0)
    throw ExternalFileRefused("refusing to read '" + shown +
                              "': its size is 0 (an empty file, or a special file such as those in /proc)");
  // Refused before a byte is read when it cannot fit the budget.
  if (ledger) ledger->charge("external file '" + shown + "'", uint64_t(st.st_size));
  std::ifstream f(resolved, std::ios::binary);
  if (!f) throw Error("cannot open '" + shown + "': " + std::strerror(errno));
  std::vector<unsigned char> bytes(size_t(st.st_size));
  f.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size()));
  if (size_t(f.gcount()) != bytes.size())
    throw Error("cannot read '" + shown + "': it has fewer bytes than its size says (" + std::to_string(f.gcount()) +
                " of " + std::to_string(bytes.size()) + ")");
  return bytes;
}

}  // namespace rast
