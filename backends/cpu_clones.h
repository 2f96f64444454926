// RAST_CPU_CLONES in front of a free function of plain loops: on x86-64 with
// GCC (the host backends' compiler) the function is also compiled for AVX-512
// (x86-64-v4) and AVX2, and the variant the CPU supports is picked at load
// time (target_clones). The baseline build targets SSE2 only; the wider
// variants without contraction (-ffp-contract=off, CMakeLists.txt: no FMA
// although both ISAs have it) compute the same IEEE results, element by
// element, so every variant gives the same image. Elsewhere (GPU compilers,
// other hosts) it is a plain inline function.
//
// RAST_CPU_CLONES_GATHER: the same without the AVX-512 variant, for loops
// whose work is table lookups (texels, sRGB tables). On this project's
// machine (AMD EPYC, 2 cores) AVX-512 made the arithmetic loops faster and
// the gather loops slower: duck 800x800 went 2.50 -> 2.44 ms with every loop
// on AVX-512 (bilinear blending 15% -> 22% of the frame), 2.49 -> 2.18 ms
// with the two gather loops kept on AVX2 (medians of same-run A/Bs).
//
// Only for code that runs on the host: a cloned function is host code.
#pragma once

#include <Kokkos_Core.hpp>

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(__CUDACC__) && !defined(__HIPCC__)
#define RAST_CPU_CLONES __attribute__((target_clones("arch=x86-64-v4", "avx2", "default"), unused)) static
#define RAST_CPU_CLONES_GATHER __attribute__((target_clones("avx2", "default"), unused)) static
#else
#define RAST_CPU_CLONES KOKKOS_INLINE_FUNCTION
#define RAST_CPU_CLONES_GATHER KOKKOS_INLINE_FUNCTION
#endif

namespace rast {
// Spans shorter than this stay in the inline (baseline) loop: a cloned
// function is reached through an indirect call.
constexpr int kWideSpan = 8;
}  // namespace rast
