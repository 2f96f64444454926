// Which GPU the execution space runs on, and which stream its default
// instance queues work on, for the library's callers that must name them (the
// Python module's DLPack arrays carry a device index, and consumers such as
// torch check it; a DLPack producer given the stream makes its data ready on
// it without a wait on the host). Kokkos answers with device_id() since
// 4.1; the Kokkos 3.4 that the HIP bootstrap builds asks the instance. Host
// spaces have no device: -1.
#pragma once

#include "backends/exec_space.h"

#include <cstdint>

namespace rast {

inline int deviceIndex() {
  if (!kOnDevice) return -1;
#if KOKKOS_VERSION >= 40100
  return Kokkos::device_id();
#elif defined(RAST_EXEC_HIP)
  return Exec().hip_device();
#elif defined(RAST_EXEC_CUDA)
  return Exec().cuda_device();
#else
  return -1;
#endif
}

// The default instance's stream as an integer; 0 on host backends (and for
// a GPU instance on the legacy default stream).
inline std::uintptr_t deviceStream() {
#if defined(RAST_EXEC_HIP)
  return reinterpret_cast<std::uintptr_t>(Exec().hip_stream());
#elif defined(RAST_EXEC_CUDA)
  return reinterpret_cast<std::uintptr_t>(Exec().cuda_stream());
#else
  return 0;
#endif
}

// Whether the default instance's stream waits for the work queued before on
// the GPU's legacy default stream: it is that stream, or a blocking one (as
// Kokkos creates its own). A caller queuing there (torch's default) then
// needs no event to order its work before the library's.
inline bool deviceStreamFollowsLegacy() {
#if defined(RAST_EXEC_HIP)
  unsigned int flags = 0;
  hipStream_t s = Exec().hip_stream();
  return s == nullptr || (hipStreamGetFlags(s, &flags) == hipSuccess && (flags & hipStreamNonBlocking) == 0);
#elif defined(RAST_EXEC_CUDA)
  unsigned int flags = 0;
  cudaStream_t s = Exec().cuda_stream();
  return s == nullptr || (cudaStreamGetFlags(s, &flags) == cudaSuccess && (flags & cudaStreamNonBlocking) == 0);
#else
  return false;
#endif
}

}  // namespace rast
