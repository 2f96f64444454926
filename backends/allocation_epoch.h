// A counter of device allocations, bumped by every allocation of a pipeline
// buffer (core/device.h's helpers). A recorded frame (frame_graphs.h) holds raw
// pointers to the buffers its kernels use: it is valid only while no buffer
// has been allocated or replaced since it was recorded.
#pragma once

#include <atomic>
#include <cstdint>

namespace rast {

inline std::atomic<uint64_t>& allocationEpochCounter() {
  static std::atomic<uint64_t> epoch{0};
  return epoch;
}
inline uint64_t allocationEpoch() { return allocationEpochCounter().load(std::memory_order_relaxed); }
inline void noteAllocation() { allocationEpochCounter().fetch_add(1, std::memory_order_relaxed); }

}  // namespace rast
