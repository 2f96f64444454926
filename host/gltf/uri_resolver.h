// Where the external files of a glTF scene (buffers and images given by URI)
// may be read from: inside the scene's folder, unless the user allows more.
//
// Both the loader's own checks and tinygltf's file callbacks go through one
// UriResolver, so what is checked is what is read: the URI is percent-decoded
// once (as tinygltf decodes it), joined to the scene's folder, resolved with
// realpath (symlinks, "..") and refused when the result lies outside that
// folder. An absolute path is outside by definition. data: URIs never reach
// the resolver (they are decoded in memory).
#pragma once

#include "host/scene/scene.h"

#include <cstdint>
#include <string>
#include <vector>

namespace rast {

class MemoryLedger;

// Thrown for a URI that resolves outside the scene's folder.
struct ExternalFileRefused : Error {
  using Error::Error;
};

class UriResolver {
 public:
  // sceneFile: the .gltf/.glb path as given; its folder is the root.
  UriResolver(const std::string& sceneFile, bool allowExternalFiles);

  // The folder tinygltf is given as its base: every path it hands back to the
  // file callbacks is this folder, '/', and the decoded URI.
  const std::string& baseDir() const { return base_; }

  // URI (as written in the file) -> resolved absolute path. Throws Error,
  // naming the resolved path, when it is outside the scene's folder (and that
  // is not allowed), missing or not a regular file.
  std::string resolveUri(const std::string& uri) const;
  // A path tinygltf built (baseDir() + "/" + decoded URI) -> resolved path.
  std::string resolveJoined(const std::string& path) const;

  // Reads a resolved file whole (charged to `ledger` when given).
  static std::vector<unsigned char> read(const std::string& resolved, MemoryLedger* ledger);

  // %XX decoding exactly as tinygltf's (which also turns '+' into a space).
  static std::string percentDecode(const std::string& uri);
  // Throws Error for a '%' not followed by two hex digits (tinygltf decodes
  // "%zz" to a NUL byte) and for %00.
  static void checkEscapes(const std::string& uri);

 private:
  std::string resolveDecoded(const std::string& decoded, const std::string& shown) const;

  std::string base_;  // the scene's folder as given ("." when the path has none)
  std::string root_;  // realpath of base_
  bool allowExternal_;
};

}  // namespace rast
