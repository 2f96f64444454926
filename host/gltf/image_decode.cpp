// The glTF loader's texture images: decoding them, and turning the decoded
// pixels into rast's RGBA8 Textures. An image's header is read before any
// pixel is decoded, so that an absurd size (a few bytes of PNG can claim
// 100000x100000 texels) is refused before memory is allocated for it: per side,
// and in total against the load's memory budget. When stb_image fails, its own
// reason is reported (tinygltf says "Unknown image format" whatever went
// wrong). The conversion then checks what tinygltf produced (size, channels,
// bit depth), the texture's image and sampler indices and its wrap modes.
#include "host/gltf/gltf_internal.h"

#include <stb/stb_image.h>

namespace rast::gltf_detail {
namespace {

constexpr int kMaxTextureSide = 16384;  // same limit as the image size

}  // namespace

// tinygltf's image decoder (stb_image), after a look at the header so that an
// absurd image size is refused before anything is allocated for it: per side,
// and in total against the memory budget (the decoded pixels, tinygltf's copy
// of them, and the texture built from them).
bool loadImageChecked(tinygltf::Image* image, const int index, std::string* err, std::string* warn, int reqWidth,
                      int reqHeight, const unsigned char* bytes, int size, void* user) {
  LoadContext& ctx = *static_cast<LoadContext*>(user);
  const std::string at = "image " + std::to_string(index);
  int w = 0, h = 0, comp = 0;
  // When stb cannot read the header, its decoder fails at the header too (and
  // says why more precisely than the header probe, which tries every format).
  const bool known = size > 0 && stbi_info_from_memory(bytes, size, &w, &h, &comp);
  if (known && (w > kMaxTextureSide || h > kMaxTextureSide)) {
    if (err)
      *err += at + " is " + std::to_string(w) + "x" + std::to_string(h) + " texels, more than " +
              std::to_string(kMaxTextureSide) + " per side";
    return false;
  }
  // tinygltf decodes to RGBA (8 or 16 bits per channel) and copies the result.
  if (known) {
    const uint64_t decoded = mulSat(mulSat(uint64_t(w), uint64_t(h)), stbi_is_16_bit_from_memory(bytes, size) ? 8 : 4);
    const std::string what = at + " (" + std::to_string(w) + "x" + std::to_string(h) + " texels, decoded)";
    try {
      ctx.ledger.check(what, 2 * decoded);
      ctx.ledger.charge(what, decoded);
    } catch (const Error& e) {
      if (ctx.fatal.empty()) ctx.fatal = e.what();
      if (err) *err += e.what();
      return false;
    }
  }
  std::string decodeErr;
  if (tinygltf::LoadImageData(image, index, &decodeErr, warn, reqWidth, reqHeight, bytes, size, nullptr)) return true;
  // tinygltf says "Unknown image format" whatever went wrong; stb knows why.
  const char* why = stbi_failure_reason();
  if (err) *err += at + ": cannot decode (stb_image: " + std::string(why ? why : "unknown reason") + ")";
  return false;
}

Texture decodeTexture(const tinygltf::Model& m, int texIndex, MemoryLedger& ledger) {
  if (texIndex < 0 || size_t(texIndex) >= m.textures.size()) throw Error("texture index out of range");
  const tinygltf::Texture& t = m.textures[texIndex];
  if (t.source < 0 || size_t(t.source) >= m.images.size()) throw Error("texture has no valid image source");
  const tinygltf::Image& im = m.images[t.source];
  if (im.width <= 0 || im.height <= 0 || im.image.empty()) {
    if (!im.uri.empty() && im.uri.rfind("data:", 0) != 0)
      throw Error("texture image " + std::to_string(t.source) + ": cannot read '" + im.uri + "'");
    throw Error("texture image " + std::to_string(t.source) + " could not be decoded");
  }
  const int comps = im.component, bytes = im.bits / 8;
  if (comps < 1 || comps > 4 || (bytes != 1 && bytes != 2) ||
      im.image.size() < size_t(im.width) * im.height * comps * bytes)
    throw Error("texture image " + std::to_string(t.source) + " has an unsupported layout");
  ledger.charge("texture image " + std::to_string(t.source) + " (" + std::to_string(im.width) + "x" +
                     std::to_string(im.height) + " texels)",
                 mulSat(mulSat(uint64_t(im.width), uint64_t(im.height)), 4));
  Texture out;
  out.width = im.width;
  out.height = im.height;
  out.rgba.resize(size_t(im.width) * im.height);
  for (size_t i = 0; i < out.rgba.size(); ++i) {
    uint8_t c[4] = {0, 0, 0, 255};
    for (int k = 0; k < comps; ++k) {
      const unsigned char* p = &im.image[(i * comps + k) * bytes];
      c[k] = bytes == 1 ? p[0] : p[1];  // 16-bit little endian: keep the high byte
    }
    if (comps == 1 || comps == 2) {  // grey (+alpha)
      c[3] = comps == 2 ? c[1] : 255;
      c[1] = c[2] = c[0];
    }
    out.rgba[i] = uint32_t(c[0]) | uint32_t(c[1]) << 8 | uint32_t(c[2]) << 16 | uint32_t(c[3]) << 24;
  }
  if (t.sampler >= 0) {
    if (size_t(t.sampler) >= m.samplers.size()) throw Error("texture sampler index out of range");
    out.wrapS = m.samplers[t.sampler].wrapS;
    out.wrapT = m.samplers[t.sampler].wrapT;
  }
  for (int32_t w : {out.wrapS, out.wrapT})
    if (w != WrapRepeat && w != WrapClamp && w != WrapMirror) throw Error("sampler has an invalid wrap mode");
  return out;
}

}  // namespace rast::gltf_detail
