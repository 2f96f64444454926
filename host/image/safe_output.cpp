#include "host/image/safe_output.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <climits>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <random>

namespace rast {
namespace {

std::string realPath(const std::string& p) {
  char buf[PATH_MAX];
  return ::realpath(p.c_str(), buf) ? std::string(buf) : std::string();
}

std::string folderOf(const std::string& p) {
  const auto slash = p.find_last_of('/');
  return slash == std::string::npos ? std::string(".") : slash == 0 ? std::string("/") : p.substr(0, slash);
}

std::string baseOf(const std::string& p) {
  const auto slash = p.find_last_of('/');
  return slash == std::string::npos ? p : p.substr(slash + 1);
}

// ---------------------------------------------------------------- temporary files removed on a fatal signal

// The signal handler may only call async-signal-safe functions: it unlinks the
// paths of this fixed table, then lets the signal do what it would have done.
constexpr int kSlots = 16;
char g_tempPath[kSlots][PATH_MAX];
std::atomic<int> g_tempUsed[kSlots];
std::atomic<bool> g_handlersInstalled{false};
constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP, SIGXFSZ, SIGPIPE, SIGQUIT};

extern "C" void removeTempsAndDie(int sig) {
  for (int i = 0; i < kSlots; ++i)
    if (g_tempUsed[i].load() == 2) ::unlink(g_tempPath[i]);
  ::signal(sig, SIG_DFL);
  ::raise(sig);
}

void installHandlers() {
  if (g_handlersInstalled.exchange(true)) return;
  for (int sig : kSignals) {
    struct sigaction old;
    if (::sigaction(sig, nullptr, &old) != 0) continue;
    // An ignored signal stays ignored (a write past `ulimit -f` then fails
    // with EFBIG and is reported); a handler someone else installed is kept.
    if (!(old.sa_flags & SA_SIGINFO) && old.sa_handler == SIG_DFL) {
      struct sigaction sa;
      std::memset(&sa, 0, sizeof sa);
      sa.sa_handler = removeTempsAndDie;
      sigemptyset(&sa.sa_mask);
      ::sigaction(sig, &sa, nullptr);
    }
  }
}

int claimSlot(const std::string& path) {
  if (path.size() >= PATH_MAX) return -1;
  for (int i = 0; i < kSlots; ++i) {
    int expected = 0;  // 0 free, 1 being filled, 2 a path the handler removes
    if (g_tempUsed[i].compare_exchange_strong(expected, 1)) {
      std::memcpy(g_tempPath[i], path.c_str(), path.size() + 1);
      g_tempUsed[i].store(2);
      return i;
    }
  }
  return -1;  // more than kSlots at once: still atomic, only not removed on a signal
}

void releaseSlot(int slot) {
  if (slot >= 0) g_tempUsed[slot].store(0);
}

}  // namespace

// ---------------------------------------------------------------- OutputSet

OutputSet::Entry OutputSet::entry(const std::string& path, const std::string& what) {
  Entry e;
  e.path = path;
  e.what = what;
  struct stat st;
  if (::stat(path.c_str(), &st) == 0) {
    e.exists = true;
    e.dev = uint64_t(st.st_dev);
    e.ino = uint64_t(st.st_ino);
    e.key = realPath(path);
  } else {
    const std::string dir = realPath(folderOf(path));
    if (!dir.empty()) e.key = (dir == "/" ? dir : dir + "/") + baseOf(path);
  }
  return e;
}

void OutputSet::addInput(const std::string& path, const std::string& role) {
  Entry e = entry(path, role);
  if (e.exists) inputs_.push_back(std::move(e));
}

void OutputSet::addOutput(const std::string& path, const std::string& what) { outputs_.push_back(entry(path, what)); }

void OutputSet::check() const {
  const auto same = [](const Entry& a, const Entry& b) {
    return (a.exists && b.exists && a.dev == b.dev && a.ino == b.ino) || (!a.key.empty() && a.key == b.key);
  };
  for (size_t k = 0; k < outputs_.size(); ++k) {
    const Entry& o = outputs_[k];
    for (const Entry& in : inputs_)
      if (same(o, in))
        throw Error(o.what + ": '" + printable(o.path) + "' is " + in.what + " '" + printable(in.path) +
                    "' (same file): refusing to write over an input");
    for (size_t j = 0; j < k; ++j)
      if (same(o, outputs_[j]))
        throw Error(o.what + ": '" + printable(o.path) + "' is the same file as the output of " + outputs_[j].what +
                    " ('" + printable(outputs_[j].path) + "'): each output needs a file of its own");
  }
}

// ---------------------------------------------------------------- AtomicFile

