// Sort-last compositing (docs/distributed.md): each rank draws its share of the
// scene (host/distributed/scene_share.h) and, between raster and shade, the
// ranks exchange visibility keys made global: depth bits << 32 | global
// primitive (or point/line item) + 1, which order exactly as the whole scene's
// keys do, so that their element-wise minimum is the single-device
// visibility buffer. Each rank then keeps the keys of the pixels whose winner
// it owns and shades them; the others' are cleared. After shading every
// output of a pixel not owned is zero, so a bitwise-or reduction merges the
// colour, the film and the AOVs on rank 0, bit for bit. MSAA pixels whose
// samples are won by several ranks ("mixed") are shaded per triangle by their
// owners into sample slots, and resolved on rank 0 in the single-device
// order (mixed_samples.cpp). Per execution space; the collective steps are
// host/distributed/ranks.h, staged through host memory, or NCCL on GPUs
// (nccl_composite.h) where the build has it. glTF BLEND surfaces are
// composited by rank 0 alone, which holds every BLEND draw whole, over the
// merged opaque film and the composited keys' depth (docs/distributed.md).
#pragma once

#include "host/distributed/scene_share.h"
#include "pipeline/distributed/nccl_composite.h"
#include "pipeline/frame/renderer.h"

#include <vector>

namespace rast {

// A failure every rank knows of (SortLast::agree): each rank ends with it,
// none waits for the others.
struct AgreedFailure : Error {
  using Error::Error;
};

// Device tables of the cut: every rank's first triangle, segment and point
// (size + 1 entries each), and this rank's place in them.
struct ShareTables {
  DView<uint64_t> tStart, lStart, pStart;
  int ranks = 1, me = 0;
  uint64_t T = 0, L = 0, P = 0;      // the whole scene's triangles, segments, points
  uint64_t t0 = 0, l0 = 0, p0 = 0;   // this rank's first of each
  uint32_t Tr = 0, Lr = 0, Pr = 0;   // this rank's counts
  // This rank's local triangles: its range's Tr, then (rank 0 of a scene with
  // BLEND draws) the BLEND triangles it holds whole beyond them, runs of
  // consecutive global triangles starting at runLocal(j) (scene_share.h).
  uint32_t Tl = 0;
  int runs = 0;
  DView<uint64_t> runLocal, runGlobal;
};

// What mixed MSAA pixels carry to rank 0 (mixed_samples.cpp).
struct MixedSamples {
  DView<uint32_t> at;      // per pixel: its mixed index (exclusive scan of the mixed flags)
  DView<float4> colour;    // per mixed pixel and sample: a triangle's shaded colour at its first sample
  DView<uint32_t> count;   // ... and the samples it covers (0: none starts there)
  uint32_t pixels = 0;
};

class SortLast : public FrameSplit {
 public:
  // blendWhole: rank 0's BLEND triangles beyond its range (takeShare);
  // sceneBlends: the whole scene draws BLEND triangles (drawsBlend).
  SortLast(const std::vector<ShareRange>& shares, int me, const std::vector<TriRun>& blendWhole = {},
           bool sceneBlends = false);
  ~SortLast() override;

  void agree(const std::string& error) override;
  bool all(bool ok) override;
  void afterRaster(const DeviceScene& s, FrameBuffers& f, const FramePlan& plan, const DView<LightGPU>& lights,
                   StageTimer* timer) override;
  void afterShade(const DeviceScene& s, FrameBuffers& f, const FramePlan& plan, const DView<LightGPU>& lights,
                  StageTimer* timer) override;
  bool holdsFrame() const override { return tables_.me == 0; }
  bool sceneBlends() const override { return sceneBlends_; }
  bool blendsHere() const override { return sceneBlends_ && tables_.me == 0; }
  const DView<uint64_t>& compositedKeys() const override { return global_; }
  // The composited keys and the ownership flags, their host staging on GPUs
  // without NCCL, the runs of BLEND triangles held whole, and MSAA's mixed index (its slots, sized by the frame, are not
  // known before it).
  uint64_t frameBytes(int width, int height, int samples) const override;

  // The last frame's exchange of keys and merge of outputs, wall milliseconds
  // on this rank (staging and waiting for the device included).
  double compositeMs() const { return compositeMs_; }
  double mergeMs() const { return mergeMs_; }
  const char* transport() const;

 private:
  template <class T>
  void merge(DView<T>& v, size_t n);
  // At the first frame, every rank in step: NCCL when every rank has it
  // (RAST_COMPOSITE=auto|nccl|mpi chooses), else MPI.
  void connect();

  bool connected_ = false;
  std::unique_ptr<NcclComposite> nccl_;

  ShareTables tables_;
  bool sceneBlends_ = false;
  DView<uint64_t> global_;  // the composited keys (n * samples)
  DView<uint8_t> flag_;     // per pixel: 0 another rank's, 1 this rank's, 2 mixed (MSAA)
  MixedSamples mixed_;
  std::vector<uint64_t> hostKeys_;    // staging (device backends)
  std::vector<uint32_t> hostWords_;
  double compositeMs_ = 0.0, mergeMs_ = 0.0;
};

// Mixed MSAA pixels (mixed_samples.cpp, compiled as the shade stage is).
uint32_t countMixed(const DView<uint8_t>& flag, MixedSamples& m, size_t pixels);
void shadeMixed(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights,
                const DView<uint8_t>& flag, MixedSamples& m);
void resolveMixed(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights,
                  const DView<uint8_t>& flag, const DView<uint64_t>& global, MixedSamples& m);

}  // namespace rast
