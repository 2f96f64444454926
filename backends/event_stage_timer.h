// StageTimer for GPU backends: events recorded on the stream the kernels run
// on, read after the frame, so timing adds no host wait between stages. One
// implementation for every event API (CUDA, HIP): Api provides
//   using Event;  static Event create();  static void destroy(Event);
//   static void record(Event);  // on the execution space's stream
//   static void wait(Event);  static float elapsedMs(Event from, Event to);
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace rast {

template <class Api>
class EventStageTimer {
 public:
  EventStageTimer() = default;
  EventStageTimer(const EventStageTimer&) = delete;
  EventStageTimer& operator=(const EventStageTimer&) = delete;
  ~EventStageTimer() {
    for (typename Api::Event e : events_) Api::destroy(e);
  }

  void start() {
    used_ = 0;
    names_.clear();
    Api::record(next());
  }

  void mark(const char* stage) {
    names_.emplace_back(stage);
    Api::record(next());
  }

  void replayMark(const char* stage) {
    names_.emplace_back(stage);
    next();  // the replayed recording records this event
  }
  size_t marks() const { return names_.size(); }
  std::string markName(size_t i) const { return names_.at(i); }
  void rewind(size_t marks) {
    names_.resize(marks);
    used_ = marks + 1;  // the start event and one per mark
  }

  std::vector<std::pair<std::string, double>> finish() {
    std::vector<std::pair<std::string, double>> out;
    if (used_ == 0) return out;
    Api::wait(events_[used_ - 1]);
    for (size_t i = 0; i < names_.size(); ++i) out.emplace_back(names_[i], double(Api::elapsedMs(events_[i], events_[i + 1])));
    return out;
  }

 private:
  // Events are created once and reused frame after frame.
  typename Api::Event next() {
    if (used_ == events_.size()) events_.push_back(Api::create());
    return events_[used_++];
  }

  std::vector<typename Api::Event> events_;
  std::vector<std::string> names_;
  size_t used_ = 0;
};

}  // namespace rast
