// How the CPU's span kernel (shade_spans.h) cuts a row of ids into runs
// (runStarts), and the lane batch that takes the runs too short to fill a
// vector: LaneBatch holds, lane by lane, each pixel's own triangle constants,
// and laneLighting is spanLightingFrom (span_math.h) over them.
//
// It exists because scenes of tiny triangles are almost all one-pixel runs,
// and a span of one pixel ran the vector loops over a single lane; batching
// the runs of different triangles fills the vectors with the same operations,
// so the same bits. The kernel's members that fill and shade a batch
// (ShadeSpans::addLanes, shadeBatch) are in span_lanes.h: they need the
// kernel's state, and LaneBatch must be complete before the kernel uses it.
#pragma once

#include "backends/cpu_clones.h"
#include "pipeline/cpu/span_math.h"

namespace rast {
namespace shading {

// Where the runs of equal ids of a row of n <= kRunMaskBits pixels start: bit j is set
// where idx[j] differs from idx[j - 1] (bit 0 always), in one pass without
// branches. A search for each run's end (the earlier runEnd) mispredicted
// its exit about once a run: duck 800x800 2.15 -> 2.03 ms with the mask, cow
// 1.53 -> 1.42. A row of one run (a large triangle's, the background) is
// told first by a cheaper vectorized test: bigtri 1080p 5.48 -> 5.02 ms.
constexpr int32_t kRunMaskBits = 64;  // the longest row runStarts takes
KOKKOS_FORCEINLINE_FUNCTION uint64_t runStarts(const uint32_t* __restrict__ idx, int32_t n) {
  uint32_t differs = 0;
  for (int32_t j = 1; j < n; ++j) differs |= idx[j] ^ idx[0];
  if (differs == 0) return 1;
  uint64_t starts = 1;
  for (int32_t j = 1; j < n; ++j) starts |= uint64_t(idx[j] != idx[j - 1]) << j;
  return starts;
}
static_assert(kMaxSpanRun <= kRunMaskBits, "shadeTile finds a row's runs with one runStarts");

// Pixels of short runs of different triangles, shaded together as the lanes
// of one vector (ShadeSpans::shadeRow). On scenes of tiny triangles nearly
// every pixel is a triangle of its own, and a span of one pixel ran the
// span's loops over a single lane: a chain of dependent divisions and square
// roots a pixel. Here each lane carries its own triangle's constants (those
// of SpanConsts, and the base colour), so that the loops below are those of
// spanLightingFrom with a lane's constants for the span's: the same
// operations, so the same bits.
constexpr int32_t kLaneRunMax = 4;  // runs shorter than this (untextured) go to a batch
struct LaneBatch {
  int32_t m = 0;                   // lanes in use
  int32_t X[kMaxSpanRun];          // each lane's pixel column (the row is the batch's)
  float e0[kMaxSpanRun], e1[kMaxSpanRun], e2[kMaxSpanRun];  // exact edge values, as float(double(E))
  float ia[kMaxSpanRun], iw0[kMaxSpanRun], iw1[kMaxSpanRun], iw2[kMaxSpanRun];
  float t00[kMaxSpanRun], t10[kMaxSpanRun], t20[kMaxSpanRun], t01[kMaxSpanRun], t11[kMaxSpanRun], t21[kMaxSpanRun];
  float n[9][kMaxSpanRun], q[9][kMaxSpanRun];  // normals and positions of corners 0..2, x y z each
  float base[4][kMaxSpanRun];                  // base colour
  float col[12][kMaxSpanRun];                  // vertex colours of corners 0..2, rgba each (scenes with them)
};

// spanLightingFrom's loop with each lane's triangle constants: the weights
// (b0..b2) out, and the normal and headlight of every lane.
KOKKOS_FORCEINLINE_FUNCTION void laneLighting(const LaneBatch& L, int32_t m, float3 eye, float ambient, float headI,
                                              float* __restrict__ b0, float* __restrict__ b1, float* __restrict__ b2,
                                              float* __restrict__ nx, float* __restrict__ ny, float* __restrict__ nz,
                                              float* __restrict__ diffuse) {
  for (int32_t j = 0; j < m; ++j) {
    const float ia = L.ia[j];
    // Shade::bary's screen-space weights: l0 from edge 1, l1 from edge 2, l2 from edge 0
    litPixel((L.e1[j] * ia) * L.iw0[j], (L.e2[j] * ia) * L.iw1[j], (L.e0[j] * ia) * L.iw2[j], L.t00[j], L.t10[j],
             L.t20[j], L.t01[j], L.t11[j], L.t21[j], float3{L.n[0][j], L.n[1][j], L.n[2][j]},
             float3{L.n[3][j], L.n[4][j], L.n[5][j]}, float3{L.n[6][j], L.n[7][j], L.n[8][j]},
             float3{L.q[0][j], L.q[1][j], L.q[2][j]}, float3{L.q[3][j], L.q[4][j], L.q[5][j]},
             float3{L.q[6][j], L.q[7][j], L.q[8][j]}, eye, ambient, headI, b0[j], b1[j], b2[j], nx[j], ny[j], nz[j],
             diffuse[j]);
  }
}
RAST_CPU_CLONES void laneLightingWide(const LaneBatch& L, int32_t m, float3 eye, float ambient, float headI,
                                      float* __restrict__ b0, float* __restrict__ b1, float* __restrict__ b2,
                                      float* __restrict__ nx, float* __restrict__ ny, float* __restrict__ nz,
                                      float* __restrict__ diffuse) {
  laneLighting(L, m, eye, ambient, headI, b0, b1, b2, nx, ny, nz, diffuse);
}

}  // namespace shading
}  // namespace rast
