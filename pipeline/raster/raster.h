// The raster stage's front: one entry per raster method (naive, visbuffer,
// binned), the clear and the statistics that `auto` reads. Every method
// min-combines the same 64-bit depth|id keys into FrameBuffers::vis, so they
// are interchangeable bit for bit; the frame plan (pipeline/frame/frame_plan.h)
// picks one. Points and lines have their own front, raster_lines.h.
#pragma once

#include "pipeline/data/frame_buffers.h"

namespace rast {

void clearVisibility(FrameBuffers& f);

// Raster methods: each reads f.tris / f.counters(kRasterTris) and min-combines
// visKey values into f.vis. All produce bit-identical visibility buffers.
void rasterNaive(FrameBuffers& f);
// occluders: large triangles first lower the depth bounds of the blocks they
// cover whole (raster_visbuffer.cpp), for frames of high depth complexity;
// the setup must have been told too (primitiveSetup). rowLanes: a block's
// rows on consecutive lanes (RasterBlockRows), for frames of large triangles
// (Renderer::useRowLanes); the same keys either way.
void rasterVisBuffer(FrameBuffers& f, bool occluders, bool rowLanes = false);
void rasterBinned(FrameBuffers& f);  // writes every pixel: needs no clearVisibility

// Cheap statistics of the raster triangles (sum and maximum of their pixel
// bounding-box areas, and the summed area of the occluder candidates) into
// f.sumArea / f.maxArea / f.occArea, for choosing a method.
void rasterStatistics(FrameBuffers& f);

}  // namespace rast
