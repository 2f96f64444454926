// FrameBuffers::bytes (frame_buffers.h): what the frame holds on the device,
// for the memory budget and `rast bench`'s report.
#include "pipeline/data/frame_buffers.h"

namespace rast {

size_t FrameBuffers::bytes() const {
  return viewBytes(uploaded) + viewBytes(clip) + viewBytes(snap) + viewBytes(worldPos) + viewBytes(worldNormal) + viewBytes(chunkOffset) + viewBytes(chunkBlocks) + viewBytes(setupStatus) + viewBytes(clipCount) + viewBytes(clipBlocks) +
         viewBytes(tris) + viewBytes(workOffset) + viewBytes(workHint) + viewBytes(blockDepth) + viewBytes(blockFrame) + viewBytes(occCount) + viewBytes(occStart) + viewBytes(occTri) + viewBytes(work) + viewBytes(tileStart) + viewBytes(accum) + viewBytes(counters) + viewBytes(vis) +
         viewBytes(color) + viewBytes(depth) + viewBytes(primId) + viewBytes(normal) + lines.bytes() + post.bytes() + blend.bytes();
}

}  // namespace rast
