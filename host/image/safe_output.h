// Writing outputs without ever losing the user's data (docs/security.md,
// "Outputs"): an output is refused when it is one of the run's inputs (the
// scene file, a file the scene reads) or another output of the same run, by
// realpath and by device and inode, so `rast render duck.glb -o duck.glb`, an
// output through a symlink or hard link to an input, and two outputs naming
// one file fail before anything is written. And every output is written to a
// temporary file in the same folder, flushed to disk and renamed over the
// path only when complete: a failed write, a full disk, a file size limit or
// a signal leaves the file that was at the path as it was, never a partial one.
#pragma once

#include "base/error.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace rast {

// The outputs of one run, checked against its inputs and each other.
class OutputSet {
 public:
  // A file the run reads (missing files are ignored: nothing to protect).
  void addInput(const std::string& path, const std::string& role);
  // An output; `what` names its flag ("-o", "--aov depth").
  void addOutput(const std::string& path, const std::string& what);
  // Throws Error (one line) when an output is an input or another output.
  void check() const;

 private:
  struct Entry {
    std::string path, what, key;  // key: the resolved path ("" when unresolvable)
    bool exists = false;
    uint64_t dev = 0, ino = 0;
  };
  static Entry entry(const std::string& path, const std::string& what);
  std::vector<Entry> inputs_, outputs_;
};

// A file written atomically. The bytes go to a temporary file beside the
// target (".NAME.rast-XXXXXX"); commit() flushes it to disk and renames it
// over the target. Not committed (an error, an exception, a signal: SIGINT,
// SIGTERM, SIGHUP, SIGXFSZ, SIGPIPE remove it first), the temporary file is
// removed and the target is untouched. A symlink is followed (its target is
// replaced, the link kept); an existing file keeps its permission bits. An
// existing path that is not a regular file (/dev/null, a FIFO) is written
// directly, as there is nothing to replace.
class AtomicFile {
 public:
  explicit AtomicFile(const std::string& path);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile();

  void write(const void* p, size_t n);
  void write(const std::string& s) { write(s.data(), s.size()); }
  // Flushes, syncs and renames into place. Throws Error on failure (the
  // target then keeps its old content).
  void commit();
  const std::string& path() const { return path_; }

 private:
  [[noreturn]] void fail(const std::string& doing, int err);
  void discard();
  void flushBuffer();

  std::string path_;    // as given, for messages
  std::string target_;  // what rename() replaces (a symlink followed)
  std::string temp_;    // "" when writing directly
  int fd_ = -1;
  int slot_ = -1;       // in the signal handler's table of temporary files
  std::vector<unsigned char> buf_;
};

// The whole of `bytes` to `path`, atomically.
void writeFileAtomically(const std::string& path, const void* bytes, size_t n);

}  // namespace rast
