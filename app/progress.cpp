#include "app/progress.h"

#include "base/error.h"
#include "host/image/safe_output.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <unistd.h>

namespace rast {
namespace {

double nowSeconds() {
  using namespace std::chrono;
  return duration<double>(steady_clock::now().time_since_epoch()).count();
}

}  // namespace

Progress::Progress(std::string what) : what_(std::move(what)), active_(isatty(STDERR_FILENO) == 1) {}

Progress::~Progress() {
  if (drawn_) std::fprintf(stderr, "\r\033[K");
}

void Progress::update(int done, int total) {
  if (!active_) return;
  const double t = nowSeconds();
  if (done < total && lastDraw_ >= 0.0 && t - lastDraw_ < 0.1) return;  // at most 10 redraws a second
  lastDraw_ = t;
  drawn_ = true;
  std::fprintf(stderr, "\r\033[K%s %d/%d (%d%%)", what_.c_str(), done, total, total > 0 ? 100 * done / total : 100);
  std::fflush(stderr);
}

void checkOutputPath(const std::string& path, const char* what) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (path.empty()) throw Error(std::string(what) + ": empty output path");
  const std::string shown = printable(path);
  const fs::path p(path);
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  if (!fs::is_directory(dir, ec))
    throw Error(std::string(what) + ": cannot write '" + shown + "': folder '" + printable(dir.string()) +
                "' does not exist");
  if (fs::is_directory(p, ec)) throw Error(std::string(what) + ": '" + shown + "' is a folder");
  const bool exists = fs::exists(p, ec);
  if (exists && access(path.c_str(), W_OK) != 0) throw Error(std::string(what) + ": '" + shown + "' is not writable");
  // A regular file is replaced by renaming a temporary file over it
  // (host/image/safe_output.h): its folder must be writable too.
  if ((!exists || fs::is_regular_file(p, ec)) && access(dir.c_str(), W_OK) != 0)
    throw Error(std::string(what) + ": cannot write '" + shown + "': its folder '" + printable(dir.string()) +
                "' is not writable");
}

}  // namespace rast
