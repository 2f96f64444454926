// The one exception type for bad input (files, options, budgets). It lives at
// the bottom of the tree so that every layer, host or pipeline, can throw it
// without depending on the scene: the CLI prints what() on one line and exits
// non-zero, and a library caller catches it. Its definition is public
// (include/rast/error.h), so that the installed API throws the same type.
#pragma once

#include "include/rast/error.h"

#include <cstddef>
#include <stdexcept>
#include <string>

namespace rast {

// Text from outside (a path, a URI, a flag's value) made fit to be echoed in
// an Error: control characters become '?', and beyond `cap` bytes it is cut,
// with its length said: "...(N bytes)".
inline std::string printable(const std::string& s, size_t cap = 200) {
  std::string out = s.size() > cap ? s.substr(0, cap) : s;
  for (char& c : out)
    if ((unsigned char)c < 0x20 || c == 0x7f) c = '?';
  if (s.size() > cap) out += "...(" + std::to_string(s.size()) + " bytes)";
  return out;
}

}  // namespace rast
