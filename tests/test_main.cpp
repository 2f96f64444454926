// Catch2 runner with Kokkos initialised once for all tests.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include <Kokkos_Core.hpp>

#include <cstdlib>

int main(int argc, char** argv) {
  // Kokkos' OpenMP start-up advice goes to stdout, where ctest's test discovery
  // would read it as test names; unit tests do not pin threads anyway.
  setenv("OMP_PROC_BIND", "false", 0);
  Kokkos::initialize();
  int rc = 0;
  {
    rc = Catch::Session().run(argc, argv);
  }
  Kokkos::finalize();
  return rc;
}
