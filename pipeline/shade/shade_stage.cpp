// The shade stage: colour, ids, depth (and the float film's inputs) per pixel
// from the visibility buffer, on every backend. The fragment shader is in
// shade_fragment.h; makeShade fills its parameters and allocates its outputs
// for this kernel and for the CPU's span and fused tile shading
// (pipeline/cpu/), which the frame plan chooses instead on host backends.
#include "pipeline/shade/pbr_fragment.h"
#include "pipeline/rules/visbuffer_blocks.h"
#include "pipeline/data/test_hooks.h"

namespace rast {
namespace {

using shading::Shade;

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

// The per-pixel kernel, which clears the visibility buffer behind it
// (FrameBuffers::visClear).
// The GPU's layout (a warp shades a 32-pixel-wide tile, kShadeInterleave rows),
// with one sample a pixel and runs of one pixel.
bool interleavedLayout(int run, int samples) { return kShadeInterleave > 1 && run == 1 && samples == 1; }

// The glTF shading's kernel (pbr_fragment.h) for the scene's features,
// compiled in the layout of the backend (rows on CPUs, columns on GPUs).
// Every instance launches lightweight on a GPU, as the lit kernel does (its
// functor in the kernel's parameters, its frames replayed from a recording:
// backends/frame_graphs.h): nothing in them takes the functor's address,
// which would make every thread copy the 2.2 KB functor to its stack first
// (docs/cuda.md). The CUDA 11.8 build for sm_90 (`cuobjdump -res-usage`):
// STACK 0 bytes for the instances without texture coordinates, 400 to 416
// for the textured ones (their material's texels, Shade::materialTexels);
// 2,416 to 2,440 when they sampled each texture at its own call site and
// nvcc left the kernel's body out of line (they launched heavyweight then).
template <int kFeat>
void launchPbrWith(const Shade& k, const Range& items) {
  using Bounded = Kokkos::RangePolicy<Exec, Kokkos::LaunchBounds<kShadeLaunchBounds[0], kShadeLaunchBounds[1]>>;
  const Bounded policy(items.begin(), items.end());
  // A CPU's one instance checks for the BLEND composite (a predictable
  // branch a pixel); a GPU's opaque frames take one without it.
  if constexpr (kOnDevice) {
    if (!k.blendComposite.data()) {
      Kokkos::parallel_for("rast::shade::pbr", lightweight(policy), shading::ShadePbr<kFeat, true, false>{k});
      return;
    }
  }
  Kokkos::parallel_for("rast::shade::pbr", lightweight(policy), shading::ShadePbr<kFeat, kOnDevice, true>{k});
}

void launchPbr(const Shade& k, const Range& items) {
  using shading::kPbrBaseTexture;
  using shading::kPbrClearcoat;
  using shading::kPbrEnv;
  using shading::kPbrPunctual;
  using shading::kPbrTextured;
  // A scene with a clear coat takes the one instance that draws it (the
  // other features read at run time: see PbrFeature).
  if (k.hasClearcoat) return launchPbrWith<kPbrClearcoat>(k, items);
  // Scenes whose only textures are base colours (the three textured shared
  // models are) sample that one texture without the loop over the slots: on
  // the H100 the loop and its texel array cost those models about as much as
  // the sampler's derivatives and level of detail, and more than the glTF
  // BRDF (docs/performance.md).
  constexpr int kBase = kPbrTextured | kPbrBaseTexture;
  switch ((k.hasUV ? (k.baseTexturesOnly ? kBase : kPbrTextured) : 0) | (k.p.useEnv ? kPbrEnv : 0) |
          (k.numPunctual > 0 ? kPbrPunctual : 0)) {
    case 0: return launchPbrWith<0>(k, items);
    case kPbrTextured: return launchPbrWith<kPbrTextured>(k, items);
    case kPbrEnv: return launchPbrWith<kPbrEnv>(k, items);
    case kPbrTextured | kPbrEnv: return launchPbrWith<kPbrTextured | kPbrEnv>(k, items);
    case kPbrPunctual: return launchPbrWith<kPbrPunctual>(k, items);
    case kPbrTextured | kPbrPunctual: return launchPbrWith<kPbrTextured | kPbrPunctual>(k, items);
    case kPbrEnv | kPbrPunctual: return launchPbrWith<kPbrEnv | kPbrPunctual>(k, items);
    case kPbrTextured | kPbrEnv | kPbrPunctual: return launchPbrWith<kPbrTextured | kPbrEnv | kPbrPunctual>(k, items);
    case kBase: return launchPbrWith<kBase>(k, items);
    case kBase | kPbrEnv: return launchPbrWith<kBase | kPbrEnv>(k, items);
    case kBase | kPbrPunctual: return launchPbrWith<kBase | kPbrPunctual>(k, items);
    default: return launchPbrWith<kBase | kPbrEnv | kPbrPunctual>(k, items);
  }
}

// Whether the glTF shading's kernel shades a frame: the glTF shading at one
// sample a pixel, in the backend's own layout (a run of one pixel on GPUs).
bool takesPbrKernel(const ShadeParams& p, int samples, bool interleaved) {
  return p.mode == ShadingMode::Pbr && samples == 1 && interleaved == kOnDevice && !testHooks().generalShade;
}

void launchShade(Shade k, const Range& items) {
  k.clearVis = 1;
  if (takesPbrKernel(k.p, k.samples.count, k.interleaved != 0)) {
    launchPbr(k, items);
    return;
  }
  // On a GPU the fragment shader keeps one triangle's data (TriFrag) live:
  // unbounded, ptxas gives it 166 registers a thread, too few warps to hide the
  // loads of a latency-bound kernel. kShadeLaunchBounds caps that (host
  // backends ignore launch bounds).
  using Bounded = Kokkos::RangePolicy<Exec, Kokkos::LaunchBounds<kShadeLaunchBounds[0], kShadeLaunchBounds[1]>>;
  // Lit frames (the usual ones) take a kernel compiled without the other
  // modes' code: a third of the general kernel's instructions (1,617 against
  // 5,488 in its SASS), with fewer branches a pixel; the H100's frames were
  // 1-4% faster (milktruck_cab 0.1626 -> 0.1566 ms, engine 0.1286 -> 0.1246;
  // docs/journal/performance-2026-11-*.md). The same arithmetic: the same bytes. It is built
  // twice, with and without vertex colours, so that a scene without them
  // (every benchmark model) keeps no registers for them.
  const bool lit = k.interleaved && k.litOnly() && !testHooks().generalShade;
  if (lit && k.hasColor)
    Kokkos::parallel_for("rast::shade::lit", lightweight(Bounded(items.begin(), items.end())),
                         shading::ShadeInterleaved<true, 1>{k});
  else if (lit)
    Kokkos::parallel_for("rast::shade::lit", lightweight(Bounded(items.begin(), items.end())),
                         shading::ShadeInterleaved<true, 0>{k});
  else if (k.interleaved)
    Kokkos::parallel_for("rast::shade", heavyweight(Bounded(items.begin(), items.end())), shading::ShadeInterleaved<false>{k});
  else
    Kokkos::parallel_for("rast::shade", heavyweight(Bounded(items.begin(), items.end())), k);
}

}  // namespace

shading::Shade makeShade(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights) {
  using shading::Shade;
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
  // Filled by name: the functor has some thirty members.
  Shade k{};
  k.draws = s.draws;
  k.drawTriStart = s.drawTriStart;
  k.indices = s.indices;
  k.triDraw = s.triDraw;
  k.uvs = s.uvs;
  k.colors = s.colors;
  k.tangents = s.tangents;
  k.uvs1 = s.uvs1;
  k.hasUV1 = s.hasUV1 ? 1 : 0;
  k.baseTexturesOnly = s.baseTexturesOnly ? 1 : 0;
  k.hasTangent = s.hasTangents ? 1 : 0;
  k.materials = s.materials;
  k.clearcoats = s.clearcoats;
  k.hasClearcoat = s.hasClearcoat ? 1 : 0;
  k.textures = s.textures;
  k.texels = s.texels;
  k.lut = s.srgbToLinear;
  k.unorm = s.unormToFloat;
  k.punctual = s.lights;
  k.numPunctual = int32_t(s.lights.extent(0));
  k.encodePacked = s.srgbEncodePacked;
  k.numDraws = s.numDraws;
  k.hasUV = s.hasUV ? 1 : 0;
  k.hasColor = s.hasColor ? 1 : 0;
  k.tris = f.tris;
  k.vis = f.vis;
  k.worldPos = f.worldPos;
  k.worldNormal = f.worldNormal;
  k.color = f.color;
  k.depthOut = f.depth;
  k.primOut = f.primId;
  k.normalOut = f.normal;
  k.hdr = f.post.hdr;
  k.geom = f.post.geom;
  k.viewDepth = f.post.depth;
  k.lights = lights;
  k.depthRange = f.depthRange;
  k.width = f.vp.width;
  k.samples = f.vp.samples;
  k.p = p;
  k.lineShade = makeLineShade(s, f.lines);
  // Runs of kShadeRun pixels along a row (the last run of a row may be shorter).
  k.run = p.shadeRun > 0 ? p.shadeRun : kShadeRun;
  k.runsPerRow = (f.vp.width + k.run - 1) / k.run;
  k.height = f.vp.height;
  k.interleaved = interleavedLayout(k.run, f.vp.samples.count);
  k.blockFrame = f.blockFrame;
  k.blockDepth = f.blockDepth;
  const uint32_t numBlocks = visBlocks(f.vp, k.blocksPerRow);
  k.resetBlocks = f.blockDepth.data() && f.blockDepth.extent(0) >= numBlocks ? 1 : 0;
  return k;
}

bool shadeLaunchesLightweight(const ShadeParams& p, int samples) {
  shading::Shade k{};
  k.p = p;
  k.run = p.shadeRun > 0 ? p.shadeRun : kShadeRun;
  const bool interleaved = interleavedLayout(k.run, samples);
  return (interleaved && k.litOnly() && !testHooks().generalShade) || takesPbrKernel(p, samples, interleaved);
}

bool shadeWritesOpaqueDepth(const ShadeParams& p, int samples) {
  const int run = p.shadeRun > 0 ? p.shadeRun : kShadeRun;
  return takesPbrKernel(p, samples, interleavedLayout(run, samples));
}

void shadeStage(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights,
                const ShadeBlend& blend) {
  Shade k = makeShade(s, f, p, lights);
  // (Asked only where shadeWritesOpaqueDepth, launchShade's own choice.)
  k.opaqueDepth = blend.opaqueDepth;
  k.blendComposite = blend.composite;
  k.blendFrags = blend.frags;
  k.blendBlocksX = blendBlocks(f.vp.width);
  k.blendEncode = blend.encode ? 1 : 0;
  k.blendRaw = blend.raw ? 1 : 0;
  k.blendStraight = blend.straight ? 1 : 0;
  k.blendFilmless = blend.filmless ? 1 : 0;
  launchShade(k, Range(0, k.workItems()));
  f.visClear = true;
}

}  // namespace rast
