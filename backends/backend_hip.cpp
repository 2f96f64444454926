// HIP backend (AMD GPUs): stage timing with hipEvents on Kokkos' HIP stream,
// and the device's name, architecture and size for `rast info`.
#include "backends/event_stage_timer.h"
#include "backends/exec_space.h"
#include "backends/frame_graphs.h"
#include "backends/stage_timer.h"

#include <hip/hip_runtime.h>

#include <cstring>
#include <sstream>
#include <stdexcept>

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

StageTimer::StageTimer() : impl_(new Impl), id_(nextStageTimerId()) {}
StageTimer::~StageTimer() = default;
void StageTimer::start() { impl_->start(); }
void StageTimer::mark(const char* stage) { impl_->mark(stage); }
std::vector<std::pair<std::string, double>> StageTimer::finish() { return impl_->finish(); }
void StageTimer::replayMark(const char* stage) { impl_->replayMark(stage); }
size_t StageTimer::marks() const { return impl_->marks(); }
std::string StageTimer::markName(size_t i) const { return impl_->markName(i); }
void StageTimer::rewind(size_t marks) { impl_->rewind(marks); }

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

// HIP records no frames yet: ROCm cannot time events recorded inside a graph
// (ROCm/rocm-systems#2380), which the stage timer needs.
// The upload goes through pinned staging memory, as on CUDA (backend_cuda.cpp).
struct FrameGraphs::Impl {
  void* staging = nullptr;
  size_t capacity = 0;
  hipEvent_t copied = nullptr;
  Impl() { (void)hipEventCreateWithFlags(&copied, hipEventDisableTiming); }
  ~Impl() {
    (void)hipEventSynchronize(copied);
    (void)hipEventDestroy(copied);
    if (staging) (void)hipHostFree(staging);
  }
};
FrameGraphs::FrameGraphs() : impl_(new Impl) {}
FrameGraphs::~FrameGraphs() = default;
bool FrameGraphs::records() { return false; }
uint32_t* FrameGraphs::uploadSeen() const { return nullptr; }  // not measured on AMD: the event's wait stays
bool FrameGraphs::run(const std::string&, StageTimer*, uint64_t&, const Upload& u, const std::function<void()>& launch) {
  Impl& m = *impl_;
  (void)hipEventSynchronize(m.copied);  // the previous frame's copy has left the staging buffer
  if (u.bytes > m.capacity) {
    if (m.staging) (void)hipHostFree(m.staging);
    m.staging = nullptr;
    m.capacity = 0;
    if (hipHostMalloc(&m.staging, u.bytes, hipHostMallocDefault) != hipSuccess)
      throw std::runtime_error("hipHostMalloc of " + std::to_string(u.bytes) + " bytes failed");
    m.capacity = u.bytes;
  }
  std::memcpy(m.staging, u.src, u.bytes);
  (void)hipMemcpyAsync(u.dst, m.staging, u.bytes, hipMemcpyHostToDevice, Exec().hip_stream());
  (void)hipEventRecord(m.copied, Exec().hip_stream());
  launch();
  return false;
}

}  // namespace rast
