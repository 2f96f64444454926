// An exclusive prefix sum over a device buffer, with its total left on the
// device: the setup's chunk offsets, the binned raster's bins and the
// point/line pass's spans all number their outputs this way, so it sits with
// the buffers, below every stage that uses it.
#pragma once

#include "pipeline/data/device.h"

namespace rast {

// Exclusive prefix sum of data[0, n) in place; the total goes to counters(slot)
// on the device.
void scanExclusive(const char* label, const DView<uint32_t>& data, uint32_t n, const DView<uint32_t>& counters,
                   int slot);

}  // namespace rast
