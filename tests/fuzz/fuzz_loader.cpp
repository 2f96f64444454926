// libFuzzer harness for the glTF/GLB loader (scripts/fuzz/fuzz_loader.sh builds and
// runs it; docs/security.md records the campaigns).
//
// Each input is written to a file in a private folder and loaded with
// loadGltf, as `rast render FILE` would. A rast::Error is the expected outcome
// of bad input; anything else (a crash, a sanitizer report, another exception,
// a leak, a hang past -timeout, memory past -rss_limit_mb) is a finding.
// The memory budget is small so that the budget, not libFuzzer's RSS limit,
// is what stops inputs claiming huge sizes.
#include "host/gltf/gltf_loader.h"

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

namespace {

std::string scenePath() {
  static std::string path = [] {
    char tmpl[] = "/tmp/rast_fuzz_XXXXXX";
    const char* dir = ::mkdtemp(tmpl);
    if (!dir) std::abort();
    // An image and a buffer the inputs may name (found by the dictionary's
    // "a.png" / "a.bin"), so that the external-file paths are exercised too.
    std::ofstream(std::string(dir) + "/a.bin", std::ios::binary) << std::string(64, '\0');
    static const unsigned char png[] = {  // 1x1 RGBA (tests/support/adversarial.py's _png(1, 1))
        0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52, 0x00,
        0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x08, 0x06, 0x00, 0x00, 0x00, 0x1f, 0x15, 0xc4, 0x89, 0x00,
        0x00, 0x00, 0x0b, 0x49, 0x44, 0x41, 0x54, 0x78, 0xda, 0x63, 0x60, 0x00, 0x02, 0x00, 0x00, 0x05, 0x00,
        0x01, 0xe9, 0xfa, 0xdc, 0xd8, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};
    std::ofstream(std::string(dir) + "/a.png", std::ios::binary).write(reinterpret_cast<const char*>(png), sizeof png);
    return std::string(dir) + "/scene.gltf";
  }();
  return path;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = scenePath();
  {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  }
  rast::LoadOptions options;
  options.maxMemory = 256u << 20;
  try {
    const rast::Scene s = rast::loadGltf(path, options);
    (void)s.triangleCount();
  } catch (const rast::Error& e) {
    // Expected for bad input; the message must be one line.
    for (const char* c = e.what(); *c; ++c)
      if (*c == '\n') {
        std::fprintf(stderr, "multi-line error message: %s\n", e.what());
        std::abort();
      }
  }
  return 0;
}
