// 64-bit atomicMin throughput on a 1920x1080 key buffer in two lane layouts
// (docs/performance.md, "A block's rows on lanes"): one atomic on every pixel,
// with a lane per 8x8 block walking its rows (RasterBlocks) and with a block
// row's pixels on consecutive lanes (RasterBlockRows); plain stores for scale.
// Outside the project's build. On the GPU machine:
//   nvcc -O2 -arch=sm_90 -o atomics_layout scripts/device/micro/atomics_layout.cu && ./atomics_layout
#include <cuda_runtime.h>
#include <cstdio>
const int W = 1920, H = 1080, BW = W / 8, BH = H / 8;
__global__ void laneBlock(unsigned long long* vis, unsigned long long v) {
  int b = blockIdx.x * blockDim.x + threadIdx.x;
  if (b >= BW * BH) return;
  int bx = b % BW, by = b / BW;
  for (int y = 0; y < 8; ++y) {
    unsigned long long* row = vis + size_t(by * 8 + y) * W + bx * 8;
#pragma unroll
    for (int k = 0; k < 8; ++k) atomicMin(row + k, v + k);
  }
}
__global__ void laneColumn(unsigned long long* vis, unsigned long long v) {
  int t = blockIdx.x * blockDim.x + threadIdx.x;
  int b = t / 8, k = t % 8;
  if (b >= BW * BH) return;
  int bx = b % BW, by = b / BW;
  for (int y = 0; y < 8; ++y) atomicMin(vis + size_t(by * 8 + y) * W + bx * 8 + k, v + k);
}
__global__ void storeBlock(unsigned long long* vis, unsigned long long v) {
  int b = blockIdx.x * blockDim.x + threadIdx.x;
  if (b >= BW * BH) return;
  int bx = b % BW, by = b / BW;
  for (int y = 0; y < 8; ++y) {
    unsigned long long* row = vis + size_t(by * 8 + y) * W + bx * 8;
#pragma unroll
    for (int k = 0; k < 8; ++k) row[k] = v + k;
  }
}
int main() {
  unsigned long long* vis;
  cudaMalloc(&vis, size_t(W) * H * 8);
  cudaEvent_t a, b;
  cudaEventCreate(&a);
  cudaEventCreate(&b);
  auto run = [&](const char* name, auto kernel, int threads) {
    float best = 1e9f;
    for (int it = 0; it < 50; ++it) {
      cudaMemset(vis, 0xff, size_t(W) * H * 8);
      cudaEventRecord(a);
      kernel<<<(threads + 255) / 256, 256>>>(vis, 1000ull + it);
      cudaEventRecord(b);
      cudaEventSynchronize(b);
      float ms;
      cudaEventElapsedTime(&ms, a, b);
      if (ms < best) best = ms;
    }
    std::printf("%-40s %.1f us (best of 50)\n", name, best * 1000);
  };
  run("atomicMin, a lane per block", laneBlock, BW * BH);
  run("atomicMin, a block row on 8 lanes", laneColumn, BW * BH * 8);
  run("stores, a lane per block", storeBlock, BW * BH);
  return 0;
}
