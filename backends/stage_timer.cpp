#include "stage_timer.h"

#include "../core/device.h"

#include <sstream>

#if defined(RAST_EXEC_CUDA)
#include <cuda_runtime.h>
#endif

namespace rast {

#if defined(RAST_EXEC_CUDA)

// CUDA: events on the stream the kernels run on, read after the frame.
struct StageTimer::Impl {
  std::vector<cudaEvent_t> events;
  std::vector<std::string> names;
  size_t used = 0;
  cudaEvent_t next() {
    if (used == events.size()) {
      cudaEvent_t e;
      cudaEventCreate(&e);
      events.push_back(e);
    }
    return events[used++];
  }
  ~Impl() {
    for (cudaEvent_t e : events) cudaEventDestroy(e);
  }
};

StageTimer::StageTimer() : impl_(new Impl) {}
StageTimer::~StageTimer() = default;

void StageTimer::start() {
  impl_->used = 0;
  impl_->names.clear();
  cudaEventRecord(impl_->next(), Exec().cuda_stream());
}

void StageTimer::mark(const char* stage) {
  impl_->names.emplace_back(stage);
  cudaEventRecord(impl_->next(), Exec().cuda_stream());
}

std::vector<std::pair<std::string, double>> StageTimer::finish() {
  std::vector<std::pair<std::string, double>> out;
  if (impl_->used == 0) return out;
  cudaEventSynchronize(impl_->events[impl_->used - 1]);
  for (size_t i = 0; i < impl_->names.size(); ++i) {
    float ms = 0.0f;
    cudaEventElapsedTime(&ms, impl_->events[i], impl_->events[i + 1]);
    out.emplace_back(impl_->names[i], double(ms));
  }
  return out;
}

#else

// Host backends: fence, then read the clock.
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

#endif

std::string deviceDescription() {
  std::ostringstream os;
  os << "backend: " << Exec::name() << "\n";
  os << "kokkos: " << KOKKOS_VERSION / 10000 << "." << (KOKKOS_VERSION / 100) % 100 << "." << KOKKOS_VERSION % 100 << "\n";
  os << "concurrency: " << Exec().concurrency() << "\n";
#if defined(RAST_EXEC_CUDA)
  int dev = 0;
  cudaDeviceProp prop;
  if (cudaGetDevice(&dev) == cudaSuccess && cudaGetDeviceProperties(&prop, dev) == cudaSuccess) {
    os << "device: " << prop.name << " (compute capability " << prop.major << "." << prop.minor << ", "
       << prop.multiProcessorCount << " multiprocessors, " << (prop.totalGlobalMem >> 20) << " MiB)\n";
  }
#endif
  return os.str();
}

}  // namespace rast
