// inTeamScratch(p): a pointer into a team's scratch (Kokkos' team_scratch(0),
// which CUDA places in shared memory) that the compiler knows is one. Kokkos
// hands the scratch out as a generic pointer kept in the team member, so nvcc
// cannot tell where it points and reads it with generic loads, which wait on
// the long scoreboard as global memory does: the BLEND resolve's team form
// (pipeline/blend/peel_team.h) read its entries with 310 generic loads
// against 66 shared ones (`cuobjdump -sass`). Re-derived from a __shared__
// symbol (every dynamic shared array of a kernel starts at the same
// address), the same address is read with shared loads (375 of them, and
// one generic load left): on the H100 8 mixed layers' resolve 0.430 ->
// 0.397 ms. Backend-specific, so it lives here; on host backends, and on
// HIP until measured there, the pointer as it is.
#pragma once

#include <Kokkos_Core.hpp>

#include <cstddef>

namespace rast {

template <class T>
KOKKOS_FORCEINLINE_FUNCTION T* inTeamScratch(T* p) {
#if defined(__CUDA_ARCH__)
  extern __shared__ unsigned char rastTeamShared[];
  const size_t at = size_t(__cvta_generic_to_shared(p)) - size_t(__cvta_generic_to_shared(rastTeamShared));
  return reinterpret_cast<T*>(rastTeamShared + at);
#else
  return p;
#endif
}

}  // namespace rast
