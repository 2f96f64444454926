#include "host/scene/memory_budget.h"

#include "host/scene/scene.h"

#include <unistd.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

namespace rast {

uint64_t physicalMemoryBytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), pageSize = ::sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || pageSize <= 0) return 0;
  return mulSat(uint64_t(pages), uint64_t(pageSize));
}

uint64_t defaultMemoryBudget() {
  const uint64_t phys = physicalMemoryBytes();
  return phys ? phys / 2 : (uint64_t(4) << 30);
}

uint64_t parseMemorySize(const std::string& s) {
  const auto bad = [&s]() { return Error("--max-memory: expected a size such as 512M or 4G, got '" + s + "'"); };
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (end == s.c_str() || !std::isfinite(v) || v <= 0.0) throw bad();
  std::string unit(end);
  for (char& c : unit) c = char(std::toupper((unsigned char)c));
  if (unit.size() > 1 && unit.back() == 'B') unit.pop_back();   // "MB", "GiB" -> "M", "Gi"
  if (unit.size() > 1 && unit.back() == 'I') unit.pop_back();
  double scale = 1.0;
  if (unit.empty() || unit == "B") scale = 1.0;
  else if (unit == "K") scale = 1024.0;
  else if (unit == "M") scale = 1024.0 * 1024.0;
  else if (unit == "G") scale = 1024.0 * 1024.0 * 1024.0;
  else if (unit == "T") scale = 1024.0 * 1024.0 * 1024.0 * 1024.0;
  else throw bad();
  const double bytes = v * scale;
  if (bytes < 1.0) throw bad();
  if (bytes >= 18446744073709551615.0) return std::numeric_limits<uint64_t>::max();
  return uint64_t(bytes);
}

std::string formatBytes(uint64_t b) {
  static const char* units[] = {"KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  if (b < 1024) return std::to_string(b) + " bytes";
  double v = double(b);
  int u = -1;
  while (v >= 1024.0 && u < 5) {
    v /= 1024.0;
    ++u;
  }
  char buf[32];
  std::snprintf(buf, sizeof buf, v < 10.0 ? "%.2f %s" : v < 100.0 ? "%.1f %s" : "%.0f %s", v, units[u]);
  return buf;
}

uint64_t mulSat(uint64_t a, uint64_t b) {
  if (a != 0 && b > std::numeric_limits<uint64_t>::max() / a) return std::numeric_limits<uint64_t>::max();
  return a * b;
}

uint64_t addSat(uint64_t a, uint64_t b) {
  return b > std::numeric_limits<uint64_t>::max() - a ? std::numeric_limits<uint64_t>::max() : a + b;
}

void MemoryLedger::check(const std::string& what, uint64_t bytes) const {
  const uint64_t total = addSat(used_, bytes);
  if (total <= limit_) return;
  std::string m = what + " needs " + formatBytes(bytes);
  if (used_) m += " (with " + formatBytes(used_) + " already held)";
  m += ", over the memory budget of " + formatBytes(limit_) + " by " + formatBytes(total - limit_) +
       " (raise it with --max-memory)";
  throw BudgetExceeded(m);
}

void MemoryLedger::charge(const std::string& what, uint64_t bytes) {
  check(what, bytes);
  used_ += bytes;
}

}  // namespace rast
