// Host backends (Serial, OpenMP, and any other space whose kernels run on the
// host's cores): stage timing by fence and host clock, which costs nothing
// extra because these backends run kernels synchronously anyway.
#include "stage_timer.h"

#include "exec_space.h"

#include <sstream>

namespace rast {

static_assert(!kOnDevice, "backend_host.cpp is for execution spaces that run on the host (CMakeLists.txt picks the file)");

struct StageTimer::Impl {
  Kokkos::Timer timer;
  double last = 0.0;
  std::vector<std::pair<std::string, double>> stages;
};

StageTimer::StageTimer() : impl_(new Impl) {}
StageTimer::~StageTimer() = default;

void StageTimer::start() {
  Exec().fence();
  impl_->stages.clear();
  impl_->timer.reset();
  impl_->last = 0.0;
}

void StageTimer::mark(const char* stage) {
  Exec().fence();
  const double now = impl_->timer.seconds();
  impl_->stages.emplace_back(stage, (now - impl_->last) * 1e3);
  impl_->last = now;
}

std::vector<std::pair<std::string, double>> StageTimer::finish() { return impl_->stages; }

std::string deviceDescription() { return describeExecSpace(); }

DeviceMemory deviceMemory() { return {}; }

}  // namespace rast
