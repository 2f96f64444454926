// planFrame (frame_plan.h): every per-frame decision in one place, in the
// order they depend on each other: method, then its options, then the shading
// path, then the key.
#include "pipeline/frame/frame_plan.h"

#include "base/color.h"
#include "pipeline/data/test_hooks.h"
#include "pipeline/raster/raster_lines.h"

namespace rast {

RasterMethod chooseMethod(const RenderSettings& rs, const AutoStats& stats) {
  switch (rs.raster) {
    case RasterMethod::Naive:
    case RasterMethod::VisBuffer:
    case RasterMethod::Binned:
      return rs.raster;
    case RasterMethod::Auto:
      break;
  }
  // Thresholds per kind of machine: backends/tuning.h.
  // Without statistics yet (first frame): a method with bounded work per item.
  if (!stats.valid) return kPreferVisBuffer ? RasterMethod::VisBuffer : RasterMethod::Binned;
  // Nothing to draw: on a GPU naive has the fewest launches (0.043 against
  // visbuffer's 0.053 ms for an empty 1080p frame on the H100); a CPU's
  // binned shades its tiles directly.
  if (stats.tris == 0) return kPreferVisBuffer ? RasterMethod::Naive : RasterMethod::Binned;
  // Only small triangles: one work item per triangle walking its box is the
  // cheapest (no expansion into blocks or bins).
  if (stats.maxArea <= kNaiveMaxBoxArea) return RasterMethod::Naive;
  return kPreferVisBuffer ? RasterMethod::VisBuffer : RasterMethod::Binned;
}

Transparency chooseTransparency(const RenderSettings& rs, bool fallback) {
  switch (rs.transparency) {
    case Transparency::Weighted:
    case Transparency::KBuffer:
      return rs.transparency;
    case Transparency::Exact:
    case Transparency::Sorted:
      return fallback ? Transparency::KBuffer : rs.transparency;
    case Transparency::Auto:
      break;
  }
  return fallback ? Transparency::KBuffer : Transparency::Exact;
}

namespace {

// The visbuffer's occluder pass (raster_visbuffer.cpp) pays where large
// triangles lie in layers: `auto` runs it when its candidates' summed area
// reaches kOccluderMinLayers frames (backends/tuning.h); an explicit
// visbuffer always runs it. Single-sample frames only.
bool useOccluders(const RenderSettings& rs, const FramePlan& p, const AutoStats& stats) {
  if (p.method != RasterMethod::VisBuffer || !p.fill || p.samples != 1) return false;
  if (rs.raster != RasterMethod::Auto) return true;
  return stats.valid && double(stats.occArea) >= kOccluderMinLayers * double(rs.width) * double(rs.height);
}

// The visbuffer raster's layout with a block's row on lanes (raster_visbuffer.cpp):
// on GPUs under `auto`, for frames whose raster triangles' mean bounding box
// reaches kRowLanesMinBoxArea without the occluder pass (backends/tuning.h).
// Tests may ask for it on any backend (TestHooks::rowLanes).
bool useRowLanes(const RenderSettings& rs, const FramePlan& p, const AutoStats& stats) {
  if (p.method != RasterMethod::VisBuffer || !p.fill || p.samples != 1) return false;
  if (testHooks().rowLanes != 0) return testHooks().rowLanes > 0;
  if (!kOnDevice || rs.raster != RasterMethod::Auto || p.occluders || !stats.valid || stats.tris == 0) return false;
  return stats.sumArea >= kRowLanesMinBoxArea * uint64_t(stats.tris);
}

ShadeParams shadeParamsFor(const RenderSettings& rs, const FrameBuffers& f, const FramePlan& p) {
  ShadeParams sp{};
  sp.mode = rs.shading;
  sp.filter = rs.filter;
  sp.anisotropy = rs.anisotropy;
  sp.frame = f.uniforms;
  sp.ambient = rs.ambient;
  sp.specular = rs.specular;
  sp.shininess = rs.shininess;
  sp.background = rs.background;
  sp.backgroundPacked = linearToSrgb8(rs.background.x) | linearToSrgb8(rs.background.y) << 8 |
                        linearToSrgb8(rs.background.z) << 16 | linearToSrgb8(1.0f) << 24;
  sp.headlight = rs.lights.empty() ? 1 : 0;
  sp.wantDepth = rs.wantDepth;
  sp.wantPrimId = rs.wantPrimId;
  sp.wantNormals = rs.wantNormals;
  sp.perspective = rs.perspectiveCorrect ? 1 : 0;
  sp.floatOut = p.film ? 1 : 0;
  sp.wantGeom = rs.post.ssao ? 1 : 0;
  sp.shadeRun = testHooks().shadeRun;
  // Raw modes keep the direct path's background bytes.
  sp.backgroundFilm = isRawShading(rs.shading) ? unpackRaw8(sp.backgroundPacked) : rs.background;
  if (rs.background.w < 1.0f) {  // premultiplied, as the film holds colour
    const float a = rs.background.w > 0.0f ? rs.background.w : 0.0f;
    sp.background = float4{rs.background.x * a, rs.background.y * a, rs.background.z * a, a};
    sp.backgroundFilm = float4{sp.backgroundFilm.x * a, sp.backgroundFilm.y * a, sp.backgroundFilm.z * a, a};
  }
  // Only the visbuffer or naive raster wrote keys this frame, one sample per
  // pixel: blocks they did not tag hold clear keys.
  // (The MASK pass writes keys too, and tags nothing.)
  sp.blockFrames = p.tagsBlocks && p.samples == 1 && p.lines.lineItems() + p.lines.pointItems() == 0 && !p.blend.mask;
  return sp;
}

}  // namespace

FramePlan planFrame(const RenderSettings& rs, const PlanInputs& in) {
  const FrameBuffers& f = *in.frame;
  FramePlan p;
  p.method = chooseMethod(rs, in.stats);
  p.autoStats = in.statsDue;
  p.samples = f.vp.samples.count;
  p.fill = rs.polygon == PolygonMode::Fill;
  // glTF's single-sided materials cull their back faces in the glTF model
  // (--shading pbr); the other shadings draw every face, as glref does.
  p.cull = rs.cull == CullMode::Back          ? CullFaces::All
           : readsGltfMaterial(rs.shading) ? CullFaces::SingleSided
                                              : CullFaces::None;
  p.occluders = useOccluders(rs, p, in.stats);
  p.rowLanes = useRowLanes(rs, p, in.stats);
  // The visbuffer raster's work items are numbered by the setup; the
  // visbuffer and naive rasters tag the blocks they write.
  p.numberBlocks = p.method == RasterMethod::VisBuffer && p.fill;
  p.tagsBlocks = p.numberBlocks || (p.method == RasterMethod::Naive && p.fill);
  p.needWorld = !rs.keysOnly && (!(rs.shading == ShadingMode::Depth || rs.shading == ShadingMode::TexCoord) ||
                                  rs.wantNormals || rs.post.ssao);
  // The float film: when a post pass or an HDR output needs it, and for every
  // pass of a supersampled frame (resolved in float).
  p.film = rs.post.needsFloat() || in.supersampling;
  // MASK and BLEND triangles (filled only): their passes, and BLEND's
  // compositing in linear light on the film.
  p.blend.mask = in.scene->hasMask && p.fill;
  p.blend.blend = in.blendPasses && p.fill;
  p.blend.method = chooseTransparency(rs, in.blendFallback);
  p.blend.k = rs.blendK;
  p.blend.lists = walksTileLists(p.blend.method, in.blendFallback);
  // A transparent background (alpha < 1): the film keeps alpha, premultiplied.
  p.film = p.film || (in.blendFilm && p.fill) || rs.background.w < 1.0f;
  p.blend.raw = isRawShading(rs.shading);
  p.blend.straight = rs.background.w < 1.0f;
  p.lines = makeLinePass(*in.scene, rs);
  p.shadeParams = shadeParamsFor(rs, f, p);
  // The tile lists' resolve writes every pixel of the film last: where no
  // post pass, float output, supersampling or split reads the film after it,
  // it writes the colour's bytes too and the post chain does not run, where
  // that is faster (blendResolveEncodes).
  p.blend.encode = p.blend.blend && p.blend.lists && !rs.post.needsFloat() &&
                   !in.supersampling && !in.keepKeys && !rs.keysOnly && !testHooks().chainEncode &&
                   blendResolveEncodes(p.shadeParams);
  // On the CPU the binned raster can shade each tile as it finishes: the
  // shade stage's time is then part of the raster's.
  const bool linesOrPoints = p.lines.lineItems() + p.lines.pointItems() > 0;
  if (rs.keysOnly)
    p.shade = ShadePath::None;
  else if (p.method == RasterMethod::Binned && p.fill && !in.keepKeys && !p.blend.mask && !p.blend.blend &&
      fusedBinnedShadeUsable(f, p.shadeParams, linesOrPoints))
    p.shade = ShadePath::FusedBinned;
  else if (spanShadeUsable(f, p.shadeParams))
    p.shade = ShadePath::Spans;
  else
    p.shade = ShadePath::Pixels;
  // The per-pixel glTF kernel writes the opaque depth for the tile lists'
  // resolve as it clears the keys; not under a split, whose resolve reads
  // the composited keys' depth.
  p.blend.shadeDepth = p.blend.blend && p.blend.lists && p.shade == ShadePath::Pixels && !in.keepKeys &&
                       shadeWritesOpaqueDepth(p.shadeParams, p.samples);
  // Its team form's uniform blocks classified before shading and composited
  // by that kernel as it shades them (uniform_blocks.h).
  p.blend.shadeComposite = p.blend.shadeDepth && blendShadeComposites(p.shadeParams);
  p.blend.filmless = p.blend.shadeComposite && p.blend.encode && !testHooks().keepFilm;

  // Everything the frame's launches depend on besides device memory: a
  // recorded frame is replayed only under the same key (frame_graphs.h).
  p.key = settingsKey(rs) + testHooks().key();
  for (uint64_t v : {uint64_t(p.method), uint64_t(p.autoStats), uint64_t(p.occluders), uint64_t(p.rowLanes),
                     uint64_t(f.visClear), uint64_t(in.supersampling), uint64_t(f.triCapacity), uint64_t(f.workCapacity),
                     uint64_t(p.blend.method), uint64_t(p.blend.lists), uint64_t(p.blend.encode),
                     uint64_t(p.blend.shadeDepth), uint64_t(p.blend.shadeComposite), f.blend.tileCapacity,
                     p.blend.blend ? blendLaunchKey(f) : 0})
    p.key.append(reinterpret_cast<const char*>(&v), sizeof v);
  return p;
}

}  // namespace rast
