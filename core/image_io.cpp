#include "image_io.h"

#include "scene.h"

#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

namespace rast {

void writePng(const std::string& path, int w, int h, const std::vector<uint32_t>& rgba) {
  // Opaque images are written as RGB, like glref's.
  std::vector<unsigned char> rgb(size_t(w) * h * 3);
  for (size_t i = 0; i < size_t(w) * h; ++i) {
    rgb[3 * i] = rgba[i] & 0xff;
    rgb[3 * i + 1] = (rgba[i] >> 8) & 0xff;
    rgb[3 * i + 2] = (rgba[i] >> 16) & 0xff;
  }
  if (!stbi_write_png(path.c_str(), w, h, 3, rgb.data(), w * 3)) throw Error("cannot write '" + path + "'");
}

void writePfm(const std::string& path, int w, int h, int channels, const float* data) {
  std::ofstream f(path, std::ios::binary);
  if (!f) throw Error("cannot write '" + path + "'");
  f << (channels == 3 ? "PF" : "Pf") << "\n" << w << " " << h << "\n-1.0\n";
  f.write(reinterpret_cast<const char*>(data), std::streamsize(sizeof(float)) * w * h * channels);
  if (!f) throw Error("cannot write '" + path + "'");
}

void writeIdsBin(const std::string& path, int w, int h, const std::vector<uint32_t>& idsBottomUp) {
  std::ofstream f(path, std::ios::binary);
  if (!f) throw Error("cannot write '" + path + "'");
  f << "glref-ids " << w << " " << h << " u32le top-down\n";
  for (int y = h - 1; y >= 0; --y)
    f.write(reinterpret_cast<const char*>(idsBottomUp.data() + size_t(y) * w), std::streamsize(sizeof(uint32_t)) * w);
  if (!f) throw Error("cannot write '" + path + "'");
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
