// The buffers of the transparency passes (pipeline/blend/, docs/transparency.md):
// the per-class work lists of MASK and BLEND raster triangles, the exact
// method's fragment store, the k-buffer and the weighted method's sums. Each
// is allocated the first time a frame needs it and grown (never capped); a
// scene without MASK or BLEND materials allocates none of them.
#pragma once

#include "pipeline/data/device.h"
#include "base/vec.h"

namespace rast {

// Slots of BlendBuffers::totals (64-bit, written on the device, read after a frame).
enum BlendTotal : int {
  kMaskItems = 0,     // work items (8x8 blocks) of the MASK raster triangles
  kBlendItems = 1,    // work items of the BLEND raster triangles
  kBlendFrags = 2,    // fragments the exact (and sorted) methods kept this frame
  kBlendMaxDepth = 3, // most fragments of one sample (the depth complexity `auto` reads)
  kNumBlendTotals = 4
};

struct BlendBuffers {
  DView<uint64_t> totals;            // BlendTotal
  DView<uint64_t> maskStart, blendStart;  // per raster triangle: its first work item (exclusive scan)
  // exact / sorted: per sample the fragment count, and its end in `frags`
  // after the write pass (start = end - count)
  DView<uint32_t> count, end;
  DView<uint64_t> frags;             // per fragment: sort key (depth or order << 32 | raster index + 1)
  uint64_t fragCapacity = 0;
  // kbuffer: k keys per sample, nearest first
  DView<uint64_t> slots;
  int k = 0;
  // weighted (and the k-buffer's merged tail): per sample, the weighted
  // premultiplied colour and weight sums, and the product of (1 - alpha)
  DView<float4> accum;
  DView<float> reveal;

  void release() { *this = BlendBuffers(); }
  size_t bytes() const {
    return viewBytes(totals) + viewBytes(maskStart) + viewBytes(blendStart) + viewBytes(count) + viewBytes(end) +
           viewBytes(frags) + viewBytes(slots) + viewBytes(accum) + viewBytes(reveal);
  }
};

}  // namespace rast
