// Execution and memory spaces of the pipeline, chosen once at configure time.
//
// Every kernel of the renderer runs in rast::Exec and every device buffer lives
// in rast::Mem. The CMake option RAST_EXEC_SPACE picks the space; a build can
// compile the same sources twice (e.g. OpenMP and Serial) to compare backends.
// What is backend-specific (the space itself, team sizes and thread counts) is
// in backends/exec_space.h and backends/tuning.h; this header only forwards.
#pragma once

#include "backends/allocation_epoch.h"
#include "backends/exec_space.h"
#include "backends/tuning.h"

#include <Kokkos_Core.hpp>
#include <cstdint>

namespace rast {

// 1-D device buffer and its host mirror type.
template <class T>
using DView = Kokkos::View<T*, Mem>;

using Range = Kokkos::RangePolicy<Exec>;
using TeamPolicy = Kokkos::TeamPolicy<Exec>;
using TeamMember = TeamPolicy::member_type;

// Marks a kernel's policy so that its functor travels as a kernel argument
// (up to 4 KiB). Without it, Kokkos' CUDA backend launches functors over 512
// bytes through one shared constant-memory buffer and, before each such launch,
// waits on the host for the previous one to finish: a host-device
// synchronisation in the middle of the frame, which cost the H100 about 10 us
// per frame with the setup and shading kernels. Use it for every kernel whose
// functor carries the frame's views and parameters.
template <class Policy>
auto lightweight(const Policy& p) {
  return Kokkos::Experimental::require(p, Kokkos::Experimental::WorkItemProperty::HintLightWeight);
}

// Marks a kernel's policy so that its functor is copied to device memory and
// the kernel reads it there. For kernels whose code nvcc leaves partly out of
// line (the general shading kernel, the blend passes): a call out of line
// needs its `this` in addressable memory, and a functor that travels as a
// kernel argument is then copied to every thread's stack first (2.2 KB a
// thread for the shading functor: the H100's glTF-shaded frames took 0.46 ms
// to Blinn-Phong's 0.03). Kokkos copies the functor with an asynchronous copy
// from host memory before each launch, which a recorded frame cannot replay:
// frames with such a kernel are launched directly (Renderer::render).
template <class Policy>
auto heavyweight(const Policy& p) {
  return Kokkos::Experimental::require(p, Kokkos::Experimental::WorkItemProperty::HintHeavyWeight);
}

// Every pipeline buffer is allocated through these helpers, which count the
// allocations (allocation_epoch.h): a recorded frame whose buffers moved must
// not be replayed.
//
// Allocate a device buffer without initialising it: every kernel that reads a
// buffer first has it written by an earlier stage, so zero-filling would be
// wasted bandwidth.
template <class T>
DView<T> allocUninit(const char* label, size_t n) {
  noteAllocation();
  return DView<T>(Kokkos::view_alloc(Kokkos::WithoutInitializing, std::string(label)), n);
}

// A zero-filled buffer (counters), or with n == 0 a zero-filled scalar view.
template <class T>
DView<T> allocZeroed(const char* label, size_t n) {
  noteAllocation();
  return DView<T>(std::string(label), n);
}
template <class T>
Kokkos::View<T, Mem> allocScalar(const char* label) {
  noteAllocation();
  return Kokkos::View<T, Mem>(std::string(label));
}

// Grow-only resize: keeps the allocation when it is already large enough so that
// steady-state frames allocate nothing. Returns true when it reallocated.
template <class T>
bool ensureCapacity(DView<T>& v, const char* label, size_t n) {
  if (v.extent(0) >= n && v.data() != nullptr) return false;
  v = allocUninit<T>(label, n > 0 ? n : 1);  // never empty: an empty view would be allocated every frame
  return true;
}

// Bytes held by a view (for the peak-memory report).
template <class V>
size_t viewBytes(const V& v) {
  return v.span() * sizeof(typename V::value_type);
}

}  // namespace rast
