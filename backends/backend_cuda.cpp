// CUDA backend: stage timing with cudaEvents on Kokkos' CUDA stream, and the
// device's name and size for `rast info`.
#include "event_stage_timer.h"
#include "exec_space.h"
#include "stage_timer.h"

#include <cuda_runtime.h>

#include <sstream>

namespace rast {

namespace {
struct CudaEvents {
  using Event = cudaEvent_t;
  static Event create() {
    cudaEvent_t e = nullptr;
    cudaEventCreate(&e);
    return e;
  }
  static void destroy(Event e) { cudaEventDestroy(e); }
  static void record(Event e) { cudaEventRecord(e, Exec().cuda_stream()); }
  static void wait(Event e) { cudaEventSynchronize(e); }
  static float elapsedMs(Event from, Event to) {
    float ms = 0.0f;
    cudaEventElapsedTime(&ms, from, to);
    return ms;
  }
};
}  // namespace

struct StageTimer::Impl : EventStageTimer<CudaEvents> {};

StageTimer::StageTimer() : impl_(new Impl) {}
StageTimer::~StageTimer() = default;
void StageTimer::start() { impl_->start(); }
void StageTimer::mark(const char* stage) { impl_->mark(stage); }
std::vector<std::pair<std::string, double>> StageTimer::finish() { return impl_->finish(); }

std::string deviceDescription() {
  std::ostringstream os;
  os << describeExecSpace();
  int dev = 0;
  cudaDeviceProp prop;
  if (cudaGetDevice(&dev) == cudaSuccess && cudaGetDeviceProperties(&prop, dev) == cudaSuccess) {
    os << "device: " << prop.name << " (compute capability " << prop.major << "." << prop.minor << ", "
       << prop.multiProcessorCount << " multiprocessors, " << (prop.totalGlobalMem >> 20) << " MiB)\n";
  }
  return os.str();
}

DeviceMemory deviceMemory() {
  DeviceMemory m;
  size_t freeB = 0, totalB = 0;
  if (cudaMemGetInfo(&freeB, &totalB) == cudaSuccess) {
    m.known = true;
    m.freeBytes = freeB;
    m.totalBytes = totalB;
  }
  return m;
}

}  // namespace rast
