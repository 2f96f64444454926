// CUDA-GL interop (CUDA builds of rast-viewer): the texture is registered
// once, and each frame is map, copy device to device, unmap. No host copy.
#include "backends/gl_interop.h"

#include "backends/exec_space.h"

#include <GL/gl.h>
#include <cuda_gl_interop.h>
#include <cuda_runtime.h>

namespace rast {

namespace {
std::string cudaWhy(const char* what, cudaError_t e) {
  cudaGetLastError();  // clear it: the host upload takes over
  return std::string(what) + ": " + cudaGetErrorString(e);
}
}  // namespace

const char* GlTextureInterop::name() { return "CUDA-GL interop"; }

std::unique_ptr<GlTextureInterop> GlTextureInterop::create(unsigned glTexture, std::string* why) {
  // The GL context must live on a CUDA device; cudaGLGetDevices lists the
  // CUDA devices behind the current context (none for Mesa's llvmpipe).
  unsigned int count = 0;
  int devices[8];
  const cudaError_t e = cudaGLGetDevices(&count, devices, 8, cudaGLDeviceListAll);
  if (e != cudaSuccess || count == 0) {
    if (why) *why = e != cudaSuccess ? cudaWhy("the GL context is not on a CUDA device", e)
                                    : "the GL context is not on a CUDA device";
    return nullptr;
  }
  cudaGraphicsResource_t res = nullptr;
  const cudaError_t r =
      cudaGraphicsGLRegisterImage(&res, glTexture, GL_TEXTURE_2D, cudaGraphicsRegisterFlagsWriteDiscard);
  if (r != cudaSuccess) {
    if (why) *why = cudaWhy("cudaGraphicsGLRegisterImage", r);
    return nullptr;
  }
  std::unique_ptr<GlTextureInterop> t(new GlTextureInterop());
  t->resource_ = res;
  return t;
}

GlTextureInterop::~GlTextureInterop() {
  if (resource_) cudaGraphicsUnregisterResource(static_cast<cudaGraphicsResource_t>(resource_));
}

bool GlTextureInterop::copyFrom(const void* deviceRgba, int w, int h, std::string* why) {
  auto res = static_cast<cudaGraphicsResource_t>(resource_);
  // Kokkos' stream: the copy is ordered after the frame's kernels without a
  // host wait; unmap orders GL's use of the texture after the copy.
  cudaStream_t stream = Exec().cuda_stream();
  cudaError_t e = cudaGraphicsMapResources(1, &res, stream);
  if (e != cudaSuccess) {
    if (why) *why = cudaWhy("cudaGraphicsMapResources", e);
    return false;
  }
  cudaArray_t array = nullptr;
  e = cudaGraphicsSubResourceGetMappedArray(&array, res, 0, 0);
  if (e == cudaSuccess)
    e = cudaMemcpy2DToArrayAsync(array, 0, 0, deviceRgba, size_t(w) * 4, size_t(w) * 4, size_t(h),
                                 cudaMemcpyDeviceToDevice, stream);
  const cudaError_t u = cudaGraphicsUnmapResources(1, &res, stream);
  if (e == cudaSuccess) e = u;
  if (e != cudaSuccess) {
    if (why) *why = cudaWhy("CUDA-GL copy", e);
    return false;
  }
  return true;
}

}  // namespace rast
