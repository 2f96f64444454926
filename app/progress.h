// Progress of long runs (bench, reference renders) on stderr, shown only when
// stderr is a terminal: logs and pipes get no carriage-return noise.
#pragma once

#include <string>

namespace rast {

class Progress {
 public:
  explicit Progress(std::string what);
  ~Progress();  // clears the line it drew
  void update(int done, int total);
  bool active() const { return active_; }

 private:
  std::string what_;
  bool active_ = false, drawn_ = false;
  double lastDraw_ = -1.0;
};

// Throws Error (one line) when `path` cannot be written: a missing or
// unwritable folder, a folder in the way, a read-only file. Checked before
// rendering, so that a long render does not end in a failed write.
void checkOutputPath(const std::string& path, const char* what);

}  // namespace rast
