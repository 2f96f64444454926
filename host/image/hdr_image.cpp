// Radiance .hdr decoding (written here rather than through stb_image's
// stbi_loadf, which fills a cut-short file with zeros instead of failing) and
// the built-in neutral environment.
#include "host/image/hdr_image.h"

#include "base/error.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sys/stat.h>

namespace rast {

namespace {

constexpr size_t kMaxHeaderBytes = 64 * 1024;

[[noreturn]] void refuse(const std::string& name, const std::string& why) {
  throw Error("environment '" + printable(name) + "': " + why);
}

// One header line (without its '\n') starting at `pos`; false at the end of the data.
bool headerLine(const uint8_t* b, size_t n, size_t& pos, std::string& line) {
  line.clear();
  while (pos < n && pos < kMaxHeaderBytes) {
    const char c = char(b[pos++]);
    if (c == '\n') {
      if (!line.empty() && line.back() == '\r') line.pop_back();  // CRLF headers
      return true;
    }
    line.push_back(c);
  }
  return false;
}

float rgbeComponent(uint8_t c, uint8_t e) { return e == 0 ? 0.0f : std::ldexp(float(c), int(e) - (128 + 8)); }

}  // namespace

HdrImage decodeHdr(const uint8_t* b, size_t n, const std::string& name, MemoryLedger& ledger) {
  if (n == 0) refuse(name, "is empty (0 bytes), not a Radiance .hdr image");
  if (n < 2 || b[0] != '#' || b[1] != '?')
    refuse(name, "is not a Radiance .hdr image (it does not start with #?RADIANCE)");
  size_t pos = 0;
  std::string line;
  // Header: lines of VAR=value up to an empty line. EXPOSURE and the others
  // are ignored, as the Khronos Sample Renderer ignores them.
  headerLine(b, n, pos, line);
  for (;;) {
    if (!headerLine(b, n, pos, line))
      refuse(name, pos >= kMaxHeaderBytes ? "header is longer than 64 KiB (not a Radiance .hdr image?)"
                                         : "ends inside its header (truncated)");
    if (line.empty()) break;
    if (line.compare(0, 7, "FORMAT=") == 0 && line != "FORMAT=32-bit_rle_rgbe")
      refuse(name, "has pixel format '" + printable(line.substr(7), 40) + "'; only 32-bit_rle_rgbe is read");
  }
  if (!headerLine(b, n, pos, line)) refuse(name, "ends before its resolution line (truncated)");
  int w = 0, h = 0;
  char tail = 0;
  long long hw = 0, hh = 0;
  if (std::sscanf(line.c_str(), "-Y %lld +X %lld%c", &hh, &hw, &tail) != 2)
    refuse(name, "has resolution line '" + printable(line, 40) +
                     "'; only '-Y height +X width' (rows from the top, the panorama layout) is read");
  if (hw < 1 || hh < 1 || hw > kMaxHdrSide || hh > kMaxHdrSide || uint64_t(hw) * uint64_t(hh) > kMaxHdrPixels)
    refuse(name, "is " + std::to_string(hw) + "x" + std::to_string(hh) + " texels; at most " +
                     std::to_string(kMaxHdrSide) + " a side and " + std::to_string(kMaxHdrPixels) +
                     " in all are read");
  w = int(hw);
  h = int(hh);
  const uint64_t texels = uint64_t(w) * uint64_t(h);
  const std::string what = "environment '" + printable(name) + "' (" + std::to_string(w) + "x" +
                           std::to_string(h) + " texels, decoded)";
  ledger.charge(what, mulSat(texels, 3 * sizeof(float)));

  HdrImage img;
  img.width = w;
  img.height = h;
  img.name = name;
  img.rgb.resize(size_t(texels) * 3);
  std::vector<uint8_t> scan(size_t(w) * 4);
  for (int y = 0; y < h; ++y) {
    const std::string cut = "ends after " + std::to_string(y) + " of its " + std::to_string(h) + " rows (truncated)";
    const bool rle = w >= 8 && w < 32768 && pos + 4 <= n && b[pos] == 2 && b[pos + 1] == 2 &&
                     ((int(b[pos + 2]) << 8) | b[pos + 3]) == w;
    if (rle) {
      pos += 4;
      // Four planes (R, G, B, E), each as runs (count > 128: one byte
      // repeated count - 128 times) and literals (count bytes).
      for (int c = 0; c < 4; ++c) {
        int x = 0;
        while (x < w) {
          if (pos >= n) refuse(name, cut);
          int count = b[pos++];
          if (count > 128) {
            count -= 128;
            if (pos >= n) refuse(name, cut);
            if (count > w - x) refuse(name, "row " + std::to_string(y) + " has a run past its end (corrupt)");
            const uint8_t v = b[pos++];
            for (int k = 0; k < count; ++k) scan[size_t(x++) * 4 + c] = v;
          } else {
            if (count == 0 || count > w - x)
              refuse(name, "row " + std::to_string(y) + " has a bad run length (corrupt)");
            if (n - pos < size_t(count)) refuse(name, cut);
            for (int k = 0; k < count; ++k) scan[size_t(x++) * 4 + c] = b[pos++];
          }
        }
      }
    } else {
      // Flat RGBE pixels (as the reference reads any row not marked 2,2,w).
      if (n - pos < scan.size()) refuse(name, cut);
      std::memcpy(scan.data(), b + pos, scan.size());
      pos += scan.size();
    }
    float* out = img.rgb.data() + size_t(y) * size_t(w) * 3;
    for (int x = 0; x < w; ++x) {
      const uint8_t* p = &scan[size_t(x) * 4];
      out[3 * x + 0] = rgbeComponent(p[0], p[3]);
      out[3 * x + 1] = rgbeComponent(p[1], p[3]);
      out[3 * x + 2] = rgbeComponent(p[2], p[3]);
    }
  }
  return img;
}

HdrImage readHdr(const std::string& path, MemoryLedger& ledger) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw Error("cannot read environment '" + printable(path) + "': " + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) throw Error("environment '" + printable(path) + "' is not a regular file");
  // No valid file is larger than its flat pixels and a header.
  const uint64_t cap = kMaxHdrPixels * 4 + kMaxHeaderBytes;
  if (uint64_t(st.st_size) > cap)
    refuse(path, "is " + formatBytes(uint64_t(st.st_size)) + ", more than any .hdr of at most " +
                     std::to_string(kMaxHdrPixels) + " texels can be");
  const std::string what = "environment file '" + printable(path) + "'";
  ledger.charge(what, uint64_t(st.st_size));
  std::vector<uint8_t> bytes(size_t(st.st_size));
  FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw Error("cannot read environment '" + printable(path) + "': " + std::strerror(errno));
  const size_t got = bytes.empty() ? 0 : std::fread(bytes.data(), 1, bytes.size(), f);
  std::fclose(f);
  if (got != bytes.size()) throw Error("cannot read environment '" + printable(path) + "': short read");
  HdrImage img = decodeHdr(bytes.data(), bytes.size(), path, ledger);
  ledger.release(uint64_t(st.st_size));  // the file's bytes go when this returns
  return img;
}

