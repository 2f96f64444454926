// shareChunks (host_workers.h): chunks claimed by ticket from one atomic word
// (the job's generation in the high half, the next chunk in the low half), so
// a helper holding a stale job can never claim a chunk of a later one; the
// calling thread works through the chunks itself and waits only for chunks
// already running on a helper. Helpers sleep on a condition variable between
// jobs (no spinning that would take a core from other programs).
#include "host/scene/host_workers.h"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <mutex>
#include <thread>

namespace rast {

namespace {

struct Job {
  uint32_t gen = 0, chunks = 0;
  int helpers = 0;  // helpers with an index below this may join
  void (*run)(void*, uint32_t) = nullptr;
  void* ctx = nullptr;
};

struct Workers {
  std::mutex callers;  // one job at a time
  int started = 0;     // helper threads started (under callers)
  std::mutex m;        // guards job and posted
  std::condition_variable wake;
  Job job;
  uint64_t posted = 0;
  std::atomic<uint64_t> ticket{0};  // job generation << 32 | next chunk
  std::atomic<uint32_t> done{0};    // chunks of the current job finished
};

// Never destroyed: detached helpers may still sleep on it at exit.
Workers& workers() {
  static Workers* w = new Workers;
  return *w;
}

// The next chunk of job `gen` into c; false when none is left or the job is over.
bool claim(Workers& w, uint32_t gen, uint32_t chunks, uint32_t& c) {
  uint64_t v = w.ticket.load(std::memory_order_acquire);
  for (;;) {
    if (uint32_t(v >> 32) != gen || uint32_t(v) >= chunks) return false;
    if (w.ticket.compare_exchange_weak(v, v + 1, std::memory_order_acq_rel, std::memory_order_acquire)) {
      c = uint32_t(v);
      return true;
    }
  }
}

void runClaimed(Workers& w, const Job& j) {
  uint32_t c = 0;
  while (claim(w, j.gen, j.chunks, c)) {
    j.run(j.ctx, c);
    w.done.fetch_add(1, std::memory_order_acq_rel);
  }
}

void helperLoop(Workers& w, int index) {
  uint64_t seen = 0;
  for (;;) {
    Job j;
    {
      std::unique_lock<std::mutex> lock(w.m);
      w.wake.wait(lock, [&] { return w.posted != seen; });
      seen = w.posted;
      j = w.job;  // a consistent copy: the caller writes the job under m
    }
    if (index < j.helpers) runClaimed(w, j);
  }
}

}  // namespace

void shareChunks(uint32_t chunks, int threads, void (*run)(void* ctx, uint32_t chunk), void* ctx) {
  if (threads <= 1 || chunks <= 1) {
    for (uint32_t c = 0; c < chunks; ++c) run(ctx, c);
    return;
  }
  Workers& w = workers();
  std::lock_guard<std::mutex> one(w.callers);
  const int helpers = std::min(threads - 1, 63);
  while (w.started < helpers) {
    std::thread(helperLoop, std::ref(w), w.started).detach();
    ++w.started;
  }
  Job j;
  {
    std::lock_guard<std::mutex> lock(w.m);
    j.gen = w.job.gen + 1;
    j.chunks = chunks;
    j.helpers = helpers;
    j.run = run;
    j.ctx = ctx;
    w.job = j;
    w.done.store(0, std::memory_order_relaxed);
    w.ticket.store(uint64_t(j.gen) << 32, std::memory_order_release);
    ++w.posted;
  }
  w.wake.notify_all();
  runClaimed(w, j);
  // Chunks still running on helpers: they are on a core (they claimed them).
  for (unsigned spins = 0; w.done.load(std::memory_order_acquire) < chunks; ++spins)
    if (spins > 64) std::this_thread::yield();
}

}  // namespace rast
