// `rast bench`: warm-up frames, then the median over many frames of every
// stage and of the whole frame, as a table and as JSON/CSV rows.
#pragma once

#include "app/cli_options.h"

namespace rast {

struct BenchOptions {
  int frames = 100, warmup = 10;
  std::string json, csv;
  bool allMethods = false;
  bool distribute = false;  // under mpirun: sort-last over the ranks (docs/distributed.md)
  std::string methods;  // comma list of methods (auto allowed); overrides --raster
  void addTo(CLI::App& app);
};

int runBench(const SceneOptions& so, const BenchOptions& bo);

}  // namespace rast
