// Per-stage timing of a frame, and the device description. Implemented once
// per kind of backend, and CMakeLists.txt compiles the one that matches the
// core library's execution space: backend_cuda.cpp and backend_hip.cpp record
// events on the execution stream (no host wait between stages,
// event_stage_timer.h); backend_host.cpp fences and reads a host clock.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace rast {

class StageTimer {
 public:
  StageTimer();
  ~StageTimer();
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;

  void start();                  // before the first stage of a frame
  void mark(const char* stage);  // after a stage has been enqueued
  // Waits for the frame and returns the milliseconds of each marked stage.
  std::vector<std::pair<std::string, double>> finish();

  // For recorded frames (frame_graphs.h). A mark made while a frame is being
  // recorded records its event in the recording; when the recording is
  // replayed, replayMark() takes that mark's place without recording anything
  // (the replay records the same event). marks() counts this frame's marks and
  // markName() names one; rewind() drops marks back to a count (a recording
  // that failed). id() tells timers apart: a recording uses one timer's events.
  void replayMark(const char* stage);
  size_t marks() const;
  std::string markName(size_t i) const;
  void rewind(size_t marks);
  uint64_t id() const { return id_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  uint64_t id_;
};

// A process-wide serial number for StageTimer::id().
inline uint64_t nextStageTimerId() {
  static std::atomic<uint64_t> next{1};
  return next.fetch_add(1);
}

// Backend, Kokkos version and parallelism, one "key: value" per line.
std::string deviceDescription();

// The accelerator's memory as its runtime reports it (cudaMemGetInfo,
// hipMemGetInfo), for soak tests and overlays; known == false on host
// backends, whose memory is the process's own (RSS).
struct DeviceMemory {
  bool known = false;
  size_t freeBytes = 0, totalBytes = 0;
};
DeviceMemory deviceMemory();

}  // namespace rast
