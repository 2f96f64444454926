// Sort-last rendering cuts the scene by geometry (docs/distributed.md): rank r
// of N draws a contiguous, balanced run of the drawn triangles, of the line
// segments and of the points, in the scene's primitive order, so that its
// primitive ids are a global id minus an offset and no rank holds the whole
// scene on its device. A share is a Scene of its own: draws that fall wholly
// in the run keep their mesh primitive (stored once, however many draws use
// it); a draw cut by the run's ends gets a primitive of just its part, with
// only the vertices that part uses. Compiled once; no MPI here.
//
// glTF BLEND draws are not cut (docs/distributed.md, "Transparency"): the first
// share, which holds the composited frame and composites the BLEND surfaces,
// keeps every BLEND draw whole, with all of its mesh primitive's vertices (so
// that its bounding box centre, the `sorted` method's key, is the whole
// scene's); the triangles this adds beyond its range are numbered after the
// range, in the scene's order, and TriRun maps them to global ids. The other
// shares keep the BLEND triangles of their range (they run no BLEND pass;
// their local triangle numbering is what makes ids global).
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

// Local triangles [local, local + count) of a share are the whole scene's
// drawn triangles [global, global + count).
struct TriRun {
  uint64_t local = 0, global = 0, count = 0;
};

// Whether a draw is a glTF BLEND one (its material's alphaMode, triangles only:
// what the transparency passes draw, pipeline/data/device_alpha.cpp).
bool isBlendDraw(const Scene& s, const Draw& d);
bool drawsBlend(const Scene& s);

// Every rank's range (balanced: sizes differ by at most one).
std::vector<ShareRange> planShares(uint64_t triangles, uint64_t lines, uint64_t points, int ranks);

// The part of `full` that draws `r`, with full's camera, look, materials,
// textures and file facts. With `blendWhole` (the first share only: r.t0 == 0),
// every BLEND draw is kept whole and the runs of triangles added beyond r's
// triangles are appended to *blendWhole.
Scene takeShare(const Scene& full, const ShareRange& r, std::vector<TriRun>* blendWhole = nullptr);

}  // namespace rast
