// What a frame's point/line pass draws (LinePass) and the device buffers it
// uses (LineFrame): plain data, kept apart from the point and line rules
// (pipeline/raster/raster_lines.h) so that FrameBuffers can hold them without
// the data layer depending on a raster method. The key space these items
// number is described in raster_lines.h.
#pragma once

#include "pipeline/data/device.h"
#include "pipeline/data/gpu_types.h"

namespace rast {

constexpr uint32_t kLineFlag = 0x80000000u;
constexpr int32_t kLineSpan = 32;      // major-axis pixels per line work item
constexpr float kMaxLineWidth = 64.0f;  // also the maximum point size
// Hidden-line wireframe: edges win over the fill they lie on when their window
// depth is within this fraction of (1 - depth), i.e. about 0.4% of the eye
// distance under a perspective projection; enough for surfaces up to about 80
// degrees from facing the camera at the default field of view.
constexpr float kHiddenLineBias = 0.004f;

// What a frame's point/line pass draws (per frame, by value into kernels).
struct LinePass {
  uint32_t numLines = 0, numPoints = 0, numTris = 0;  // key space layout
  int32_t edges = 0;    // 0: none, 1: polygon mode line, 2: overlay on top, 3: overlay, hidden-line
  int32_t corners = 0;  // 1: polygon mode point
  int32_t width = kSubOne;  // line width, 1/256 pixel
  int32_t size = kSubOne;   // point size, 1/256 pixel
  int32_t cullBack = 0;
  uint32_t lineItems() const { return numLines + (edges ? 3 * numTris : 0); }
  uint32_t pointItems() const { return numPoints + (corners ? 3 * numTris : 0); }
  // Key index of line item k (segments, then edges) and point item k (points, then corners).
  KOKKOS_INLINE_FUNCTION uint32_t lineKey(uint32_t k) const { return k < numLines ? k : numLines + numPoints + (k - numLines); }
  KOKKOS_INLINE_FUNCTION uint32_t pointKey(uint32_t k) const {
    return k < numPoints ? numLines + k : numLines + numPoints + 3 * numTris + (k - numPoints);
  }
};

// Device buffers of the pass.
struct LineFrame {
  LinePass pass;
  DView<uint32_t> lineOffset, pointOffset;  // per item: work items, then their exclusive prefix sum
  DView<uint32_t> counters;                 // [0]: line spans, [1]: point rows
  size_t bytes() const { return viewBytes(lineOffset) + viewBytes(pointOffset) + viewBytes(counters); }
};

}  // namespace rast
