// One number of bytes that loading and rendering may use (--max-memory), and a
// ledger that checks each large allocation against it *before* it is made, so
// that a small hostile file claiming huge counts or sizes ends in one clear
// Error instead of gigabytes of allocation (or the OOM killer).
#pragma once

#include "base/error.h"

#include <cstdint>
#include <string>

namespace rast {

// Thrown when something would go over the budget.
struct BudgetExceeded : Error {
  using Error::Error;
};

// Physical memory of the machine (sysconf), 0 when unknown.
uint64_t physicalMemoryBytes();
// The default budget: half of physical memory (4 GiB when that is unknown).
uint64_t defaultMemoryBudget();
// "512M", "4G", "1.5GiB", "65536" (bytes), "2T"; K/M/G/T are powers of 1024.
// Throws Error for anything else or for zero.
uint64_t parseMemorySize(const std::string& s);
// "1.5 GiB", "512 MiB", "100 bytes".
std::string formatBytes(uint64_t bytes);

// a * b (+ c), saturating at UINT64_MAX instead of wrapping: sizes computed
// from untrusted counts must not overflow into something small.
uint64_t mulSat(uint64_t a, uint64_t b);
uint64_t addSat(uint64_t a, uint64_t b);

// Bytes held against a limit. charge() keeps what it admits (data that stays
// for the rest of the load); check() only asks whether a temporary fits now.
class MemoryLedger {
 public:
  explicit MemoryLedger(uint64_t limit = defaultMemoryBudget()) : limit_(limit) {}
  // Throws Error "<what> needs N, over the memory budget of L by D (--max-memory)".
  void check(const std::string& what, uint64_t bytes) const;
  void charge(const std::string& what, uint64_t bytes);
  void release(uint64_t bytes) { used_ = bytes > used_ ? 0 : used_ - bytes; }
  uint64_t used() const { return used_; }
  uint64_t limit() const { return limit_; }

 private:
  uint64_t limit_, used_ = 0;
};

}  // namespace rast
