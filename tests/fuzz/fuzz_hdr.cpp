// libFuzzer harness for the Radiance .hdr reader (host/image/hdr_image.h), the
// one other file format rast reads from strangers (--env FILE);
// scripts/fuzz/fuzz_hdr.sh builds and runs it. A rast::Error is the expected
// outcome of bad input; a crash, a sanitizer report, another exception, a hang
// or memory past -rss_limit_mb is a finding. The budget is small (64 MiB) so
// that the ledger, not libFuzzer's RSS limit, stops inputs claiming huge sizes.
#include "host/image/hdr_image.h"

#include <cstdint>
#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  rast::MemoryLedger ledger(uint64_t(64) << 20);
  try {
    const rast::HdrImage img = rast::decodeHdr(data, size, "fuzz.hdr", ledger);
    if (img.rgb.size() != size_t(img.width) * size_t(img.height) * 3 || ledger.used() != img.bytes()) std::abort();
  } catch (const rast::Error&) {
  }
  return 0;
}
