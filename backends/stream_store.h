// Copies of whole 16-byte pieces to memory that this pass will not read
// again, for host code: x86-64's streaming stores (SSE2, in every x86-64)
// write them without first reading each line into the cache, elsewhere a
// plain copy (backend-specific, so it lives in backends/). The host setup
// (core/primitive_setup.cpp) copies its staged triangles with it; call
// streamFence() before another thread or pass may read what was written.
#pragma once

#include <cstddef>
#include <cstring>

#if defined(__x86_64__) && !defined(__CUDACC__) && !defined(__HIPCC__)
#include <emmintrin.h>
#define RAST_STREAM_STORES 1
#endif

namespace rast {

// dst and src 16-byte aligned; n pieces of 16 bytes.
inline void streamCopy16(void* dst, const void* src, size_t n) {
#ifdef RAST_STREAM_STORES
  __m128i* d = static_cast<__m128i*>(dst);
  const __m128i* s = static_cast<const __m128i*>(src);
  for (size_t i = 0; i < n; ++i) _mm_stream_si128(d + i, _mm_load_si128(s + i));
#else
  std::memcpy(dst, src, n * 16);
#endif
}

inline void streamFence() {
#ifdef RAST_STREAM_STORES
  _mm_sfence();
#endif
}

}  // namespace rast
