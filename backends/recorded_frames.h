// FrameGraphs' bookkeeping (frame_graphs.h) for any runtime that can record
// launches on a stream and replay them. Api is an object providing
//   using Exec;                                 // an instantiated recording
//   void begin();                               // start recording the stream
//   bool end(Exec& out);                        // stop; false if the recording failed
//   bool launch(Exec e);                        // replay on the stream
//   void destroy(Exec e);
//   void stage(const FrameGraphs::Upload& u);   // host: u.src into the staging buffer, once
//                                               // the previous frame's copy has left it
//   void copy(const FrameGraphs::Upload& u);    // stream: staging buffer -> u.dst
#pragma once

#include "backends/allocation_epoch.h"
#include "backends/frame_graphs.h"
#include "backends/stage_timer.h"

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace rast {

template <class Api>
class RecordedFrames {
 public:
  RecordedFrames() = default;
  RecordedFrames(const RecordedFrames&) = delete;
  RecordedFrames& operator=(const RecordedFrames&) = delete;
  ~RecordedFrames() {
    for (auto& kv : entries_) drop(kv.second);
  }

  bool run(const std::string& key, StageTimer* timer, uint64_t& hostState, const FrameGraphs::Upload& upload,
           const std::function<void()>& launch) {
    std::string k = key;
    const uint64_t t = timer ? timer->id() : 0;  // a recording records one timer's events
    k.append(reinterpret_cast<const char*>(&t), sizeof t);
    Entry& e = entries_[k];
    e.lastUse = ++tick_;
    evict();  // the least recently used beyond kMaxEntries (never e, the newest)
    api_.stage(upload);
    const uint64_t epoch = allocationEpoch();
    if (e.recorded && e.epoch == epoch && api_.launch(e.exec)) {
      if (timer)
        for (const std::string& m : e.marks) timer->replayMark(m.c_str());
      hostState = e.hostState;
      return true;
    }
    drop(e);
    // Record only a key's second frame with unchanged buffers: the first
    // grows them, and allocating while recording would record nothing.
    if (!e.failed && e.directEpoch == epoch) {
      const size_t marks0 = timer ? timer->marks() : 0;
      const uint64_t state0 = hostState;
      bool ok = true;
      api_.begin();
      try {
        api_.copy(upload);
        launch();
      } catch (...) {
        ok = false;  // something waited on the device (a bug: launch() must not)
      }
      typename Api::Exec exec{};
      ok = api_.end(exec) && ok;
      const bool moved = allocationEpoch() != epoch;
      if (ok && !moved && api_.launch(exec)) {
        e.exec = exec;
        e.recorded = true;
        e.epoch = epoch;
        e.hostState = hostState;
        e.marks.clear();
        for (size_t i = marks0; timer && i < timer->marks(); ++i) e.marks.push_back(timer->markName(i));
        return false;
      }
      if (ok) api_.destroy(exec);
      e.failed = !moved;  // a recording that fails with unchanged buffers would fail again
      if (timer) timer->rewind(marks0);
      hostState = state0;
    }
    api_.copy(upload);
    launch();
    e.directEpoch = allocationEpoch();
    return false;
  }

  const Api& api() const { return api_; }

  // The upload and launch() with no recording (recording turned off).
  void direct(const FrameGraphs::Upload& upload, const std::function<void()>& launch) {
    api_.stage(upload);
    api_.copy(upload);
    launch();
  }

 private:
  struct Entry {
    typename Api::Exec exec{};
    bool recorded = false, failed = false;
    uint64_t epoch = 0, directEpoch = ~uint64_t(0), hostState = 0, lastUse = 0;
    std::vector<std::string> marks;
  };
  static constexpr size_t kMaxEntries = 8;  // settings a viewer toggles between

  void drop(Entry& e) {
    if (e.recorded) api_.destroy(e.exec);
    e.recorded = false;
  }
  void evict() {
    while (entries_.size() > kMaxEntries) {
      auto oldest = entries_.begin();
      for (auto it = entries_.begin(); it != entries_.end(); ++it)
        if (it->second.lastUse < oldest->second.lastUse) oldest = it;
      drop(oldest->second);
      entries_.erase(oldest);
    }
  }

  Api api_;
  std::map<std::string, Entry> entries_;
  uint64_t tick_ = 0;
};

}  // namespace rast