AtomicFile::AtomicFile(const std::string& path) : path_(path), target_(path) {
  if (path.empty()) throw Error("cannot write an empty output path");
  struct stat lst, st;
  if (::lstat(path.c_str(), &lst) == 0 && S_ISLNK(lst.st_mode)) {
    const std::string resolved = realPath(path);
    if (!resolved.empty()) target_ = resolved;  // the link's target is replaced, the link kept
  }
  const bool exists = ::stat(target_.c_str(), &st) == 0;
  buf_.reserve(size_t(1) << 20);
  if (exists && !S_ISREG(st.st_mode)) {  // a device or FIFO: nothing to replace, write through
    fd_ = ::open(target_.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
    if (fd_ < 0) fail("cannot open", errno);
    return;
  }
  installHandlers();
  const std::string dir = folderOf(target_), base = baseOf(target_);
  const std::string stem = (dir == "/" ? dir : dir + "/") + "." + (base.size() > 200 ? base.substr(0, 200) : base);
  std::random_device rd;
  static const char kAlnum[] = "abcdefghijklmnopqrstuvwxyz0123456789";
  for (int attempt = 0; attempt < 100 && fd_ < 0; ++attempt) {
    std::string name = stem + ".rast-";
    for (int i = 0; i < 8; ++i) name += kAlnum[rd() % 36];
    const int slot = claimSlot(name);  // claimed before the file exists: a signal removes it
    const int fd = ::open(name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) {
      fd_ = fd;
      temp_ = name;
      slot_ = slot;
    } else {
      const int err = errno;
      releaseSlot(slot);
      if (err != EEXIST)
        throw Error("cannot write '" + printable(path_) + "': cannot create a temporary file in its folder '" +
                    printable(dir) + "': " + std::strerror(err));
    }
  }
  if (fd_ < 0) throw Error("cannot write '" + printable(path_) + "': no free temporary file name in its folder");
  if (exists) (void)::fchmod(fd_, st.st_mode & 07777);  // the replaced file's permissions, not umask's
}

AtomicFile::~AtomicFile() {
  if (fd_ >= 0) discard();
}

void AtomicFile::discard() {
  ::close(fd_);
  fd_ = -1;
  if (!temp_.empty()) ::unlink(temp_.c_str());
  releaseSlot(slot_);
  slot_ = -1;
}

void AtomicFile::fail(const std::string& doing, int err) {
  if (fd_ >= 0) discard();
  throw Error(doing + " '" + printable(path_) + "': " + std::strerror(err));
}

void AtomicFile::flushBuffer() {
  size_t done = 0;
  while (done < buf_.size()) {
    const ssize_t n = ::write(fd_, buf_.data() + done, buf_.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail("cannot write", n < 0 ? errno : ENOSPC);
    done += size_t(n);
  }
  buf_.clear();
}

void AtomicFile::write(const void* p, size_t n) {
  if (fd_ < 0) throw Error("cannot write '" + printable(path_) + "': already closed");
  const auto* c = static_cast<const unsigned char*>(p);
  while (n > 0) {
    const size_t room = buf_.capacity() > buf_.size() ? buf_.capacity() - buf_.size() : 0;
    if (room == 0) {
      flushBuffer();
      continue;
    }
    const size_t k = n < room ? n : room;
    buf_.insert(buf_.end(), c, c + k);
    c += k;
    n -= k;
  }
}

void AtomicFile::commit() {
  if (fd_ < 0) throw Error("cannot write '" + printable(path_) + "': already closed");
  flushBuffer();
  if (temp_.empty()) {  // written through to a device or FIFO
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0) throw Error("cannot write '" + printable(path_) + "': " + std::strerror(errno));
    return;
  }
  // The data reaches the disk before the rename makes it the file at the path.
  if (::fsync(fd_) != 0 && errno != EINVAL && errno != EROFS) fail("cannot write", errno);
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) {
    const int err = errno;
    ::unlink(temp_.c_str());
    releaseSlot(slot_);
    throw Error("cannot write '" + printable(path_) + "': " + std::strerror(err));
  }
  if (::rename(temp_.c_str(), target_.c_str()) != 0) {
    const int err = errno;
    ::unlink(temp_.c_str());
    releaseSlot(slot_);
    throw Error("cannot write '" + printable(path_) + "': cannot rename the finished file into place: " +
                std::strerror(err));
  }
  releaseSlot(slot_);
  slot_ = -1;
  const int dfd = ::open(folderOf(target_).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {  // the rename itself on disk (best effort)
    (void)::fsync(dfd);
    ::close(dfd);
  }
}

void writeFileAtomically(const std::string& path, const void* bytes, size_t n) {
  AtomicFile f(path);
  f.write(bytes, n);
  f.commit();
}

}  // namespace rast
