// The one exception type of rast, public: the command line prints what() on one
// line and exits non-zero; a library caller (include/rast/rast.h, the Python
// module) catches it. The rest of the tree reaches it through base/error.h.
#pragma once

#include <stdexcept>

namespace rast {

// Errors from bad input (files, options, arrays, budgets). The message is the
// one the CLI prints after "rast: error: ".
struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace rast
