// The work items of the alpha classes' passes (docs/transparency.md): the
// 8x8 blocks of a raster triangle's pixel box. Here, below the setup and the
// blend passes, because both number them: the blend passes walk them, and on
// a GPU the setup's single-pass scan numbers the BLEND class's (so that no
// scan of its own follows it).
#pragma once

#include "pipeline/data/blend_buffers.h"
#include "pipeline/rules/raster_rules.h"

namespace rast {

// A raster triangle's box in items (8x8 blocks) and pixels.
struct ItemBox {
  int32_t minX, maxX, minY, maxY, bx0, by0, bw;
  uint32_t items;
};

KOKKOS_INLINE_FUNCTION ItemBox itemBox(const RasterTri& t, const Viewport& vp) {
  ItemBox b;
  pixelBox(t, vp, b.minX, b.maxX, b.minY, b.maxY);
  b.bx0 = b.minX >> kBlendBlockShift;
  b.by0 = b.minY >> kBlendBlockShift;
  b.bw = (b.maxX >> kBlendBlockShift) - b.bx0 + 1;
  const int32_t bh = (b.maxY >> kBlendBlockShift) - b.by0 + 1;
  b.items = b.minX <= b.maxX && b.minY <= b.maxY ? uint32_t(b.bw) * uint32_t(bh) : 0u;
  return b;
}

// The work items raster triangle t adds to alpha class cls's list: its box's
// when it is of that class, else none.
KOKKOS_INLINE_FUNCTION uint32_t classItems(const RasterTri& t, const Viewport& vp, int32_t cls) {
  return alphaClassOf(t) == cls ? itemBox(t, vp).items : 0u;
}

}  // namespace rast
