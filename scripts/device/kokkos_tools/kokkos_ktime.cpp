// A minimal Kokkos Tools library that times every kernel by name: it
// synchronises the device (driver API, cuCtxSynchronize, looked up at run time)
// before and after each parallel_for / reduce / scan and prints the median and
// count per name on Kokkos::finalize. The synchronisation removes overlap
// between kernels, so the sum is an upper bound on a real frame; use it to see
// which kernel of a stage dominates, not for frame times.
//   g++ -O2 -shared -fPIC -o kokkos_ktime.so scripts/device/kokkos_tools/kokkos_ktime.cpp -ldl
//   KOKKOS_TOOLS_LIBS=$PWD/kokkos_ktime.so rast bench SCENE --frames 100
#include <dlfcn.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

namespace {
using Clock = std::chrono::steady_clock;
int (*ctxSync)() = nullptr;
void sync() {
  if (ctxSync) ctxSync();
}
std::map<std::string, std::vector<double>>& table() {
  static std::map<std::string, std::vector<double>> t;
  return t;
}
std::vector<std::pair<std::string, Clock::time_point>>& open() {
  static std::vector<std::pair<std::string, Clock::time_point>> o;
  return o;
}
void begin(const char* name, uint64_t* id) {
  sync();
  *id = open().size();
  open().push_back({name ? name : "(null)", Clock::now()});
}
void end(uint64_t id) {
  sync();
  const auto t = Clock::now();
  if (id >= open().size()) return;
  auto e = open()[id];
  open().resize(id);
  table()[e.first].push_back(std::chrono::duration<double, std::micro>(t - e.second).count());
}
}  // namespace

extern "C" {
void kokkosp_init_library(int, uint64_t, uint32_t, void*) {
  if (void* h = dlopen("libcuda.so.1", RTLD_NOW | RTLD_GLOBAL)) ctxSync = (int (*)())dlsym(h, "cuCtxSynchronize");
  std::fprintf(stderr, "kokkos_ktime: %s\n", ctxSync ? "timing with cuCtxSynchronize" : "no libcuda: host times only");
}
void kokkosp_finalize_library() {
  std::fprintf(stderr, "kokkos_ktime: %10s %10s %8s  %s\n", "median_us", "min_us", "count", "kernel");
  for (auto& [name, v] : table()) {
    std::sort(v.begin(), v.end());
    std::fprintf(stderr, "kokkos_ktime: %10.2f %10.2f %8zu  %s\n", v[v.size() / 2], v.front(), v.size(), name.c_str());
  }
}
void kokkosp_begin_parallel_for(const char* n, uint32_t, uint64_t* id) { begin(n, id); }
void kokkosp_end_parallel_for(uint64_t id) { end(id); }
void kokkosp_begin_parallel_reduce(const char* n, uint32_t, uint64_t* id) { begin(n, id); }
void kokkosp_end_parallel_reduce(uint64_t id) { end(id); }
void kokkosp_begin_parallel_scan(const char* n, uint32_t, uint64_t* id) { begin(n, id); }
void kokkosp_end_parallel_scan(uint64_t id) { end(id); }
}
