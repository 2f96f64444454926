// CUDA backend: stage timing with cudaEvents on Kokkos' CUDA stream, frames
// recorded as CUDA graphs by stream capture, and the device's name and size
// for `rast info`.
#include "backends/event_stage_timer.h"
#include "backends/exec_space.h"
#include "backends/frame_graphs.h"
#include "backends/recorded_frames.h"
#include "backends/stage_timer.h"

#include <cuda_runtime.h>

#include <cstdlib>
#include <stdexcept>
#include <cstring>
#include <sstream>

namespace rast {

namespace {
// Records e on stream s. While s is being recorded into a graph, as an
// external event: the replay records it, and the host can wait on it and time
// it (a plain record would only order the graph's nodes).
void recordEvent(cudaEvent_t e, cudaStream_t s) {
  cudaStreamCaptureStatus st = cudaStreamCaptureStatusNone;
  if (cudaStreamIsCapturing(s, &st) == cudaSuccess && st == cudaStreamCaptureStatusActive)
    cudaEventRecordWithFlags(e, s, cudaEventRecordExternal);
  else
    cudaEventRecord(e, s);
}

struct CudaEvents {
  using Event = cudaEvent_t;
  static Event create() {
    cudaEvent_t e = nullptr;
    cudaEventCreate(&e);
    return e;
  }
  static void destroy(Event e) { cudaEventDestroy(e); }
  static void record(Event e) { recordEvent(e, Exec().cuda_stream()); }
  static void wait(Event e) { cudaEventSynchronize(e); }
  static float elapsedMs(Event from, Event to) {
    float ms = 0.0f;
    cudaEventElapsedTime(&ms, from, to);
    return ms;
  }
};
}  // namespace

struct StageTimer::Impl : EventStageTimer<CudaEvents> {};

StageTimer::StageTimer() : impl_(new Impl), id_(nextStageTimerId()) {}
StageTimer::~StageTimer() = default;
void StageTimer::start() { impl_->start(); }
void StageTimer::mark(const char* stage) { impl_->mark(stage); }
std::vector<std::pair<std::string, double>> StageTimer::finish() { return impl_->finish(); }
void StageTimer::replayMark(const char* stage) { impl_->replayMark(stage); }
size_t StageTimer::marks() const { return impl_->marks(); }
std::string StageTimer::markName(size_t i) const { return impl_->markName(i); }
void StageTimer::rewind(size_t marks) { impl_->rewind(marks); }

namespace {
// Stream capture of Kokkos' launches. Relaxed mode: Kokkos' team launches
// call cudaMalloc for zero bytes of level-1 scratch, which the global mode
// forbids while capturing; nothing in a frame waits on the device.
// The upload's staging buffer is pinned host memory, so that the copy is an
// asynchronous DMA that a graph can replay (from pageable memory the driver
// may stage it and wait). The buffer may be refilled once the copy of what it
// holds has finished. The frame's vertex stage, which runs after the copy,
// writes the sequence number it read into `seen_`, mapped host memory: when
// that is the staged upload's, the host refills the buffer at once. Otherwise
// (no kernel has read it yet, or none wrote it) it waits on an event
// recorded after each copy. That wait was a driver call in every frame,
// before its launch, even with the copy long done: on the H100 the host's
// time to queue a frame fell from 8.4 to 6.2 us without it, and frames
// 0.4-2.3 us (docs/journal/performance-2026-11-*.md).
class CudaGraphs {
 public:
  using Exec = cudaGraphExec_t;
  CudaGraphs() {
    cudaEventCreateWithFlags(&copied_, cudaEventDisableTiming);
    void* p = nullptr;
    if (cudaHostAlloc(&p, sizeof(uint32_t), cudaHostAllocMapped) == cudaSuccess) {
      seen_ = static_cast<volatile uint32_t*>(p);
      *seen_ = 0;  // no sequence is 0 (frame_graphs.h)
      void* d = nullptr;  // the device's address of it (the same under unified addressing)
      if (cudaHostGetDevicePointer(&d, p, 0) == cudaSuccess) seenDevice_ = static_cast<uint32_t*>(d);
    }
    cudaGetLastError();  // a failure only costs the wait
  }
  ~CudaGraphs() {
    cudaEventSynchronize(copied_);
    cudaEventDestroy(copied_);
    if (staging_) cudaFreeHost(staging_);
    if (seen_) {
      cudaDeviceSynchronize();  // a frame's vertex stage may still write it
      cudaFreeHost(const_cast<uint32_t*>(seen_));
    }
  }
  CudaGraphs(const CudaGraphs&) = delete;
  CudaGraphs& operator=(const CudaGraphs&) = delete;

