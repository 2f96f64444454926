// The CPU's shading paths, built on the fragment maths of pipeline/shade/:
// runs of pixels shaded as spans (rast::shade::spans, cpu/shade_spans.h), and
// the binned raster fused with shading per tile (rast::raster::binned::fine_shade).
// GPU builds compile these files but never instantiate the kernels; the frame
// plan asks spanShadeUsable / fusedBinnedShadeUsable before choosing them.
#pragma once

#include "pipeline/shade/shade.h"

namespace rast {

// Whether the span kernel covers a frame with these parameters (host backends
// only: false on GPUs).
bool spanShadeUsable(const FrameBuffers& f, const ShadeParams& p);
// The shade stage as spans of one triangle along a row; the same ids, depth
// and colours as shadeStage. Leaves the visibility buffer as it was.
void shadeSpansStage(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights);

// The binned raster and the shade stage in one pass on host backends: each
// tile is shaded as soon as its triangles are depth-tested, from the tile's
// depth and ids in cache, and no visibility buffer is written (f.vis is left
// as it was). Same ids, depth and colours as rasterBinned + shadeStage.
// Usable where the span kernel covers the frame and no points or lines are
// drawn afterwards into the visibility buffer.
bool fusedBinnedShadeUsable(const FrameBuffers& f, const ShadeParams& p, bool linesOrPoints);
void rasterBinnedShaded(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights);

}  // namespace rast
