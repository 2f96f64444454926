// Host cost of cudaGraphLaunch, and the GPU's time from a graph's launch to
// its end, for graphs shaped like rast's recorded frame (a copy node, an
// event node, a few kernels): docs/performance.md, "A block's rows on lanes".
// COLD runs read 64 MiB on the host between launches. Outside the project's
// build. On the GPU machine:
//   nvcc -O2 -arch=sm_90 -o graph_launch_cost scripts/device/micro/graph_launch_cost.cu && ./graph_launch_cost
#include <cuda_runtime.h>
#include <chrono>
#include <cstdio>
#include <vector>
#include <algorithm>
struct Big { char b[1024]; };
__global__ void k0(int* p) { if (p && threadIdx.x == 0 && blockIdx.x == 0) p[0] += 1; }
__global__ void kbig(const Big b, int* p) { if (p && threadIdx.x == 0 && blockIdx.x == 0) p[0] += b.b[5]; }
int main() {
  cudaStream_t s; cudaStreamCreateWithFlags(&s, cudaStreamNonBlocking);
  cudaStream_t sb; cudaStreamCreate(&sb);
  std::vector<char> junk(64 << 20, 1);
  bool cold = false;
  int* d; cudaMalloc(&d, 4096);
  void* h; cudaHostAlloc(&h, 1024, cudaHostAllocDefault);
  cudaEvent_t ev; cudaEventCreateWithFlags(&ev, cudaEventDisableTiming);
  cudaEvent_t a, b; cudaEventCreate(&a); cudaEventCreate(&b);
  auto test = [&](const char* name, int kernels, bool copy, bool event, bool big, int grid) {
    cudaGraph_t g; cudaGraphExec_t e;
    cudaStreamBeginCapture(s, cudaStreamCaptureModeRelaxed);
    if (copy) cudaMemcpyAsync(d, h, 576, cudaMemcpyHostToDevice, s);
    if (event) cudaEventRecordWithFlags(ev, s, cudaEventRecordExternal);
    Big bb{};
    for (int i = 0; i < kernels; ++i) { if (big) kbig<<<grid, 128, 0, s>>>(bb, d); else k0<<<grid, 128, 0, s>>>(d); }
    cudaStreamEndCapture(s, &g);
    cudaGraphInstantiateWithFlags(&e, g, 0);
    std::vector<double> t, f;
    for (int it = 0; it < 400; ++it) {
      if (cold) { volatile char* j = junk.data(); long sum = 0; for (size_t q = 0; q < junk.size(); q += 64) sum += j[q]; junk[it] = char(sum); }
      cudaEventRecord(a, s);
      auto t0 = std::chrono::steady_clock::now();
      cudaGraphLaunch(e, s);
      auto t1 = std::chrono::steady_clock::now();
      cudaEventRecord(b, s);
      cudaEventSynchronize(b);
      float ms; cudaEventElapsedTime(&ms, a, b);
      if (it >= 50) { t.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count()); f.push_back(ms * 1000); }
    }
    std::sort(t.begin(), t.end()); std::sort(f.begin(), f.end());
    printf("%-34s launch %.2f us (p10 %.2f)  frame %.2f us\n", name, t[t.size()/2], t[t.size()/10], f[f.size()/2]);
    cudaGraphExecDestroy(e); cudaGraphDestroy(g);
  };
  test("1 kernel", 1, false, false, false, 1);
  test("copy + event + 4 kernels", 4, true, true, true, 1000);
  std::swap(s, sb);
  test("BLOCKING copy + event + 4 kernels", 4, true, true, true, 1000);
  std::swap(s, sb);
  cold = true;
  test("COLD copy + event + 4 kernels", 4, true, true, true, 1000);
  test("COLD 4 kernels", 4, false, false, true, 1000);
  cold = false;
  test("5 kernels", 5, false, false, false, 1);
  test("5 kernels grid 1000", 5, false, false, false, 1000);
  test("5 kernels 1KB params", 5, false, false, true, 1);
  test("copy + 5 kernels", 5, true, false, false, 1);
  test("copy + event + 5 kernels", 5, true, true, false, 1);
  test("copy + event + 5 kernels 1KB", 5, true, true, true, 1000);
  test("10 kernels", 10, false, false, false, 1);
  test("1 kernel", 1, false, false, false, 1);
  return 0;
}
