// HIP backend (AMD GPUs): stage timing with hipEvents on Kokkos' HIP stream,
// and the device's name, architecture and size for `rast info`.
#include "event_stage_timer.h"
#include "exec_space.h"
#include "stage_timer.h"

#include <hip/hip_runtime.h>

#include <sstream>

namespace rast {

namespace {
struct HipEvents {
  using Event = hipEvent_t;
  static Event create() {
    hipEvent_t e = nullptr;
    (void)hipEventCreate(&e);
    return e;
  }
  static void destroy(Event e) { (void)hipEventDestroy(e); }
  static void record(Event e) { (void)hipEventRecord(e, Exec().hip_stream()); }
  static void wait(Event e) { (void)hipEventSynchronize(e); }
  static float elapsedMs(Event from, Event to) {
    float ms = 0.0f;
    (void)hipEventElapsedTime(&ms, from, to);
    return ms;
  }
};
}  // namespace

struct StageTimer::Impl : EventStageTimer<HipEvents> {};

StageTimer::StageTimer() : impl_(new Impl) {}
StageTimer::~StageTimer() = default;
void StageTimer::start() { impl_->start(); }
void StageTimer::mark(const char* stage) { impl_->mark(stage); }
std::vector<std::pair<std::string, double>> StageTimer::finish() { return impl_->finish(); }

std::string deviceDescription() {
  std::ostringstream os;
  os << describeExecSpace();
  int dev = 0;
  hipDeviceProp_t prop;
  if (hipGetDevice(&dev) == hipSuccess && hipGetDeviceProperties(&prop, dev) == hipSuccess) {
    os << "device: " << prop.name << " (" << prop.gcnArchName << ", " << prop.multiProcessorCount << " compute units, wavefront "
       << prop.warpSize << ", " << (prop.totalGlobalMem >> 20) << " MiB)\n";
  }
  return os.str();
}

DeviceMemory deviceMemory() {
  DeviceMemory m;
  size_t freeB = 0, totalB = 0;
  if (hipMemGetInfo(&freeB, &totalB) == hipSuccess) {
    m.known = true;
    m.freeBytes = freeB;
    m.totalBytes = totalB;
  }
  return m;
}

}  // namespace rast
