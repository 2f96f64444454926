// Environment images for image-based light (docs/lighting.md): an
// equirectangular Radiance .hdr read into linear float RGB, and the built-in
// neutral environment used when the user gives none. A .hdr comes from
// strangers like a glTF file does: it is checked before anything is allocated
// (its size against kMaxHdrSide / kMaxHdrPixels and the memory budget), and
// a file that is not one, is cut short or is absurdly large is refused with
// one line (rast::Error).
#pragma once

#include "host/scene/memory_budget.h"

#include <cstdint>
#include <string>
#include <vector>

namespace rast {

// An equirectangular (latitude-longitude) image in linear light: row 0 is the
// zenith, the last row the nadir; column 0 is the direction the Khronos Sample
// Renderer maps to u = 0 (docs/lighting.md gives the mapping).
struct HdrImage {
  int width = 0, height = 0;
  std::vector<float> rgb;  // width * height * 3, row 0 first
  std::string name;        // the file's name as given, or the built-in's name
  uint64_t bytes() const { return uint64_t(rgb.size()) * sizeof(float); }
};

// Caps on a .hdr's size, checked from its header before decoding: 16384 texels
// a side (16K panoramas, 16384x8192, are the largest in common use) and
// 2^27 texels in all (16384x8192: 1.5 GiB as float RGB), whatever the budget.
constexpr int kMaxHdrSide = 16384;
constexpr uint64_t kMaxHdrPixels = uint64_t(1) << 27;

// Decodes Radiance RGBE ("#?RADIANCE" or "#?RGBE", FORMAT=32-bit_rle_rgbe,
// resolution "-Y H +X W": the orientation every panorama uses), flat or
// run-length encoded scanlines. `name` is used in messages only. The decoded
// floats are charged to `ledger` before they are allocated.
// Throws rast::Error with one line naming the file and what is wrong.
HdrImage decodeHdr(const uint8_t* bytes, size_t size, const std::string& name, MemoryLedger& ledger);

// Reads and decodes a file (its bytes are charged too).
HdrImage readHdr(const std::string& path, MemoryLedger& ledger);

// The built-in neutral environment, "neutral-studio": a grey studio dome made
// from a formula (docs/lighting.md): a sky brightening from zenith to horizon,
// a darker floor, and one soft key light high in front and to the right.
// Small (256x128) so that it costs nearly nothing to filter.
constexpr const char* kNeutralEnvironmentName = "neutral-studio";
HdrImage neutralEnvironment();

}  // namespace rast
