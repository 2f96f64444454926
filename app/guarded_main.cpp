#include "app/guarded_main.h"

#include "base/error.h"

#include <Kokkos_Core.hpp>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>
#include <string>
#include <thread>
#include <vector>

namespace rast {
namespace {

// Kokkos' OpenMP backend prints four lines of advice on stdout when OMP_PROC_BIND is
// unset. We set what the process already does: libgomp read its environment when it
// was loaded, before main, so an unset OMP_PROC_BIND has already meant "no binding",
// which is also the safe choice for a command-line tool sharing cores with other work.
// A user's own OMP_PROC_BIND / OMP_PLACES are kept (and honoured by libgomp).
bool g_bindDefault = false;

void setOpenMPDefaults() {
  if (std::getenv("OMP_PROC_BIND")) return;
  setenv("OMP_PROC_BIND", "false", 0);
  g_bindDefault = true;
}

bool isKokkosFlag(const char* a) { return std::strncmp(a, "--kokkos-", 9) == 0; }

// Kokkos 3.x takes its numbers with std::stoi and trusts them: a thread count
// of 0 or of more than the machine has ends in a segmentation fault inside its
// OpenMP backend, -1 in a five-line error. So every number rast passes on is
// checked here first, each with one line naming the flag and the valid range.
std::string printableArg(const std::string& s, size_t cap = 100) {
  std::string out = s.size() > cap ? s.substr(0, cap) + "..." : s;
  for (char& c : out)
    if ((unsigned char)c < 0x20 || c == 0x7f) c = '?';
  return out;
}

bool parseCount(const std::string& v, long lo, long hi, long* out) {
  if (v.empty() || v.size() > 9) return false;
  for (char c : v)
    if (c < '0' || c > '9') return false;
  *out = std::strtol(v.c_str(), nullptr, 10);
  return *out >= lo && *out <= hi;
}

long hardwareThreads() {
  const unsigned n = std::thread::hardware_concurrency();
  return n > 0 ? long(n) : 1;
}

// The last line of defence of "one line, always": whatever a message holds,
// it reaches stderr as one line of at most 1000 bytes, control characters as
// '?' and a data: URI's payload cut to its first 32 bytes.
std::string finalLine(const std::string& m) {
  std::string out;
  for (size_t i = 0; i < m.size(); ++i) {
    if (m.compare(i, 5, "data:") == 0) {
      size_t end = i;
      while (end < m.size() && m[end] != '\'' && m[end] != '"' && m[end] != ' ') ++end;
      if (end - i > 40) {
        out += m.substr(i, 32) + "...(a data: URI of " + std::to_string(end - i) + " bytes)";
        i = end - 1;
        continue;
      }
    }
    out += m[i];
  }
  return printableArg(out, 1000);
}

// "" when the flag is fine, else the reason (one line).
std::string checkKokkosFlag(const std::string& arg) {
  const long hw = hardwareThreads();
  const auto eq = arg.find('=');
  const std::string name = arg.substr(0, eq), value = eq == std::string::npos ? std::string() : arg.substr(eq + 1);
  const std::string threads = "from 1 to " + std::to_string(hw) + " (this machine's hardware threads)";
  long n = 0;
  if (name == "--kokkos-threads" || name == "--kokkos-num-threads" || name == "--kokkos-numa") {
    if (eq == std::string::npos) return name + " needs a value: " + name + "=N, N " + threads;
    if (!parseCount(value, 1, hw, &n)) return name + "=" + printableArg(value) + ": expected a count " + threads;
  } else if (name == "--kokkos-device-id" || name == "--kokkos-device" || name == "--kokkos-skip-device" ||
             name == "--kokkos-ndevices" || name == "--kokkos-num-devices") {
    if (eq == std::string::npos) return name + " needs a value: " + name + "=N";
    // --kokkos-ndevices=N[,M]: devices, then the device to skip.
    const auto comma = value.find(',');
    const bool pair = comma != std::string::npos && (name == "--kokkos-ndevices" || name == "--kokkos-num-devices");
    if (!parseCount(pair ? value.substr(0, comma) : value, 0, 4096, &n) ||
        (pair && !parseCount(value.substr(comma + 1), 0, 4096, &n)))
      return name + "=" + printableArg(value) + ": expected a device number from 0 to 4096";
  }
  return "";
}

// OMP_NUM_THREADS (read by libgomp and by Kokkos) and KOKKOS_NUM_THREADS, the
// same way: each entry of the list from 1 to the hardware threads.
std::string checkThreadEnvironment() {
  const long hw = hardwareThreads();
  for (const char* var : {"OMP_NUM_THREADS", "KOKKOS_NUM_THREADS"}) {
    const char* v = std::getenv(var);
    if (!v || !*v) continue;
    const std::string s(v);
    size_t start = 0;
    long n = 0;
    while (true) {
      const auto comma = s.find(',', start);
      const std::string item = s.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
      if (!parseCount(item, 1, hw, &n))
        return std::string(var) + "=" + printableArg(s) + ": expected thread counts from 1 to " + std::to_string(hw) +
               " (this machine's hardware threads)";
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
  }
  return "";
}

}  // namespace

bool openMPBindingIsDefault() { return g_bindDefault; }

int guardedMain(const char* program, int argc, char** argv, const std::function<int(int, char**)>& run) {
  setOpenMPDefaults();
  // Kokkos sees only its own --kokkos-* flags: given all of them, Kokkos 3.x also
  // answers unprefixed ones such as --help and --threads with its own text. Our
  // parser sees everything else, in order.
  std::vector<char*> kokkosArgs{argv[0]}, ownArgs{argv[0]};
  for (int i = 1; i < argc; ++i) (isKokkosFlag(argv[i]) ? kokkosArgs : ownArgs).push_back(argv[i]);
  int kargc = int(kokkosArgs.size());
  kokkosArgs.push_back(nullptr);
  std::string bad = checkThreadEnvironment();
  for (int i = 1; i < kargc && bad.empty(); ++i) bad = checkKokkosFlag(kokkosArgs[i]);
  if (!bad.empty()) {
    std::fprintf(stderr, "%s: error: %s\n", program, bad.c_str());
    return 2;
  }
  try {
    Kokkos::initialize(kargc, kokkosArgs.data());
  } catch (const std::exception& e) {
    // Kokkos 3.x parses numbers with std::stoi, whose message is just "stoi".
    std::fprintf(stderr, "%s: error: Kokkos could not start (%s): check the --kokkos-* flags\n", program,
                 finalLine(e.what()).c_str());
    return 2;
  }
  // Kokkos removes the flags it understood; any left over are not Kokkos' either.
  for (int i = 1; i < kargc; ++i) {
    std::fprintf(stderr, "%s: error: unknown Kokkos option '%s' (see --kokkos-help)\n", program,
                 printableArg(kokkosArgs[i]).c_str());
    Kokkos::finalize();
    return 2;
  }
  int rc = 1;
  const int oargc = int(ownArgs.size());
  ownArgs.push_back(nullptr);
  try {
    rc = run(oargc, ownArgs.data());
  } catch (const QuietFailure&) {
    rc = 1;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "%s: error: out of memory\n", program);
  } catch (const std::exception& e) {  // rast::Error and anything else
    std::fprintf(stderr, "%s: error: %s\n", program, finalLine(e.what()).c_str());
  }
  Kokkos::finalize();
  return rc;
}

}  // namespace rast
