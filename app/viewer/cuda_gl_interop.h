// CUDA-GL interop for CUDA builds of rast-viewer (compiled only when the
// pipeline runs on Kokkos' CUDA backend): the colour buffer is copied into the
// GL texture device to device, never through the host.
//
// Only this pair of files knows about CUDA; every other viewer file is backend
// independent. If registration fails (the GL context is not on an NVIDIA GPU,
// e.g. Mesa under Xvfb, or another GPU than CUDA's), create() returns null and
// the viewer uploads through the host instead.
#pragma once

#include <memory>

namespace rast {

class CudaGlTexture {
 public:
  // Registers an existing GL_TEXTURE_2D (RGBA8) for CUDA writes; null on failure.
  static std::unique_ptr<CudaGlTexture> create(unsigned glTexture);
  ~CudaGlTexture();
  CudaGlTexture(const CudaGlTexture&) = delete;
  CudaGlTexture& operator=(const CudaGlTexture&) = delete;

  // Copies w x h RGBA8 pixels (rows of w*4 bytes, bottom row first, as the
  // renderer keeps them and as GL textures count rows) into the texture.
  bool copyFrom(const void* deviceRgba, int w, int h);

 private:
  CudaGlTexture() = default;
  void* resource_ = nullptr;  // cudaGraphicsResource_t
};

}  // namespace rast
