// The shade stage: colour, ids, depth (and the float film's inputs) per pixel
// from the visibility buffer. The fragment shader is in shade_fragment.h; on
// the CPU, runs of pixels of one triangle go through shade_spans.h.
#include "shade_fragment.h"
#include "raster_binned.h"
#include "shade_spans.h"

#include <type_traits>

namespace rast {
namespace {

using shading::Shade;

bool generalShadeForTests = false;  // setGeneralShadeForTests


// Eye-space depth range of the covered pixels, reduced on the device (depth mode).
struct DepthRange {
  DView<uint64_t> vis;
  DView<FrameUniforms> frame;
  int samples;
  KOKKOS_INLINE_FUNCTION void operator()(const int64_t i, Kokkos::MinMaxScalar<float>& v) const {
    const uint64_t key = vis(i * samples);
    if ((key & 0xffffffffu) == 0) return;
    const float znear = frame(0).camera.znear, zfar = frame(0).camera.zfar;
    const float zn = 2.0f * bitsFloat(uint32_t(key >> 32)) - 1.0f;
    const float ze = 2.0f * znear * zfar / ((zfar + znear) - zn * (zfar - znear));
    v.min_val = ze < v.min_val ? ze : v.min_val;
    v.max_val = ze > v.max_val ? ze : v.max_val;
  }
};

// The span kernel (shade_spans.h) is compiled for the host backends only: a
// GPU shades a few pixels per thread and never launches it. Returns whether
// the kernel clears the visibility buffer behind it (only the per-pixel one:
// on a CPU the fused binned path, which writes no keys, is the common one).
template <bool kWithSpans>
bool launchShade(Shade k, int samples, const Range& items) {
  if constexpr (kWithSpans) {
    using Spans = std::conditional_t<kWithSpans, shading::ShadeSpans, Shade>;  // dependent: not built for GPUs
    if (Spans::usable(k.p, samples, k.run)) {
      Kokkos::parallel_for("rast::shade::spans", lightweight(items), Spans{k});
      return false;
    }
  }
  k.clearVis = 1;
  // On a GPU the fragment shader keeps one triangle's data (TriFrag) live:
  // unbounded, ptxas gives it 166 registers a thread, too few warps to hide the
  // loads of a latency-bound kernel. kShadeLaunchBounds caps that (host
  // backends ignore launch bounds).
  using Bounded = Kokkos::RangePolicy<Exec, Kokkos::LaunchBounds<kShadeLaunchBounds[0], kShadeLaunchBounds[1]>>;
  // Lit frames (the usual ones) take a kernel compiled without the other
  // modes' code: a third of the general kernel's instructions (1,617 against
  // 5,488 in its SASS), with fewer branches a pixel; the H100's frames were
  // 1-4% faster (milktruck_cab 0.1626 -> 0.1566 ms, engine 0.1286 -> 0.1246;
  // docs/performance.md). The same arithmetic: the same bytes. It is built
  // twice, with and without vertex colours, so that a scene without them
  // (every benchmark model) keeps no registers for them.
  const bool lit = k.interleaved && k.litOnly() && !generalShadeForTests;
  if (lit && k.hasColor)
    Kokkos::parallel_for("rast::shade::lit", lightweight(Bounded(items.begin(), items.end())),
                         shading::ShadeInterleaved<true, 1>{k});
  else if (lit)
    Kokkos::parallel_for("rast::shade::lit", lightweight(Bounded(items.begin(), items.end())),
                         shading::ShadeInterleaved<true, 0>{k});
  else if (k.interleaved)
    Kokkos::parallel_for("rast::shade", lightweight(Bounded(items.begin(), items.end())), shading::ShadeInterleaved<false>{k});
  else
    Kokkos::parallel_for("rast::shade", lightweight(Bounded(items.begin(), items.end())), k);
  return true;
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
bool launchFused(const Shade& k, FrameBuffers& f) {
  if constexpr (kHost) {
    using Fine = std::conditional_t<kHost, FineRasterHost<ShadeSink>, void>;  // dependent: not built for GPUs
    const BinGeometry g = binTriangles(f);
    // Tiles cost what they hold (background is cheap): handed out dynamically.
    using Policy = Kokkos::RangePolicy<Exec, Kokkos::Schedule<Kokkos::Dynamic>, Kokkos::IndexType<uint32_t>>;
    Kokkos::parallel_for("rast::raster::binned::fine_shade", Policy(0, g.numTiles()),
                         Fine{f.tris, f.tileStart, f.work, f.counters, g, f.vp.width, f.vp.height, f.workCapacity,
                              ShadeSink{shading::ShadeSpans{k}}});
    return true;
  }
  return false;
}

// Everything shadeStage allocates and the functor it launches.
Shade makeShade(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights);

}  // namespace

bool fusedBinnedShadeUsable(const FrameBuffers& f, const ShadeParams& p, bool linesOrPoints) {
  const int run = p.shadeRun > 0 ? p.shadeRun : kShadeRun;
  return !kOnDevice && kTeamSize == 1 && !linesOrPoints && shading::ShadeSpans::usable(p, f.vp.samples.count, run);
}

void rasterBinnedShaded(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights) {
  const Shade k = makeShade(s, f, p, lights);
  if (!launchFused<!kOnDevice>(k, f)) throw Error("internal: the fused binned raster and shade runs on host backends only");
}

namespace {

Shade makeShade(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights) {
  const int64_t n = int64_t(f.vp.width) * f.vp.height;
  ensureCapacity(f.color, "frame.color", size_t(n));
  if (p.wantDepth) ensureCapacity(f.depth, "frame.depth", size_t(n));
  if (p.wantPrimId) ensureCapacity(f.primId, "frame.primId", size_t(n));
  if (p.wantNormals) ensureCapacity(f.normal, "frame.normal", size_t(n));
  if (p.floatOut) ensureCapacity(f.post.hdr, "post.hdr", size_t(n));
  if (p.wantGeom) {
    ensureCapacity(f.post.geom, "post.geom", size_t(n));
    ensureCapacity(f.post.depth, "post.depth", size_t(n));
  }
  if (p.mode == ShadingMode::Depth) {
    if (!f.depthRange.data()) f.depthRange = allocScalar<Kokkos::MinMaxScalar<float>>("frame.depthRange");
    Kokkos::parallel_reduce("rast::shade::depth_range", Range(0, n), DepthRange{f.vis, p.frame, f.vp.samples.count},
                            Kokkos::MinMax<float, Mem>(f.depthRange));
  }
  Shade k{s.draws, s.drawTriStart, s.indices, s.triDraw, s.uvs, s.colors, s.materials, s.textures, s.texels, s.srgbToLinear, s.srgbEncodePacked,
          s.numDraws, s.hasUV ? 1 : 0, s.hasColor ? 1 : 0, f.tris, f.vis, f.worldPos, f.worldNormal, f.color,
          f.depth, f.primId, f.normal, f.post.hdr, f.post.geom, f.post.depth, lights, f.depthRange, f.vp.width, f.vp.samples, p,
          makeLineShade(s, f.lines), 1, 1};
  // Runs of kShadeRun pixels along a row (the last run of a row may be shorter).
  k.run = p.shadeRun > 0 ? p.shadeRun : kShadeRun;
  k.runsPerRow = (f.vp.width + k.run - 1) / k.run;
  k.height = f.vp.height;
  k.interleaved = kShadeInterleave > 1 && k.run == 1 && f.vp.samples.count == 1;
  k.blockFrame = f.blockFrame;
  k.blockDepth = f.blockDepth;
  const uint32_t numBlocks = visBlocks(f.vp, k.blocksPerRow);
  k.resetBlocks = f.blockDepth.data() && f.blockDepth.extent(0) >= numBlocks ? 1 : 0;
  return k;
}

}  // namespace

void setGeneralShadeForTests(bool general) { generalShadeForTests = general; }

void shadeStage(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights) {
  const Shade k = makeShade(s, f, p, lights);
  f.visClear = launchShade<!kOnDevice>(k, f.vp.samples.count, Range(0, k.workItems()));
}

}  // namespace rast
