// The one exception type for bad input (files, options, budgets). It lives at
// the bottom of the tree so that every layer, host or pipeline, can throw it
// without depending on the scene: the CLI prints what() on one line and exits
// non-zero, and a library caller catches it.
#pragma once

#include <stdexcept>

namespace rast {

// Errors from bad input (files, options). The CLI prints what() on one line and
// exits non-zero.
struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace rast
