// RAST_FLATTEN in front of a kernel's operator(): on GCC host builds every
// call inside it is inlined (`flatten`), down to the helpers it shares with
// other kernels, which GCC otherwise leaves out of line when a kernel is as
// long as the glTF shading's (pipeline/shade/pbr_fragment.h: on duck, 1080p,
// calls to the BRDF, the barycentrics, the sRGB encoder and the texture
// coordinates cost about 300 instructions a fragment in their calls,
// arguments and lost common subexpressions). On GPUs it asks for the
// operator() to be inlined into Kokkos' launch wrapper: a kernel body left
// out of line is called with the functor's address, and a kernel launched
// lightweight then copies its whole functor from the kernel's parameters to
// every thread's stack first (2.4 KB for the glTF shading's: `cuobjdump
// -res-usage` STACK 2,416 bytes; the glTF shading keeps its body small
// enough for nvcc to inline by sampling its textures in one loop,
// Shade::materialTexels in pipeline/shade/pbr_fragment.h).
#pragma once

#include <Kokkos_Core.hpp>

#if defined(__GNUC__) && !defined(__clang__) && !defined(__CUDACC__) && !defined(__HIPCC__)
#define RAST_FLATTEN __attribute__((flatten)) inline
#elif defined(__CUDACC__) || defined(__HIPCC__)
#define RAST_FLATTEN KOKKOS_FORCEINLINE_FUNCTION
#else
#define RAST_FLATTEN KOKKOS_INLINE_FUNCTION
#endif

// RAST_GPU_INLINE on the member functions a shading kernel calls per
// fragment (the glTF material's lookups): on a GPU a member function left out
// of line needs its `this`, the functor, in addressable memory, and a kernel
// launched lightweight (its functor in the kernel's parameters, data/device.h)
// then copies the whole functor to every thread's stack first. On host
// backends a plain inline function (RAST_FLATTEN decides there).
#if defined(__CUDACC__) || defined(__HIPCC__)
#define RAST_GPU_INLINE KOKKOS_FORCEINLINE_FUNCTION
#else
#define RAST_GPU_INLINE KOKKOS_INLINE_FUNCTION
#endif

// RAST_HOST_FORCEINLINE: inlined wherever it is called on GCC host builds,
// a plain inline function elsewhere (GPU compilers keep their own choice).
// For the bilinear texture filter, which GCC left out of line in the glTF
// shading's kernel despite `flatten` (a call and its register saves twice a
// fragment, and the alpha channel computed where the material ignores it).
#if defined(__GNUC__) && !defined(__clang__) && !defined(__CUDACC__) && !defined(__HIPCC__)
#define RAST_HOST_FORCEINLINE __attribute__((always_inline)) inline
#else
#define RAST_HOST_FORCEINLINE KOKKOS_INLINE_FUNCTION
#endif
