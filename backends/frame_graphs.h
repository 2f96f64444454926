// Recorded frames: on a GPU whose runtime can record a sequence of kernel
// launches and replay it as one unit (CUDA graphs), a frame's launches after
// its first kernel are recorded once and then replayed, frame after frame, for
// the cost of one launch on the host instead of one per kernel. Everything the
// recorded kernels read that changes from frame to frame (the camera) is in
// device memory, copied there at the start of the recording from a staging
// buffer that the host refills before each replay (run()'s upload).
//
// A recording is kept per key and replayed only while
//  - the key is the same: the key names everything the kernels' arguments
//    depend on besides device memory (settings, method, timer);
//  - no pipeline buffer has been allocated since it was recorded
//    (allocation_epoch.h): its kernels hold raw pointers. The count is
//    process-wide, so another renderer's allocation drops it too: safe, and
//    a renderer that keeps its buffers (a viewer, a benchmark) still replays.
// A key's first frame runs directly (its buffers grow), its second frame is
// recorded (if nothing was allocated in between) and every later one replays.
// Backends that cannot record run every frame directly; so does every backend
// with RAST_FRAME_GRAPHS=0 in the environment.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

namespace rast {

class StageTimer;

class FrameGraphs {
 public:
  FrameGraphs();
  ~FrameGraphs();
  FrameGraphs(const FrameGraphs&) = delete;
  FrameGraphs& operator=(const FrameGraphs&) = delete;

  // Whether this build records and replays frames (and RAST_FRAME_GRAPHS is not 0).
  static bool records();

  // Bytes copied from host to device memory before the frame's kernels (the
  // camera): src is read before run() returns; dst must stay allocated.
  struct Upload {
    const void* src;
    void* dst;
    size_t bytes;
    uint32_t sequence;  // not 0, and not the previous upload's (the frame number)
  };

  // Where the frame's first kernel may write the sequence of the upload it
  // read (uploadSeen): a word of host memory the device can write, or null.
  // Seeing there the sequence of what the staging buffer holds, the host
  // refills it without waiting on the device (backend_cuda.cpp).
  uint32_t* uploadSeen() const;

  // Enqueues the upload and launch()'s kernels on the execution space's
  // stream: by calling launch(), or by replaying its recording. launch() must
  // enqueue the same work for the same key and epoch, and must not wait on
  // the device. hostState: host-side bookkeeping that launch() updates; a
  // replay restores what the recorded call left. Timer marks made inside
  // launch() are replayed too. Returns true when the frame was replayed.
  bool run(const std::string& key, StageTimer* timer, uint64_t& hostState, const Upload& upload,
           const std::function<void()>& launch);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rast
