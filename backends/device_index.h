// Which GPU the execution space runs on, for the library's callers that must
// name it (the Python module's DLPack arrays carry a device index, and
// consumers such as torch check it). Kokkos answers with device_id() since
// 4.1; the Kokkos 3.4 that the HIP bootstrap builds asks the instance. Host
// spaces have no device: -1.
#pragma once

#include "backends/exec_space.h"

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

}  // namespace rast
