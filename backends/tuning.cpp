#include "backends/tuning.h"

namespace rast {

uint32_t persistentThreads() {
  const uint32_t c = uint32_t(Exec().concurrency());
  // GPU: one resident thread per hardware slot. CPU: interleaved slices per
  // core keep the cores balanced.
  return kOnDevice ? c : c * 16;
}

uint32_t binBatchLimit() { return kOnDevice ? 1024u : uint32_t(Exec().concurrency()) * 8; }

}  // namespace rast
