#include "app/guarded_main.h"

#include "base/error.h"

#include <Kokkos_Core.hpp>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <string>
#include <vector>

namespace rast {
namespace {

// Kokkos' OpenMP backend prints four lines of advice on stdout when OMP_PROC_BIND is
// unset. We set what the process already does: libgomp read its environment when it
// was loaded, before main, so an unset OMP_PROC_BIND has already meant "no binding",
// which is also the safe choice for a command-line tool sharing cores with other work.
// A user's own OMP_PROC_BIND / OMP_PLACES are kept (and honoured by libgomp).
bool g_bindDefault = false;

void setOpenMPDefaults() {
  if (std::getenv("OMP_PROC_BIND")) return;
  setenv("OMP_PROC_BIND", "false", 0);
  g_bindDefault = true;
}

bool isKokkosFlag(const char* a) { return std::strncmp(a, "--kokkos-", 9) == 0; }

}  // namespace

bool openMPBindingIsDefault() { return g_bindDefault; }

int guardedMain(const char* program, int argc, char** argv, const std::function<int(int, char**)>& run) {
  setOpenMPDefaults();
  // Kokkos sees only its own --kokkos-* flags: given all of them, Kokkos 3.x also
  // answers unprefixed ones such as --help and --threads with its own text. Our
  // parser sees everything else, in order.
  std::vector<char*> kokkosArgs{argv[0]}, ownArgs{argv[0]};
  for (int i = 1; i < argc; ++i) (isKokkosFlag(argv[i]) ? kokkosArgs : ownArgs).push_back(argv[i]);
  int kargc = int(kokkosArgs.size());
  kokkosArgs.push_back(nullptr);
  try {
    Kokkos::initialize(kargc, kokkosArgs.data());
  } catch (const std::exception& e) {
    // Kokkos 3.x parses numbers with std::stoi, whose message is just "stoi".
    std::fprintf(stderr, "%s: error: Kokkos could not start (%s): check the --kokkos-* flags\n", program, e.what());
    return 2;
  }
  // Kokkos removes the flags it understood; any left over are not Kokkos' either.
  for (int i = 1; i < kargc; ++i) {
    std::fprintf(stderr, "%s: error: unknown Kokkos option '%s' (see --kokkos-help)\n", program, kokkosArgs[i]);
    Kokkos::finalize();
    return 2;
  }
  int rc = 1;
  const int oargc = int(ownArgs.size());
  ownArgs.push_back(nullptr);
  try {
    rc = run(oargc, ownArgs.data());
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
