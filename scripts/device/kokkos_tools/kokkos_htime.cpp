// A minimal Kokkos Tools library that writes down, without synchronising, the
// host's time at every Kokkos event (kernel launches, deep copies, fences,
// profile regions), and prints, on Kokkos::finalize, the events between the
// last two occurrences of a marker kernel (KOKKOS_HTIME_MARK, by default
// rast::api::inputs_in: one rast.rasterize call). Why: to see where a call's
// host time goes (launch calls, waits, and the gaps between them where the
// host does its own work), which the CUDA traces show only in part.
//   g++ -O2 -shared -fPIC -o kokkos_htime.so scripts/device/kokkos_tools/kokkos_htime.cpp
//   KOKKOS_TOOLS_LIBS=$PWD/kokkos_htime.so python3 ...
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {
using Clock = std::chrono::steady_clock;
struct Ev {
  double t;
  char kind;  // b/e: kernel begin/end, c/C: copy, f/F: fence, r/R: region
  std::string name;
};
std::vector<Ev>& log() {
  static std::vector<Ev> v;
  return v;
}
Clock::time_point t0 = Clock::now();
void add(char k, const char* n) {
  auto& v = log();
  if (v.size() > 2000000) return;
  v.push_back(Ev{std::chrono::duration<double, std::micro>(Clock::now() - t0).count(), k, n ? n : ""});
}
std::vector<std::string> kernelNames;
}  // namespace

extern "C" void kokkosp_finalize_library();
extern "C" {
void kokkosp_init_library(int, uint64_t, uint32_t, void*) {
  log().reserve(1 << 20);
  if (std::getenv("KOKKOS_HTIME_VERBOSE")) std::fprintf(stderr, "kokkos_htime: loaded\n");
  std::atexit([] {
    static bool done = false;
    if (!done) { done = true; kokkosp_finalize_library(); }
  });
}
void kokkosp_begin_parallel_for(const char* n, uint32_t, uint64_t* id) { add('b', n); *id = 0; }
void kokkosp_end_parallel_for(uint64_t) { add('e', ""); }
void kokkosp_begin_parallel_reduce(const char* n, uint32_t, uint64_t* id) { add('b', n); *id = 0; }
void kokkosp_end_parallel_reduce(uint64_t) { add('e', ""); }
void kokkosp_begin_parallel_scan(const char* n, uint32_t, uint64_t* id) { add('b', n); *id = 0; }
void kokkosp_end_parallel_scan(uint64_t) { add('e', ""); }
void kokkosp_begin_fence(const char* n, uint32_t, uint64_t* id) { add('f', n); *id = 0; }
void kokkosp_end_fence(uint64_t) { add('F', ""); }
// Kokkos 4 fences around every event for a tool unless it says it needs none;
// those fences would change what is measured (and break frame recording).
struct ToolSettings {
  bool requires_global_fencing;
  bool padding[255];
};
void kokkosp_request_tool_settings(const uint32_t, ToolSettings* s) { s->requires_global_fencing = false; }
struct SpaceHandle {
  char name[64];
};
void kokkosp_begin_deep_copy(SpaceHandle, const char* dn, const void*, SpaceHandle, const char* sn, const void*, uint64_t b) {
  add('c', (std::string(sn) + " -> " + dn + " " + std::to_string(b) + " B").c_str());
}
void kokkosp_end_deep_copy() { add('C', ""); }
void kokkosp_push_profile_region(const char* n) { add('r', n); }
void kokkosp_pop_profile_region() { add('R', ""); }
void kokkosp_finalize_library() {
  static bool printed = false;
  if (printed) return;
  printed = true;
  const char* m = std::getenv("KOKKOS_HTIME_MARK");
  const std::string mark = m ? m : "rast::api::inputs_in";
  auto& v = log();
  std::vector<size_t> at;
  for (size_t i = 0; i < v.size(); ++i)
    if ((v[i].kind == 'b' || v[i].kind == 'r') && v[i].name == mark) at.push_back(i);
  if (at.size() < 3) {
    std::fprintf(stderr, "kokkos_htime: fewer than 3 '%s' launches\n", mark.c_str());
    return;
  }
  // Median call length over the last half, then the last full call listed.
  std::vector<double> d;
  for (size_t k = at.size() / 2; k + 1 < at.size(); ++k) d.push_back(v[at[k + 1]].t - v[at[k]].t);
  std::sort(d.begin(), d.end());
  std::fprintf(stderr, "kokkos_htime: %zu calls; median host time from one '%s' to the next %.1f us\n", at.size(),
               mark.c_str(), d[d.size() / 2]);
  const size_t a = at[at.size() - 2], b = at[at.size() - 1];
  const double base = v[a].t;
  std::fprintf(stderr, "  (the listed call starts at steady_clock %.1f us)\n",
               std::chrono::duration<double, std::micro>(t0.time_since_epoch()).count() + base);
  for (size_t i = a; i <= b; ++i)
    std::fprintf(stderr, "  %8.1f  %c %s\n", v[i].t - base, v[i].kind, v[i].name.c_str());
}
}
