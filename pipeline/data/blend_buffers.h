// The buffers of the transparency passes (pipeline/blend/, docs/transparency.md):
// the per-class work lists of MASK and BLEND raster triangles, the exact and
// sorted methods' tile lists, the k-buffer and the weighted method's sums. Each
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
  kBlendFrags = 2,    // exact and sorted: fragments in front of the opaque depth this frame
  kBlendMaxDepth = 3, // most fragments of one sample (the depth complexity `auto` reads)
  kBlendListed = 4,   // entries of the tile lists this frame (their need)
  kBlendLongest = 5,  // the longest tile list this frame (the next frame's team scratch)
  kBlendWalked = 6,   // the team form under the glTF shading: the blocks in walkedBlocks
  kBlendMerged = 7,   // the long lists' kernel: the blocks whose overlapping list it merged in one walk
  kNumBlendTotals = 8
};

// The tile lists' blocks: 8x8 pixels (blending::kItemShift).
constexpr int32_t kBlendBlockShift = 3;
// Blocks across `pixels` pixels (a partial block at the end counts): the
// frame's blocks are blendBlocks(width) x blendBlocks(height), numbered row
// by row, in every pass that indexes them.
KOKKOS_INLINE_FUNCTION int32_t blendBlocks(const int32_t pixels) {
  return (pixels + (1 << kBlendBlockShift) - 1) >> kBlendBlockShift;
}
// The block of pixel (X, Y) in a frame blocksX = blendBlocks(width) across.
KOKKOS_FORCEINLINE_FUNCTION int64_t blendBlockOf(const int32_t X, const int32_t Y, const int32_t blocksX) {
  return int64_t(Y >> kBlendBlockShift) * blocksX + (X >> kBlendBlockShift);
}

// Raises a 64-bit statistic (a slot of BlendBuffers::totals) to at least v.
// A plain read first (most threads raise nothing), then the hardware's
// maximum: Kokkos (desul) maps a 64-bit one to it for unsigned long long
// only, and uint64_t's is a compare-and-swap loop, on which a frame's
// threads, all running at once, would queue.
KOKKOS_FORCEINLINE_FUNCTION void raiseTotal(uint64_t& total, const uint64_t v) {
  static_assert(sizeof(unsigned long long) == sizeof(uint64_t), "the totals are 64-bit");
  if (v > total)
    Kokkos::atomic_fetch_max(reinterpret_cast<unsigned long long*>(&total), static_cast<unsigned long long>(v));
}
// BlendBuffers::blockFrags' value for a block the team walks.
constexpr uint32_t kUniformWalk = ~0u;

struct BlendBuffers {
  DView<uint64_t> totals;            // BlendTotal
  DView<uint64_t> maskStart, blendStart;  // per raster triangle: its first work item (exclusive scan)
  // exact / sorted (blend_tiles.cpp): per 8x8 block the count of its list,
  // and its end in `tileTris` after the fill (start = end - count); the
  // lists (raster triangle indices, 4 bytes an entry, grown to the frame's
  // need by Renderer::lastFrameFit); per sample the opaque depth's bits
  // (shading clears the visibility buffer before the resolve reads them)
  DView<uint32_t> tileCount, tileEnd, tileTris, opaque;
  // The team form under the glTF shading (pipeline/blend/uniform_blocks.h):
  // per 8x8 block the composite where it is uniform (premultiplied colour
  // and transmittance), and its fragments a sample (kUniformWalk where the
  // team walks it); the blocks that the team walks (totals(kBlendWalked) of them)
  DView<float4> blockComposite;
  DView<uint32_t> blockFrags, walkedBlocks;
  uint64_t tileCapacity = 0;
  // The frame's layout of the lists: 0 counted (a block's list ends at
  // tileEnd), else strided (it starts at block x listStride; listStrideFor)
  uint32_t listStride = 0;
  uint64_t longestList = 0;  // the last frame's kBlendLongest, read on the host (the resolve's scratch size)
  // kbuffer: k keys per sample, nearest first
  DView<uint64_t> slots;
  int k = 0;
  // weighted (and the k-buffer's merged tail): per sample, the weighted
  // premultiplied colour and weight sums, and the product of (1 - alpha)
  DView<float4> accum;
  DView<float> reveal;

  void release() { *this = BlendBuffers(); }
  size_t bytes() const {
    return viewBytes(totals) + viewBytes(maskStart) + viewBytes(blendStart) + viewBytes(tileCount) + viewBytes(tileEnd) +
           viewBytes(tileTris) + viewBytes(opaque) + viewBytes(blockComposite) +
           viewBytes(blockFrags) + viewBytes(walkedBlocks) + viewBytes(slots) + viewBytes(accum) + viewBytes(reveal);
  }
};

}  // namespace rast
