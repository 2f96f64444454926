// Device-to-device display of the pipeline's colour buffer in an OpenGL
// texture (graphics interop), for GPU builds of rast-viewer.
//
// One implementation per kind of backend, chosen by app/viewer/CMakeLists.txt
// like the stage timers: gl_interop_cuda.cpp (CUDA builds) registers the
// texture with CUDA and copies into it on the device; gl_interop_none.cpp
// (every other build) has no interop, and the viewer uploads through the host
// instead. A HIP version would be one more file (hipGraphicsGLRegisterImage).
//
// Only these files know the GPU runtime; the viewer itself is backend
// independent.
#pragma once

#include <memory>
#include <string>

namespace rast {

class GlTextureInterop {
 public:
  // Registers an existing GL_TEXTURE_2D (RGBA8) of the current GL context for
  // device writes. Null when that is impossible, with the reason in *why (not a
  // GPU build, the GL context is not on the compute GPU (e.g. Mesa's llvmpipe),
  // registration refused, ...).
  static std::unique_ptr<GlTextureInterop> create(unsigned glTexture, std::string* why);
  ~GlTextureInterop();
  GlTextureInterop(const GlTextureInterop&) = delete;
  GlTextureInterop& operator=(const GlTextureInterop&) = delete;

  // Copies w x h RGBA8 pixels in device memory (rows of w*4 bytes, bottom row
  // first, as the renderer keeps them and GL textures count rows) into the
  // texture, ordered after the work already queued on the pipeline's stream.
  // False (with the reason in *why) when the copy failed.
  bool copyFrom(const void* deviceRgba, int w, int h, std::string* why);

  // What the display path is called in the viewer's overlay and summary.
  static const char* name();

 private:
  GlTextureInterop() = default;
  void* resource_ = nullptr;  // the runtime's graphics resource handle
};

}  // namespace rast
