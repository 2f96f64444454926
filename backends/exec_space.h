// The execution space of the pipeline, chosen once at configure time, and what
// kind of machine it is.
//
// This is the only place that maps the build's RAST_EXEC_<SPACE> definition
// (set by CMakeLists.txt from RAST_EXEC_SPACE, per core library) to a Kokkos
// type. Everything else asks the type: kOnDevice says whether kernels run on an
// accelerator, derived from Kokkos' own space traits, so core/ needs no
// `#if defined(KOKKOS_ENABLE_CUDA)` and a new backend is one line here (plus
// its timer file and a preset).
#pragma once

#include <Kokkos_Core.hpp>

#include <string>

namespace rast {

#if defined(RAST_EXEC_SERIAL)
using Exec = Kokkos::Serial;
#elif defined(RAST_EXEC_OPENMP)
using Exec = Kokkos::OpenMP;
#elif defined(RAST_EXEC_CUDA)
using Exec = Kokkos::Cuda;
#elif defined(RAST_EXEC_HIP)
#if KOKKOS_VERSION >= 40000
using Exec = Kokkos::HIP;  // left Kokkos::Experimental in 4.0
#else
using Exec = Kokkos::Experimental::HIP;
#endif
#else
using Exec = Kokkos::DefaultExecutionSpace;
#endif

using Mem = Exec::memory_space;

// Host memory the device reads and writes directly, without a staged copy
// (page-locked and mapped on GPUs): small results the host waits for, such
// as a frame's counters, land there from a kernel or one asynchronous copy.
// Where Kokkos (before 4.0) has no such space, plain host memory: kernels of
// a GPU build cannot write it, and kPinnedFromDevice says so.
#if KOKKOS_VERSION >= 40000
using PinnedSpace = Kokkos::SharedHostPinnedSpace;
#else
using PinnedSpace = Kokkos::HostSpace;
#endif
constexpr bool kPinnedFromDevice = Kokkos::SpaceAccessibility<Exec, PinnedSpace>::accessible;

// True when Space's kernels cannot read host memory, i.e. they run on a
// discrete accelerator (CUDA, HIP, SYCL) rather than on the host's cores
// (Serial, OpenMP, Threads, HPX). Decided by Kokkos' accessibility traits, so
// it holds for any backend without naming it.
template <class Space>
constexpr bool runsOnDevice() {
  return !Kokkos::SpaceAccessibility<Space, Kokkos::HostSpace>::accessible;
}

constexpr bool kOnDevice = runsOnDevice<Exec>();

// Lanes of the build's GPU that run in lockstep: an AMD wavefront under HIP,
// an NVIDIA warp otherwise (meaningless on host backends). For launch shapes
// one SIMD group wide (backends/tuning.h).
#if defined(RAST_EXEC_HIP)
constexpr int kSimdWidth = 64;
#else
constexpr int kSimdWidth = 32;
#endif

// Backend, Kokkos version and parallelism, one "key: value" per line (the part
// of deviceDescription() every backend shares).
std::string describeExecSpace();

}  // namespace rast
