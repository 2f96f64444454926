// Shows the pipeline's colour buffer in the window: one RGBA8 texture drawn as a
// full-window quad (fixed-function OpenGL, so no GL loader is needed), and the
// window read back for screenshots with the overlay.
//
// The colour bytes are already sRGB-encoded, so the texture is plain RGBA8 and
// the window shows them unchanged.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

namespace rast {

class CudaGlTexture;

class GlDisplay {
 public:
  GlDisplay();
  ~GlDisplay();
  GlDisplay(const GlDisplay&) = delete;
  GlDisplay& operator=(const GlDisplay&) = delete;

  // Host path: RGBA8 (R in the low byte), top row first (Renderer::colorTopDown).
  void uploadTopDown(const uint32_t* rgba, int w, int h);
  // Device path (CUDA builds with interop): the renderer's colour buffer in
  // device memory, bottom row first. Returns false when interop is not
  // available (not a CUDA build, no CUDA device behind the GL context, ...);
  // the caller then uploads through the host.
  bool uploadDevice(const void* deviceRgbaBottomUp, int w, int h);
  // Draws the texture over the whole framebuffer of fbW x fbH pixels.
  void draw(int fbW, int fbH);
  // The back buffer as drawn so far, RGBA8 top row first (alpha forced to 255).
  static std::vector<uint32_t> readWindow(int w, int h);

  bool interopActive() const { return interopActive_; }

 private:
  void ensureTexture(int w, int h);

  unsigned tex_ = 0;
  int texW_ = 0, texH_ = 0;
  bool topDown_ = true;  // row 0 of the texture is the image's top row
  bool interopActive_ = false, interopFailed_ = false;
  std::unique_ptr<CudaGlTexture> interop_;
};

}  // namespace rast
