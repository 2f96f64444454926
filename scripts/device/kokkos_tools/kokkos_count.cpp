// A minimal Kokkos Tools library that counts kernel launches (parallel_for /
// reduce / scan), deep copies and fences by name, and prints the table on
// Kokkos::finalize. Build with any host compiler (it has no Kokkos dependency):
//   g++ -O2 -shared -fPIC -o kokkos_count.so scripts/device/kokkos_tools/kokkos_count.cpp
// Use: KOKKOS_TOOLS_LIBS=$PWD/kokkos_count.so rast bench --frames 10 --warmup 0
// (per-frame kernels then appear frames + max(warmup, 1) times).
#include <cstdint>
#include <cstdio>
#include <map>
#include <mutex>
#include <string>
#include <vector>
#include <algorithm>

namespace {
struct Counts {
  std::map<std::string, uint64_t> kernels, copies, fences;
  std::mutex m;
};
Counts& counts() {
  static Counts c;
  return c;
}
void bump(std::map<std::string, uint64_t>& map, const char* name) {
  std::lock_guard<std::mutex> g(counts().m);
  ++map[name ? name : "(null)"];
}
void dump(const char* what, const std::map<std::string, uint64_t>& map) {
  std::vector<std::pair<std::string, uint64_t>> v(map.begin(), map.end());
  std::sort(v.begin(), v.end(), [](auto& a, auto& b) { return a.second != b.second ? a.second > b.second : a.first < b.first; });
  uint64_t total = 0;
  for (auto& p : v) total += p.second;
  std::fprintf(stderr, "kokkos_count: %s: %llu in total\n", what, (unsigned long long)total);
  for (auto& p : v) std::fprintf(stderr, "kokkos_count:   %8llu  %s\n", (unsigned long long)p.second, p.first.c_str());
}
}  // namespace

struct Kokkos_Tools_SpaceHandle { char name[64]; };

extern "C" {
void kokkosp_init_library(int, uint64_t, uint32_t, void*) {}
void kokkosp_finalize_library() {
  dump("kernels (parallel_for/reduce/scan)", counts().kernels);
  dump("deep copies", counts().copies);
  dump("fences", counts().fences);
}
void kokkosp_begin_parallel_for(const char* name, uint32_t, uint64_t* id) { *id = 0; bump(counts().kernels, name); }
void kokkosp_end_parallel_for(uint64_t) {}
void kokkosp_begin_parallel_reduce(const char* name, uint32_t, uint64_t* id) { *id = 0; bump(counts().kernels, name); }
void kokkosp_end_parallel_reduce(uint64_t) {}
void kokkosp_begin_parallel_scan(const char* name, uint32_t, uint64_t* id) { *id = 0; bump(counts().kernels, name); }
void kokkosp_end_parallel_scan(uint64_t) {}
void kokkosp_begin_deep_copy(Kokkos_Tools_SpaceHandle dst, const char* dst_name, const void*, Kokkos_Tools_SpaceHandle src,
                             const char* src_name, const void*, uint64_t) {
  std::string n = std::string(src.name) + "->" + dst.name + " " + (dst_name ? dst_name : "") + " <- " + (src_name ? src_name : "");
  bump(counts().copies, n.c_str());
}
void kokkosp_end_deep_copy() {}
void kokkosp_begin_fence(const char* name, uint32_t, uint64_t* id) { *id = 0; bump(counts().fences, name); }
void kokkosp_end_fence(uint64_t) {}
}
