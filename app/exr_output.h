// OpenEXR output of the CLI (docs/first-run.md, `-o frame.exr`, `--aov
// depth=frame.exr`): compositing and film tools read multi-channel EXR, not
// PFM, so a frame's linear colour and its AOVs go into one file as named
// channels. Written with Debian's OpenEXR (libopenexr-dev) into memory, then
// through AtomicFile like every other output, so a failed run leaves the old
// file. Only the CLI links OpenEXR: the library (rast::rast) stays free of it.
#pragma once

#include "host/image/safe_output.h"

#include <cstdint>
#include <string>
#include <vector>

namespace rast {

bool isExrPath(const std::string& path);

// Channels gathered for one EXR file; rows are given bottom first (the
// frame's order) and written top first (EXR's).
class ExrImage {
 public:
  ExrImage(int width, int height) : width_(width), height_(height) {}
  void addFloat(const std::string& name, const float* bottomUp, int stride = 1, int offset = 0);
  void addUint(const std::string& name, const uint32_t* bottomUp);
  bool empty() const { return channels_.empty(); }
  // ZIP-compressed scanlines (lossless); throws Error when OpenEXR fails.
  void write(AtomicFile& file) const;

 private:
  struct Channel {
    std::string name;
    bool isUint = false;
    std::vector<uint32_t> bits;  // top row first; floats stored by their bits
  };
  int width_, height_;
  std::vector<Channel> channels_;
};

}  // namespace rast
