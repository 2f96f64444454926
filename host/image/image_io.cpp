#include "host/image/image_io.h"

#include "host/scene/scene.h"

#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

namespace rast {
namespace {

// An output file whose every write is checked, including the final flush and
// close where a full disk shows up. A file not committed (an error, an
// exception) is removed, so no partial image is left behind; only regular
// files are removed (never /dev/stdout or a device).
class OutFile {
 public:
  explicit OutFile(const std::string& path) : path_(path), f_(std::fopen(path.c_str(), "wb")) {
    if (!f_) fail(errno);
  }
  OutFile(const OutFile&) = delete;
  OutFile& operator=(const OutFile&) = delete;
  ~OutFile() {
    if (f_) discard();
  }

  void write(const void* p, size_t n) {
    if (n && std::fwrite(p, 1, n, f_) != n) fail(errno);
  }
  void write(const std::string& s) { write(s.data(), s.size()); }

  void commit() {
    const bool flushed = std::fflush(f_) == 0;
    const int err = errno;
    FILE* f = f_;
    f_ = nullptr;
    const bool closed = std::fclose(f) == 0;
    if (!flushed || !closed) {
      removeIfRegular();
      throw Error("cannot write '" + path_ + "': " + std::strerror(flushed ? errno : err));
    }
  }

 private:
  [[noreturn]] void fail(int err) {
    if (f_) discard();
    throw Error("cannot write '" + path_ + "': " + std::strerror(err));
  }
  void discard() {
    std::fclose(f_);
    f_ = nullptr;
    removeIfRegular();
  }
  void removeIfRegular() const {
    struct stat st;
    if (::stat(path_.c_str(), &st) == 0 && S_ISREG(st.st_mode)) std::remove(path_.c_str());
  }

  std::string path_;
  FILE* f_;
};

}  // namespace

void writePng(const std::string& path, int w, int h, const std::vector<uint32_t>& rgba) {
  // Opaque images are written as RGB, like glref's.
  std::vector<unsigned char> rgb(size_t(w) * h * 3);
  for (size_t i = 0; i < size_t(w) * h; ++i) {
    rgb[3 * i] = rgba[i] & 0xff;
    rgb[3 * i + 1] = (rgba[i] >> 8) & 0xff;
    rgb[3 * i + 2] = (rgba[i] >> 16) & 0xff;
  }
  // Encoded in memory first (stb_image_write does so anyway), then written
  // with every error checked: stbi_write_png ignores fwrite/fclose failures.
  std::vector<unsigned char> png;
  auto append = [](void* ctx, void* data, int size) {
    auto* out = static_cast<std::vector<unsigned char>*>(ctx);
    out->insert(out->end(), static_cast<unsigned char*>(data), static_cast<unsigned char*>(data) + size);
  };
  if (!stbi_write_png_to_func(append, &png, w, h, 3, rgb.data(), w * 3) || png.empty())
    throw Error("cannot encode the PNG for '" + path + "'");
  OutFile f(path);
  f.write(png.data(), png.size());
  f.commit();
}

void writePfm(const std::string& path, int w, int h, int channels, const float* data) {
  OutFile f(path);
  f.write(std::string(channels == 3 ? "PF" : "Pf") + "\n" + std::to_string(w) + " " + std::to_string(h) + "\n-1.0\n");
  f.write(data, sizeof(float) * size_t(w) * h * channels);
  f.commit();
}

void writeIdsBin(const std::string& path, int w, int h, const std::vector<uint32_t>& idsBottomUp) {
  OutFile f(path);
  f.write("glref-ids " + std::to_string(w) + " " + std::to_string(h) + " u32le top-down\n");
  for (int y = h - 1; y >= 0; --y) f.write(idsBottomUp.data() + size_t(y) * w, sizeof(uint32_t) * size_t(w));
  f.commit();
}

void writeNpy(const std::string& path, int w, int h, int channels, const char* descr, const void* bottomUp) {
  std::string header = std::string("{'descr': '") + descr + "', 'fortran_order': False, 'shape': (" + std::to_string(h) +
                       ", " + std::to_string(w) + (channels > 1 ? ", " + std::to_string(channels) : std::string()) + "), }";
  // Magic, version 1.0, header length; the header padded with spaces to a multiple of 64 bytes, ending in '\n'.
  const size_t total = ((10 + header.size() + 1 + 63) / 64) * 64;
  header.append(total - 10 - header.size() - 1, ' ');
  header += '\n';
  const uint16_t len = uint16_t(header.size());
  OutFile f(path);
  f.write("\x93NUMPY\x01\x00", 8);
  const unsigned char le[2] = {uint8_t(len & 0xff), uint8_t(len >> 8)};
  f.write(le, 2);
  f.write(header);
  const size_t row = size_t(w) * size_t(channels) * 4;
  const char* src = static_cast<const char*>(bottomUp);
  for (int y = h - 1; y >= 0; --y) f.write(src + size_t(y) * row, row);
  f.commit();
}

std::vector<uint32_t> readIdsBin(const std::string& path, int& w, int& h) {
  std::ifstream f(path, std::ios::binary);
  std::string line;
  if (!f || !std::getline(f, line)) throw Error("cannot read '" + path + "'");
  std::istringstream is(line);
  std::string magic;
  is >> magic >> w >> h;
  if (magic != "glref-ids" || w <= 0 || h <= 0) throw Error("'" + path + "' is not a glref-ids file");
  std::vector<uint32_t> ids(size_t(w) * h);
  f.read(reinterpret_cast<char*>(ids.data()), std::streamsize(ids.size() * 4));
  if (!f) throw Error("'" + path + "' is truncated");
  return ids;
}

std::vector<float> readPfm(const std::string& path, int& w, int& h, int& channels) {
  std::ifstream f(path, std::ios::binary);
  std::string magic;
  float scale = 0.0f;
  if (!(f >> magic >> w >> h >> scale) || (magic != "Pf" && magic != "PF")) throw Error("'" + path + "' is not a PFM file");
  f.get();
  channels = magic == "PF" ? 3 : 1;
  std::vector<float> d(size_t(w) * h * channels);
  f.read(reinterpret_cast<char*>(d.data()), std::streamsize(d.size() * 4));
  if (!f || scale >= 0.0f) throw Error("'" + path + "' is truncated or big-endian");
  return d;
}

std::vector<uint32_t> readPng(const std::string& path, int& w, int& h) {
  int comp = 0;
  unsigned char* p = stbi_load(path.c_str(), &w, &h, &comp, 4);
  if (!p) throw Error("cannot read image '" + path + "'");
  std::vector<uint32_t> out(size_t(w) * h);
  std::memcpy(out.data(), p, out.size() * 4);
  stbi_image_free(p);
  return out;
}

}  // namespace rast
