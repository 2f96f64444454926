// Catch2 runner with Kokkos initialised once for all tests.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

#include "pipeline/data/test_hooks.h"

#include <Kokkos_Core.hpp>

#include <cstdlib>

namespace {

// Every test case starts with the pipeline's test hooks at their defaults
// (pipeline/data/test_hooks.h), whatever the case before it set or how it ended,
// but for keepFilm: tests compare the float film (Renderer::filmBottomUp) also
// of frames whose output is their colour's bytes, where a frame may leave
// pixels of it unwritten (BlendPlan::filmless; test_blend_film.cpp checks those).
rast::TestHooks testDefaults() {
  rast::TestHooks h;
  h.keepFilm = true;
  return h;
}
struct ResetTestHooks : Catch::TestEventListenerBase {
  using TestEventListenerBase::TestEventListenerBase;
  void testCaseStarting(const Catch::TestCaseInfo&) override { rast::testHooks() = testDefaults(); }
  void testCaseEnded(const Catch::TestCaseStats&) override { rast::testHooks() = testDefaults(); }
};

}  // namespace

CATCH_REGISTER_LISTENER(ResetTestHooks)

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
