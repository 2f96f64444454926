// Host backends (Serial, OpenMP, and any other space whose kernels run on the
// host's cores): stage timing by fence and host clock, which costs nothing
// extra because these backends run kernels synchronously anyway.
#include "backends/frame_graphs.h"
#include "backends/stage_timer.h"

#include "backends/exec_space.h"

#include <cstring>
#include <sstream>

namespace rast {

static_assert(!kOnDevice, "backend_host.cpp is for execution spaces that run on the host (CMakeLists.txt picks the file)");

struct StageTimer::Impl {
  Kokkos::Timer timer;
  double last = 0.0;
  std::vector<std::pair<std::string, double>> stages;
};

StageTimer::StageTimer() : impl_(new Impl), id_(nextStageTimerId()) {}
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
// Host backends record no frames (frame_graphs.h): a replayed mark is a mark.
void StageTimer::replayMark(const char* stage) { mark(stage); }
size_t StageTimer::marks() const { return impl_->stages.size(); }
std::string StageTimer::markName(size_t i) const { return impl_->stages.at(i).first; }
void StageTimer::rewind(size_t marks) { impl_->stages.resize(marks); }

std::string deviceDescription() { return describeExecSpace(); }

DeviceMemory deviceMemory() { return {}; }

// Host backends record no frames: kernels run as they are launched, and a
// launch costs the host little.
struct FrameGraphs::Impl {};
FrameGraphs::FrameGraphs() = default;
FrameGraphs::~FrameGraphs() = default;
bool FrameGraphs::records() { return false; }
uint32_t* FrameGraphs::uploadSeen() const { return nullptr; }  // the copy is synchronous
bool FrameGraphs::run(const std::string&, StageTimer*, uint64_t&, const Upload& upload,
                      const std::function<void()>& launch) {
  std::memcpy(upload.dst, upload.src, upload.bytes);  // kernels before it have finished: host kernels are synchronous
  launch();
  return false;
}

}  // namespace rast
