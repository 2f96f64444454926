// OpenEXR files of the CLI's outputs (app/exr_output.h): the channels are
// flipped to EXR's top-first rows, handed to OpenEXR's scanline writer over an
// in-memory stream, and the bytes go to the AtomicFile.
#include "app/exr_output.h"

#include "base/error.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfOutputFile.h>

#include <cctype>
#include <cstring>
#include <exception>

namespace rast {
namespace {

// OpenEXR writes through a seekable stream; this one grows a byte buffer.
class MemoryStream : public Imf::OStream {
 public:
  MemoryStream() : Imf::OStream("rast EXR output") {}
  void write(const char c[], int n) override {
    if (pos_ + uint64_t(n) > bytes.size()) bytes.resize(size_t(pos_) + size_t(n));
    std::memcpy(&bytes[size_t(pos_)], c, size_t(n));
    pos_ += uint64_t(n);
  }
  uint64_t tellp() override { return pos_; }
  void seekp(uint64_t pos) override { pos_ = pos; }
  std::vector<char> bytes;

 private:
  uint64_t pos_ = 0;
};

}  // namespace

bool isExrPath(const std::string& p) {
  if (p.size() < 4) return false;
  std::string e = p.substr(p.size() - 4);
  for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
  return e == ".exr";
}

void ExrImage::addFloat(const std::string& name, const float* bottomUp, int stride, int offset) {
  Channel c{name, false, std::vector<uint32_t>(size_t(width_) * size_t(height_))};
  for (size_t y = 0; y < size_t(height_); ++y)
    for (size_t x = 0; x < size_t(width_); ++x)
      std::memcpy(&c.bits[y * size_t(width_) + x],
                  bottomUp + ((size_t(height_) - 1 - y) * size_t(width_) + x) * size_t(stride) + size_t(offset),
                  sizeof(float));
  channels_.push_back(std::move(c));
}

void ExrImage::addUint(const std::string& name, const uint32_t* bottomUp) {
  Channel c{name, true, std::vector<uint32_t>(size_t(width_) * size_t(height_))};
  for (size_t y = 0; y < size_t(height_); ++y)
    std::memcpy(&c.bits[y * size_t(width_)], bottomUp + (size_t(height_) - 1 - y) * size_t(width_),
                size_t(width_) * sizeof(uint32_t));
  channels_.push_back(std::move(c));
}

void ExrImage::write(AtomicFile& file) const {
  MemoryStream stream;
  try {
    Imf::Header header(width_, height_);
    header.compression() = Imf::ZIP_COMPRESSION;
    Imf::FrameBuffer fb;
    for (const Channel& c : channels_) {
      const Imf::PixelType t = c.isUint ? Imf::UINT : Imf::FLOAT;
      header.channels().insert(c.name, Imf::Channel(t));
      fb.insert(c.name, Imf::Slice(t, reinterpret_cast<char*>(const_cast<uint32_t*>(c.bits.data())), sizeof(uint32_t),
                                   sizeof(uint32_t) * size_t(width_)));
    }
    Imf::OutputFile out(stream, header);
    out.setFrameBuffer(fb);
    out.writePixels(height_);
  } catch (const std::exception& e) {
    throw Error(file.path() + ": OpenEXR could not write the image: " + e.what());
  }
  file.write(stream.bytes.data(), stream.bytes.size());
}

}  // namespace rast
