#include "app/views.h"

#include "base/error.h"

namespace rast {
namespace {

// Scans the pattern: returns the number of fields; fills the expansion.
int expand(const std::string& p, size_t index, std::string* out, std::string* bad) {
  int fields = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    if (p[i] != '%') {
      if (out) *out += p[i];
      continue;
    }
    if (i + 1 < p.size() && p[i + 1] == '%') {
      if (out) *out += '%';
      ++i;
      continue;
    }
    size_t j = i + 1;
    const bool zero = j < p.size() && p[j] == '0';
    if (zero) ++j;
    int width = 0;
    while (j < p.size() && p[j] >= '0' && p[j] <= '9' && width < 100) width = width * 10 + (p[j++] - '0');
    if (j >= p.size() || p[j] != 'd' || width > 12) {
      if (bad) *bad = p.substr(i, std::min<size_t>(j - i + 1, 8));
      return -1;
    }
    ++fields;
    std::string n = std::to_string(index);
    if (int(n.size()) < width) n = std::string(size_t(width) - n.size(), zero ? '0' : ' ') + n;
    if (out) *out += n;
    i = j;
  }
  return fields;
}

}  // namespace

bool hasViewField(const std::string& pattern) { return expand(pattern, 0, nullptr, nullptr) > 0; }

std::string viewPath(const std::string& pattern, size_t index, const char* what) {
  std::string out, bad;
  const int fields = expand(pattern, index, &out, &bad);
  if (fields < 0)
    throw Error(std::string(what) + " " + printable(pattern) + ": '" + printable(bad) +
                "' is not a view number field (use %d or %04d; %% for a literal %)");
  if (fields != 1)
    throw Error(std::string(what) + " " + printable(pattern) + ": with --cameras every output needs one view number "
                "field, e.g. out_%04d.png");
  return out;
}

}  // namespace rast
