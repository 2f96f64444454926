// RAST_FLATTEN in front of a kernel's operator(): on GCC host builds every
// call inside it is inlined (`flatten`), down to the helpers it shares with
// other kernels, which GCC otherwise leaves out of line when a kernel is as
// long as the glTF shading's (pipeline/shade/pbr_fragment.h: on duck, 1080p,
// calls to the BRDF, the barycentrics, the sRGB encoder and the texture
// coordinates cost about 300 instructions a fragment in their calls,
// arguments and lost common subexpressions). GPU compilers inline device
// functions of their own accord (and the kernel asks them with
// KOKKOS_FORCEINLINE_FUNCTION): there it is a plain inline function.
#pragma once

#include <Kokkos_Core.hpp>

#if defined(__GNUC__) && !defined(__clang__) && !defined(__CUDACC__) && !defined(__HIPCC__)
#define RAST_FLATTEN __attribute__((flatten)) inline
#else
#define RAST_FLATTEN KOKKOS_INLINE_FUNCTION
#endif
