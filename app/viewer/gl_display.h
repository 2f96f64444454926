// Shows the pipeline's colour buffer in the window: one RGBA8 texture drawn as a
// full-window quad (fixed-function OpenGL, so no GL loader is needed), and the
// window read back for screenshots with the overlay.
//
// The colour reaches the texture by the cheapest path the build has: device to
// device through graphics interop (backends/gl_interop*.cpp), the pipeline's
// host buffer as it is (host backends), or a copy through the host.
//
// The colour bytes are already sRGB-encoded, so the texture is plain RGBA8 and
// the window shows them unchanged.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace rast {

class GlTextureInterop;

// How the last frame reached the texture.
enum class DisplayPath {
  None,         // nothing shown yet
  Interop,      // device to device (GPU builds with graphics interop)
  HostDirect,   // host backends: the pipeline's own buffer uploaded as it is
  HostCopy,     // GPU builds without interop: copied to the host, then uploaded
};

class GlDisplay {
 public:
  GlDisplay();
  ~GlDisplay();
  GlDisplay(const GlDisplay&) = delete;
  GlDisplay& operator=(const GlDisplay&) = delete;

  // Host paths: RGBA8 (R in the low byte) in host memory, top row first
  // (Renderer::colorTopDown) or bottom row first (the pipeline's own buffer).
  void uploadHost(const uint32_t* rgba, int w, int h, bool topDown, DisplayPath path);
  // Device path (GPU builds with interop): the renderer's colour buffer in
  // device memory, bottom row first. Returns false when interop is not
  // available (not a GPU build, no CUDA device behind the GL context, ...);
  // the caller then uploads through the host, and fallbackReason() says why.
  bool uploadDevice(const void* deviceRgbaBottomUp, int w, int h);
  // Draws the texture over the whole framebuffer of fbW x fbH pixels.
  void draw(int fbW, int fbH);
  // The back buffer as drawn so far, RGBA8 top row first (alpha forced to 255).
  static std::vector<uint32_t> readWindow(int w, int h);

  DisplayPath path() const { return path_; }
  // "CUDA-GL interop", "host memory", "host copy (interop unavailable: ...)".
  std::string pathDescription() const;
  const std::string& fallbackReason() const { return fallbackReason_; }

 private:
  void ensureTexture(int w, int h);

  unsigned tex_ = 0;
  int texW_ = 0, texH_ = 0;
  bool topDown_ = true;  // row 0 of the texture is the image's top row
  DisplayPath path_ = DisplayPath::None;
  bool interopFailed_ = false;
  std::string fallbackReason_;
  std::unique_ptr<GlTextureInterop> interop_;
};

}  // namespace rast
