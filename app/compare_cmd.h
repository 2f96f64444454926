// `rast compare REF.png TEST.png [--ids ref_ids.bin] [--json F]`: image quality
// of TEST against the reference REF (core/image_metrics.h defines the metrics),
// one line per metric on stdout and optionally as a JSON object (there
// psnr_linear_db is null for identical images: JSON has no infinity).
#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace rast {

struct CompareOptions {
  std::string reference, test;  // PNG files
  std::string ids;              // optional glref-ids file of the reference (edge mask)
  std::string json;             // optional output
  void addTo(CLI::App& app);
};

// Throws rast::Error for missing/unreadable files and size mismatches.
int runCompare(const CompareOptions& co);

}  // namespace rast
