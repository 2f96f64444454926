// RAST_CPU_CLONES in front of a free function of plain loops: on x86-64 with
// GCC (the host backends' compiler) the function is also compiled for AVX2
// and the variant the CPU supports is picked at load time (target_clones).
// The baseline build targets SSE2 only; AVX2 without FMA (contraction is off,
// CMakeLists.txt) computes the same IEEE results, twice as wide. Elsewhere
// (GPU compilers, other hosts) it is a plain inline function.
// Only for code that runs on the host: a cloned function is host code.
#pragma once

#include <Kokkos_Core.hpp>

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(__CUDACC__) && !defined(__HIPCC__)
#define RAST_CPU_CLONES __attribute__((target_clones("avx2", "default"))) static
#else
#define RAST_CPU_CLONES KOKKOS_INLINE_FUNCTION
#endif

namespace rast {
// Spans shorter than this stay in the inline (baseline) loop: a cloned
// function is reached through an indirect call.
constexpr int kWideSpan = 8;
}  // namespace rast