HdrImage neutralEnvironment() {
  // Directions as the renderer reads the panorama: row v at polar angle
  // theta = pi v from +Y, column u at azimuth phi = 2 pi (u - 0.5) from +X
  // towards +Z. The key light sits at (1, 1.2, -1) here, which the default
  // environment rotation (90 degrees about Y) turns to (1, 1.2, 1): above,
  // to the right of and in front of a model seen from +Z.
  const int W = 256, H = 128;
  const double kPi = 3.14159265358979323846;
  const double kl = std::sqrt(1.0 + 1.44 + 1.0), kx = 1.0 / kl, ky = 1.2 / kl, kz = -1.0 / kl;
  const double inner = std::cos(10.0 * kPi / 180.0), outer = std::cos(22.0 * kPi / 180.0);
  HdrImage img;
  img.width = W;
  img.height = H;
  img.name = kNeutralEnvironmentName;
  img.rgb.resize(size_t(W) * H * 3);
  for (int y = 0; y < H; ++y) {
    const double theta = kPi * (y + 0.5) / H, dy = std::cos(theta), st = std::sin(theta);
    for (int x = 0; x < W; ++x) {
      const double phi = 2.0 * kPi * ((x + 0.5) / W - 0.5);
      const double dx = st * std::cos(phi), dz = st * std::sin(phi);
      // Sky: 0.9 at the horizon to 0.5 at the zenith; floor 0.2; blended
      // over the 4 degrees around the horizon.
      const double sky = 0.5 + 0.4 * (1.0 - (dy > 0.0 ? dy : 0.0));
      const double t = std::fmin(1.0, std::fmax(0.0, (dy + 0.035) / 0.07));
      double L = 0.2 + (sky - 0.2) * t * t * (3.0 - 2.0 * t);
      // Key: a soft disc 10 degrees across at full strength, fading out by 22.
      const double c = dx * kx + dy * ky + dz * kz;
      const double k = std::fmin(1.0, std::fmax(0.0, (c - outer) / (inner - outer)));
      L += 6.0 * k * k * (3.0 - 2.0 * k);
      for (int ch = 0; ch < 3; ++ch) img.rgb[(size_t(y) * W + x) * 3 + ch] = float(L);
    }
  }
  return img;
}

}  // namespace rast
