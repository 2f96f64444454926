#include "host/image/image_io.h"

#include "host/image/safe_output.h"
#include "host/scene/scene.h"

#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

namespace rast {

void writePng(AtomicFile& f, int w, int h, const std::vector<uint32_t>& rgba, bool alpha) {
  // Opaque images are written as RGB, like glref's; with alpha, RGBA.
  const int ch = alpha ? 4 : 3;
  std::vector<unsigned char> rgb(size_t(w) * h * ch);
  for (size_t i = 0; i < size_t(w) * h; ++i)
    for (int k = 0; k < ch; ++k) rgb[ch * i + k] = (rgba[i] >> (8 * k)) & 0xff;
  // Encoded in memory first (stb_image_write does so anyway), then written
  // with every error checked: stbi_write_png ignores fwrite/fclose failures.
  std::vector<unsigned char> png;
  auto append = [](void* ctx, void* data, int size) {
    auto* out = static_cast<std::vector<unsigned char>*>(ctx);
    out->insert(out->end(), static_cast<unsigned char*>(data), static_cast<unsigned char*>(data) + size);
  };
  if (!stbi_write_png_to_func(append, &png, w, h, ch, rgb.data(), w * ch) || png.empty())
    throw Error("cannot encode the PNG for '" + printable(f.path()) + "'");
  f.write(png.data(), png.size());
}

void writePfm(AtomicFile& f, int w, int h, int channels, const float* data) {
  f.write(std::string(channels == 3 ? "PF" : "Pf") + "\n" + std::to_string(w) + " " + std::to_string(h) + "\n-1.0\n");
  f.write(data, sizeof(float) * size_t(w) * h * channels);
}

void writeIdsBin(AtomicFile& f, int w, int h, const std::vector<uint32_t>& idsBottomUp) {
  f.write("glref-ids " + std::to_string(w) + " " + std::to_string(h) + " u32le top-down\n");
  for (int y = h - 1; y >= 0; --y) f.write(idsBottomUp.data() + size_t(y) * w, sizeof(uint32_t) * size_t(w));
}

void writePng(const std::string& path, int w, int h, const std::vector<uint32_t>& rgba) {
  AtomicFile f(path);
  writePng(f, w, h, rgba);
  f.commit();
}

void writePfm(const std::string& path, int w, int h, int channels, const float* data) {
  AtomicFile f(path);
  writePfm(f, w, h, channels, data);
  f.commit();
}

void writeIdsBin(const std::string& path, int w, int h, const std::vector<uint32_t>& idsBottomUp) {
  AtomicFile f(path);
  writeIdsBin(f, w, h, idsBottomUp);
  f.commit();
}

void writeNpy(AtomicFile& f, int w, int h, int channels, const char* descr, const void* bottomUp) {
  std::string header = std::string("{'descr': '") + descr + "', 'fortran_order': False, 'shape': (" + std::to_string(h) +
                       ", " + std::to_string(w) + (channels > 1 ? ", " + std::to_string(channels) : std::string()) + "), }";
  // Magic, version 1.0, header length; the header padded with spaces to a multiple of 64 bytes, ending in '\n'.
  const size_t total = ((10 + header.size() + 1 + 63) / 64) * 64;
  header.append(total - 10 - header.size() - 1, ' ');
  header += '\n';
  const uint16_t len = uint16_t(header.size());
  f.write("\x93NUMPY\x01\x00", 8);
  const unsigned char le[2] = {uint8_t(len & 0xff), uint8_t(len >> 8)};
  f.write(le, 2);
  f.write(header);
  const size_t row = size_t(w) * size_t(channels) * 4;
  const char* src = static_cast<const char*>(bottomUp);
  for (int y = h - 1; y >= 0; --y) f.write(src + size_t(y) * row, row);
}

void writeNpy(const std::string& path, int w, int h, int channels, const char* descr, const void* bottomUp) {
  AtomicFile f(path);
  writeNpy(f, w, h, channels, descr, bottomUp);
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
