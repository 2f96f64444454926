// testHooks(): one instance per process (test_hooks.h says why they exist).
#include "pipeline/data/test_hooks.h"

namespace rast {

TestHooks& testHooks() {
  static TestHooks hooks;
  return hooks;
}

std::string TestHooks::key() const {
  const int32_t v[] = {gpuSetupOnHostTeam, hostSetupStaged, hostSetupStream, generalShade ? 1 : 0, rowLanes, shadeRun,
                     teamResolve ? 1 : 0, peelRows ? 1 : 0, chainEncode ? 1 : 0,
                     int32_t(listStride), keepFilm ? 1 : 0};
  return std::string(reinterpret_cast<const char*>(v), sizeof v);
}

}  // namespace rast