  uint32_t* seen() const { return seenDevice_; }

  void stage(const FrameGraphs::Upload& u) {
    if (!(seenDevice_ && held_ != 0 && *seen_ == held_)) cudaEventSynchronize(copied_);
    if (u.bytes > capacity_) {
      if (staging_) cudaFreeHost(staging_);
      staging_ = nullptr;
      capacity_ = 0;
      if (cudaHostAlloc(&staging_, u.bytes, cudaHostAllocDefault) != cudaSuccess)
        throw std::runtime_error("cudaHostAlloc of " + std::to_string(u.bytes) + " bytes failed");
      capacity_ = u.bytes;
      noteAllocation();  // recordings copy from the old buffer
    }
    std::memcpy(staging_, u.src, u.bytes);
    held_ = u.sequence;
  }
  void copy(const FrameGraphs::Upload& u) {
    const cudaStream_t s = rast::Exec().cuda_stream();
    cudaMemcpyAsync(u.dst, staging_, u.bytes, cudaMemcpyHostToDevice, s);
    recordEvent(copied_, s);
  }

  void begin() { cudaStreamBeginCapture(rast::Exec().cuda_stream(), cudaStreamCaptureModeRelaxed); }
  bool end(Exec& out) {
    cudaGraph_t g = nullptr;
    const cudaError_t err = cudaStreamEndCapture(rast::Exec().cuda_stream(), &g);
    bool ok = err == cudaSuccess && g != nullptr && cudaGraphInstantiateWithFlags(&out, g, 0) == cudaSuccess;
    if (g) cudaGraphDestroy(g);
    if (!ok) cudaGetLastError();  // clear the (non-sticky) capture error
    return ok;
  }
  bool launch(Exec e) { return cudaGraphLaunch(e, rast::Exec().cuda_stream()) == cudaSuccess; }
  void destroy(Exec e) { cudaGraphExecDestroy(e); }

 private:
  void* staging_ = nullptr;
  size_t capacity_ = 0;
  cudaEvent_t copied_ = nullptr;
  volatile uint32_t* seen_ = nullptr;  // host view of the sequence the device last read
  uint32_t* seenDevice_ = nullptr;     // device view of the same word
  uint32_t held_ = 0;                  // sequence of the upload in the staging buffer (0: none yet)
};

bool graphsEnabled() {
  static const bool on = [] {
    const char* v = std::getenv("RAST_FRAME_GRAPHS");
    return !(v && std::strcmp(v, "0") == 0);
  }();
  return on;
}
}  // namespace

struct FrameGraphs::Impl : RecordedFrames<CudaGraphs> {};

FrameGraphs::FrameGraphs() : impl_(new Impl) {}
FrameGraphs::~FrameGraphs() = default;
bool FrameGraphs::records() { return graphsEnabled(); }
uint32_t* FrameGraphs::uploadSeen() const { return impl_->api().seen(); }
bool FrameGraphs::run(const std::string& key, StageTimer* timer, uint64_t& hostState, const Upload& upload,
                      const std::function<void()>& launch) {
  if (!graphsEnabled()) {
    impl_->direct(upload, launch);
    return false;
  }
  return impl_->run(key, timer, hostState, upload, launch);
}

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
