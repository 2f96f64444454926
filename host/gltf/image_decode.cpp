// The glTF loader's texture images: decoding them, and turning the decoded
// pixels into rast's RGBA8 Textures. An image's header is read before any
// pixel is decoded, so that an absurd size (a few bytes of PNG can claim
// 100000x100000 texels) is refused before memory is allocated for it: per side,
// and in total against the load's memory budget. When stb_image fails, its own
// reason is reported (tinygltf says "Unknown image format" whatever went
// wrong). Only PNG and JPEG are decoded, recognised by their signatures, and
// only when their stream is complete (IEND; EOI after the last scan). The
// conversion then checks what tinygltf produced (size, channels, bit depth),
// the texture's image and sampler indices and its wrap modes.
#include "host/gltf/gltf_internal.h"

#include <stb/stb_image.h>

#include <cstring>

namespace rast::gltf_detail {
namespace {

constexpr int kMaxTextureSide = 16384;  // same limit as the image size

bool startsWith(const unsigned char* b, size_t n, const char* sig, size_t len) {
  return n >= len && std::memcmp(b, sig, len) == 0;
}

// What the bytes are, by signature. glTF 2.0 allows PNG and JPEG (WebP and
// KTX2 by extensions rast does not implement); stb_image would also decode
// PNM, PSD, BMP, GIF, HDR, TGA and PIC, and its PNM reader ignores a short
// read (uninitialised texels), so nothing else reaches it.
const char* otherFormat(const unsigned char* b, size_t n) {
  if (startsWith(b, n, "RIFF", 4) && n >= 12 && std::memcmp(b + 8, "WEBP", 4) == 0)
    return "WebP (EXT_texture_webp, which rast does not support)";
  if (startsWith(b, n, "\xABKTX 20\xBB\r\n\x1A\n", 12)) return "KTX2 (KHR_texture_basisu, which rast does not support)";
  if (n >= 2 && b[0] == 'P' && b[1] >= '1' && b[1] <= '7') return "PNM";
  if (startsWith(b, n, "8BPS", 4)) return "PSD";
  if (startsWith(b, n, "BM", 2)) return "BMP";
  if (startsWith(b, n, "GIF8", 4)) return "GIF";
  if (startsWith(b, n, "#?RADIANCE", 10) || startsWith(b, n, "#?RGBE", 6)) return "Radiance HDR";
  return nullptr;
}

// Why complete-looking PNG/JPEG bytes are not complete, or "" when they are:
// a truncated file decodes without complaint in parts of stb_image (JPEG pads
// missing entropy data with zeros), so the end of the stream must be there.
std::string truncation(const unsigned char* b, size_t n, bool png) {
  if (png) {
    // The IEND chunk (length 0, type IEND) ends every complete PNG.
    static const unsigned char iend[8] = {0, 0, 0, 0, 'I', 'E', 'N', 'D'};
    for (size_t i = n >= 12 ? n - 12 + 1 : 0; i-- > 8;)
      if (std::memcmp(b + i, iend, 8) == 0) return "";
    return "truncated PNG: no IEND chunk";
  }
  // JPEG: an EOI marker (FF D9) after the last start of scan (FF DA).
  size_t sos = 0;
  for (size_t i = 2; i + 1 < n; ++i)
    if (b[i] == 0xFF && b[i + 1] == 0xDA) sos = i;
  if (sos == 0) return "truncated JPEG: no scan data";
  for (size_t i = sos + 2; i + 1 < n; ++i)
    if (b[i] == 0xFF && b[i + 1] == 0xD9) return "";
  return "truncated JPEG: no end-of-image marker after the last scan";
}

}  // namespace

// tinygltf's image decoder (stb_image), after a look at the header so that an
// absurd image size is refused before anything is allocated for it: per side,
// and in total against the memory budget (stb's working buffers, the decoded
// pixels, tinygltf's copy of them, and the texture built from them).
bool loadImageChecked(tinygltf::Image* image, const int index, std::string* err, std::string* warn, int reqWidth,
                      int reqHeight, const unsigned char* bytes, int size, void* user) {
  LoadContext& ctx = *static_cast<LoadContext*>(user);
  const std::string at = "image " + std::to_string(index);
  const auto refuse = [&](const std::string& why) {
    const std::string m = at + ": " + why;
    if (ctx.fatal.empty()) ctx.fatal = m;
    if (err) *err += m;
    return false;
  };
  const size_t n = size > 0 ? size_t(size) : 0;
  const bool png = startsWith(bytes, n, "\x89PNG\r\n\x1a\n", 8), jpeg = n >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF;
  if (n == 0) return refuse("no image data (0 bytes)");
  // KTX2 (KHR_texture_basisu) has no decoder in Debian: left undecoded, so that
  // a texture naming it only in the extension falls back to its PNG/JPEG
  // source; a texture whose source it is is refused (compression.cpp).
  if (startsWith(bytes, n, "\xABKTX 20\xBB\r\n\x1A\n", 12)) {
    ctx.ktx2Images.push_back(index);
    return true;
  }
  if (!png && !jpeg) {
    const char* other = otherFormat(bytes, n);
    return refuse(other ? std::string("is ") + other + ", not PNG or JPEG, the image formats glTF allows"
                        : std::string("is not a PNG or JPEG image (the image formats glTF allows)"));
  }
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
      // While decoding: stb's inflated (PNG) or per-component (JPEG) buffers,
      // its output, and tinygltf's copy of it, which stays.
      ctx.ledger.check(what, 3 * decoded);
      ctx.ledger.charge(what, decoded);
    } catch (const Error& e) {
      if (ctx.fatal.empty()) ctx.fatal = e.what();
      if (err) *err += e.what();
      return false;
    }
  }
  std::string decodeErr, decodeWarn;
  if (tinygltf::LoadImageData(image, index, &decodeErr, &decodeWarn, reqWidth, reqHeight, bytes, size, nullptr)) {
    (void)warn;
    if (!decodeWarn.empty()) return refuse("cannot decode: " + oneLine(decodeWarn));  // a warning is an error here
    // Decoded, but from a stream without its end: stb_image fills what is
    // missing in some cases instead of failing.
    const std::string cut = truncation(bytes, n, png);
    return cut.empty() ? true : refuse(cut);
  }
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
    const tinygltf::Sampler& sm = m.samplers[t.sampler];
    if (sm.magFilter != -1) {
      if (sm.magFilter != 9728 && sm.magFilter != 9729) throw Error("sampler has an invalid magFilter");
      out.magFilter = sm.magFilter;
    }
    if (sm.minFilter != -1) {
      if (sm.minFilter != 9728 && sm.minFilter != 9729 && (sm.minFilter < 9984 || sm.minFilter > 9987))
        throw Error("sampler has an invalid minFilter");
      out.minFilter = sm.minFilter;
    }
  }
  for (int32_t w : {out.wrapS, out.wrapT})
    if (w != WrapRepeat && w != WrapClamp && w != WrapMirror) throw Error("sampler has an invalid wrap mode");
  return out;
}

}  // namespace rast::gltf_detail
