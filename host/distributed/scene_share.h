// Sort-last rendering cuts the scene by geometry (docs/distributed.md): rank r
// of N draws a contiguous, balanced run of the drawn triangles, of the line
// segments and of the points, in the scene's primitive order, so that its
// primitive ids are a global id minus an offset and no rank holds the whole
// scene on its device. A share is a Scene of its own: draws that fall wholly
// in the run keep their mesh primitive (stored once, however many draws use
// it); a draw cut by the run's ends gets a primitive of just its part, with
// only the vertices that part uses. Compiled once; no MPI here.
#pragma once

#include "host/scene/scene.h"

#include <cstdint>
#include <vector>

namespace rast {

struct ShareRange {
  uint64_t t0 = 0, t1 = 0;  // drawn triangles [t0, t1)
  uint64_t l0 = 0, l1 = 0;  // drawn line segments
  uint64_t p0 = 0, p1 = 0;  // drawn points
};

// Every rank's range (balanced: sizes differ by at most one).
std::vector<ShareRange> planShares(uint64_t triangles, uint64_t lines, uint64_t points, int ranks);

// The part of `full` that draws `r`, with full's camera, look, materials,
// textures and file facts.
Scene takeShare(const Scene& full, const ShareRange& r);

}  // namespace rast
