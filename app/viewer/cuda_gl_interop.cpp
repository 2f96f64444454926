// Compiled only in CUDA builds (see app/viewer/CMakeLists.txt). Untested on the
// project's machines, which have no GPU with an OpenGL display: see
// docs/viewer.md.
#include "cuda_gl_interop.h"

#include <GL/gl.h>
#include <cuda_gl_interop.h>
#include <cuda_runtime.h>

#include <cstdio>

namespace rast {

std::unique_ptr<CudaGlTexture> CudaGlTexture::create(unsigned glTexture) {
  // The GL context must live on a CUDA device (cudaGLGetDevices lists them).
  unsigned int count = 0;
  int devices[8];
  if (cudaGLGetDevices(&count, devices, 8, cudaGLDeviceListAll) != cudaSuccess || count == 0) {
    cudaGetLastError();  // clear the error, the upload path takes over
    return nullptr;
  }
  cudaGraphicsResource_t res = nullptr;
  if (cudaGraphicsGLRegisterImage(&res, glTexture, GL_TEXTURE_2D, cudaGraphicsRegisterFlagsWriteDiscard) !=
      cudaSuccess) {
    cudaGetLastError();
    return nullptr;
  }
  std::unique_ptr<CudaGlTexture> t(new CudaGlTexture());
  t->resource_ = res;
  return t;
}

CudaGlTexture::~CudaGlTexture() {
  if (resource_) cudaGraphicsUnregisterResource(static_cast<cudaGraphicsResource_t>(resource_));
}

bool CudaGlTexture::copyFrom(const void* deviceRgba, int w, int h) {
  auto res = static_cast<cudaGraphicsResource_t>(resource_);
  // Default stream: ordered after the Kokkos kernels of the frame, which the
  // renderer has already fenced.
  if (cudaGraphicsMapResources(1, &res, 0) != cudaSuccess) return false;
  cudaArray_t array = nullptr;
  bool ok = cudaGraphicsSubResourceGetMappedArray(&array, res, 0, 0) == cudaSuccess &&
            cudaMemcpy2DToArray(array, 0, 0, deviceRgba, size_t(w) * 4, size_t(w) * 4, size_t(h),
                                cudaMemcpyDeviceToDevice) == cudaSuccess;
  ok = cudaGraphicsUnmapResources(1, &res, 0) == cudaSuccess && ok;
  if (!ok) {
    const cudaError_t e = cudaGetLastError();
    std::fprintf(stderr, "rast-viewer: CUDA-GL copy: %s\n", cudaGetErrorString(e));
  }
  return ok;
}

}  // namespace rast
