// The CPU's shading paths (cpu_shade.h): the span kernel and the binned raster
// fused with it. Both are compiled for every backend but instantiated for the
// host backends only (a dependent type keeps GPU builds from building them: a
// GPU shades a few pixels per thread, pipeline/shade/shade_stage.cpp).
#include "pipeline/cpu/cpu_shade.h"

#include "pipeline/cpu/shade_spans.h"
#include "pipeline/raster/raster_binned.h"

#include <type_traits>

namespace rast {
namespace {

using shading::Shade;

template <bool kHost>
void launchSpans(const Shade& k, const Range& items) {
  if constexpr (kHost) {
    using Spans = std::conditional_t<kHost, shading::ShadeSpans, Shade>;  // dependent: not built for GPUs
    Kokkos::parallel_for("rast::shade::spans", lightweight(items), Spans{k});
  }
}

// The fused binned raster's sink: a finished tile's rows shaded at once.
struct ShadeSink {
  shading::ShadeSpans spans;
  KOKKOS_INLINE_FUNCTION void tile(int32_t tx0, int32_t ty0, int32_t w, int32_t h, const uint32_t* zb,
                                   const uint32_t* ib) const {
    spans.shadeTile(tx0, ty0, w, h, kTileSize, ib, zb);
  }
  KOKKOS_INLINE_FUNCTION void emptyTile(int32_t tx0, int32_t ty0, int32_t w, int32_t h) const {
    spans.shadeEmpty(tx0, ty0, w, h);
  }
};

template <bool kHost>
void launchFused(const Shade& k, FrameBuffers& f) {
  if constexpr (kHost) {
    using Fine = std::conditional_t<kHost, FineRasterHost<ShadeSink>, void>;  // dependent: not built for GPUs
    const BinGeometry g = binTriangles(f);
    // Tiles cost what they hold (background is cheap): handed out dynamically.
    using Policy = Kokkos::RangePolicy<Exec, Kokkos::Schedule<Kokkos::Dynamic>, Kokkos::IndexType<uint32_t>>;
    Kokkos::parallel_for("rast::raster::binned::fine_shade", Policy(0, g.numTiles()),
                         Fine{f.tris, f.tileStart, f.work, f.counters, g, f.vp.width, f.vp.height, f.workCapacity,
                              ShadeSink{shading::ShadeSpans{k}}});
  }
}

int shadeRunOf(const ShadeParams& p) { return p.shadeRun > 0 ? p.shadeRun : kShadeRun; }

}  // namespace

bool spanShadeUsable(const FrameBuffers& f, const ShadeParams& p) {
  return !kOnDevice && shading::ShadeSpans::usable(p, f.vp.samples.count, shadeRunOf(p));
}

void shadeSpansStage(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights) {
  if (!spanShadeUsable(f, p)) throw Error("internal: the span shading runs on host backends, for frames it covers");
  const Shade k = makeShade(s, f, p, lights);
  launchSpans<!kOnDevice>(k, Range(0, k.workItems()));
  f.visClear = false;  // the span kernel leaves the keys (the fused path, the usual one, writes none)
}

bool fusedBinnedShadeUsable(const FrameBuffers& f, const ShadeParams& p, bool linesOrPoints) {
  return !kOnDevice && kTeamSize == 1 && !linesOrPoints && shading::ShadeSpans::usable(p, f.vp.samples.count, shadeRunOf(p));
}

void rasterBinnedShaded(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights) {
  if (!fusedBinnedShadeUsable(f, p, false))
    throw Error("internal: the fused binned raster and shade runs on host backends only");
  const Shade k = makeShade(s, f, p, lights);
  launchFused<!kOnDevice>(k, f);
}

}  // namespace rast
