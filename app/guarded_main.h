// The start and end every rast executable shares: Kokkos initialised from the
// command line (its --kokkos-* flags), the program run, and every error turned
// into one line "<program>: error: ..." on stderr with a non-zero exit.
#pragma once

#include <exception>
#include <functional>

namespace rast {

// Thrown by a rank of a distributed run whose error rank 0 reports (app/distribute.h):
// the process exits with status 1 and prints nothing.
struct QuietFailure : std::exception {
  const char* what() const noexcept override { return "failed on another rank"; }
};

// Returns the program's exit status: run()'s, 1 after an error, 2 when Kokkos
// itself cannot start (e.g. a malformed --kokkos-* flag).
// True when OMP_PROC_BIND was unset and rast chose it (false: no pinning).
bool openMPBindingIsDefault();

int guardedMain(const char* program, int argc, char** argv, const std::function<int(int, char**)>& run);

}  // namespace rast
