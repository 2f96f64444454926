#include "backends/exec_space.h"

#include <sstream>

namespace rast {

std::string describeExecSpace() {
  std::ostringstream os;
  os << "backend: " << Exec::name() << "\n";
  os << "kokkos: " << KOKKOS_VERSION / 10000 << "." << (KOKKOS_VERSION / 100) % 100 << "." << KOKKOS_VERSION % 100 << "\n";
  os << "concurrency: " << Exec().concurrency() << "\n";
  return os.str();
}

}  // namespace rast
