// Output names for many views (`rast render --cameras FILE -o out_%04d.png`):
// each view's files are named from a pattern holding one printf-style %d
// (with an optional zero-padded width, %04d), checked before any rendering.
#pragma once

#include <cstddef>
#include <string>

namespace rast {

// Whether the path holds a view-number field (%d or %0Nd).
bool hasViewField(const std::string& pattern);
// The pattern with its field replaced by `index`; throws Error for a pattern
// with no field, two fields or any other % sequence ("%%" is a literal %).
std::string viewPath(const std::string& pattern, size_t index, const char* what);

}  // namespace rast
