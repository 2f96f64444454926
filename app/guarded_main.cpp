#include "guarded_main.h"

#include "../core/scene.h"

#include <Kokkos_Core.hpp>

#include <cstdio>
#include <new>
#include <string>

namespace rast {

int guardedMain(const char* program, int argc, char** argv, const std::function<int(int, char**)>& run) {
  try {
    Kokkos::initialize(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: error: Kokkos could not start: %s\n", program, e.what());
    return 2;
  }
  int rc = 1;
  try {
    rc = run(argc, argv);
  } catch (const Error& e) {
    std::fprintf(stderr, "%s: error: %s\n", program, e.what());
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "%s: error: out of memory\n", program);
  } catch (const std::exception& e) {
    std::string m = e.what();
    for (char& c : m)
      if (c == '\n') c = ' ';
    std::fprintf(stderr, "%s: error: %s\n", program, m.c_str());
  }
  Kokkos::finalize();
  return rc;
}

}  // namespace rast
