// backends/: whether an execution space is a GPU comes from Kokkos' space
// traits, and the launch shapes follow from it.
#include <catch2/catch.hpp>

#include "core/device.h"

TEST_CASE("backends: host spaces are not devices, GPU spaces are", "[backends]") {
  STATIC_REQUIRE_FALSE(rast::runsOnDevice<Kokkos::Serial>());
  STATIC_REQUIRE_FALSE(rast::runsOnDevice<Kokkos::DefaultHostExecutionSpace>());
#if defined(KOKKOS_ENABLE_OPENMP)
  STATIC_REQUIRE_FALSE(rast::runsOnDevice<Kokkos::OpenMP>());
#endif
#if defined(KOKKOS_ENABLE_CUDA)
  STATIC_REQUIRE(rast::runsOnDevice<Kokkos::Cuda>());
#endif
#if defined(KOKKOS_ENABLE_HIP)
  STATIC_REQUIRE(rast::runsOnDevice<Kokkos::Experimental::HIP>());
#endif
  STATIC_REQUIRE(rast::kOnDevice == rast::runsOnDevice<rast::Exec>());
}

TEST_CASE("backends: team size and thread counts follow the kind of machine", "[backends]") {
  const uint32_t c = uint32_t(rast::Exec().concurrency());
  if (rast::kOnDevice) {
    // whole 64-lane wavefronts (and 32-lane warps)
    CHECK(rast::kTeamSize % 64 == 0);
    CHECK(rast::persistentThreads() == c);
  } else {
    // a host team is one thread looping over the team's range (FineRaster's
    // incremental path relies on it)
    CHECK(rast::kTeamSize == 1);
    CHECK(rast::persistentThreads() == 16 * c);
    CHECK(rast::binBatchLimit() == 8 * c);
  }
  CHECK(rast::TeamPolicy(1, rast::kTeamSize).team_size() == rast::kTeamSize);
}
