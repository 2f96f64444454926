// rast ssao-error: SSAO's error against a ray-traced ambient-occlusion
// reference (core/ao_reference.h) and its cost, for a list of sample counts;
// the data of the speed-versus-accuracy chart in docs/post.md.
#pragma once

#include "app/cli_options.h"

#include <string>

namespace rast {

struct SsaoErrorOptions {
  std::string samples = "4,8,16,32,64";
  std::string errorSize = "480x270";  // the error is measured at this size, the time at --size
  int rays = 256;                     // reference rays per pixel
  int frames = 20, warmup = 3;
  std::string csv;
  std::string referenceOut;  // optional: the reference AO as a PFM
  void addTo(CLI::App& app);
};

int runSsaoError(const SceneOptions& so, const SsaoErrorOptions& o);

}  // namespace rast
