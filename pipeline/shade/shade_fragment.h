// The fragment shader of the shade stage (rast::shade): one pixel's colour
// from the visibility buffer's winner. Shared by the per-pixel kernel and the
// CPU's span kernel (shade_spans.h).
//
// A fragment recomputes the barycentrics of the winning raster triangle at the
// pixel centre, makes them perspective-correct, maps them into the drawn
// triangle (clipping moved the vertices) and interpolates the attributes from
// there. What it needs from its triangle (edge functions, draw, indices,
// vertex attributes, material, texture) is looked up once per triangle
// (TriFrag), and a work item shades a run of pixels along a row, keeping the
// last triangle's TriFrag: neighbouring pixels mostly belong to the same
// triangle, so those lookups leave the per-pixel cost (backends/tuning.h
// kShadeRun; a GPU instead gives each thread a few pixels 32 apart, see
// shadeInterleaved). The arithmetic per fragment is the same either way, so
// the layout of work items changes no bit of the result.
#pragma once

#include "backends/flatten.h"
#include "base/color.h"
#include "pipeline/rules/raster_rules.h"
#include "pipeline/rules/visbuffer_blocks.h"
#include "pipeline/raster/raster_lines.h"
#include "pipeline/shade/ibl_shading.h"
#include "pipeline/shade/pbr_shading.h"
#include "pipeline/shade/shade.h"
#include "pipeline/shade/texture_sampling.h"

// Shade::coatTexels: forced inline on GCC host builds, as RAST_GPU_INLINE on GPUs.
#if defined(__CUDACC__) || defined(__HIPCC__)
#define RAST_TEXELS_INLINE RAST_GPU_INLINE
#else
#define RAST_TEXELS_INLINE RAST_HOST_FORCEINLINE
#endif

namespace rast {
namespace shading {

// The per-triangle part of shading a fragment (see the top of the file).
struct TriFrag {
  uint32_t index = ~0u;  // raster index (kLineFlag: a point or line), ~0u: none yet
  const RasterTri* t = nullptr;
  Edges e;
  uint32_t s0 = 0, s1 = 0, s2 = 0;  // source vertices (uv, colour)
  float3 n[3], pos[3];              // world normal and position of the drawn vertices
  float2 uv[3];                     // when textured (or in uv mode)
  float4 col[3];                    // when the scene has vertex colours
  float4 baseColor{1.0f, 1.0f, 1.0f, 1.0f};
  int32_t textured = 0;
  int32_t material = -1, mirrored = 0;  // the draw's (the glTF model reads the rest of its material)
  uint32_t draw = 0;                    // its index (the glTF model's tangents take its matrix)
  TextureGPU tex{};
  // The raster triangle's fields that every fragment reads (bary()), and the
  // eye: copied here once per triangle. Read through `t` they were loaded
  // again at every pixel (ten loads a fragment on a GPU): the stores between
  // fragments might have changed them, for all the compiler knew.
  float invArea = 0.0f;
  float invW[3] = {0.0f, 0.0f, 0.0f};
  float corner[3][2] = {{0.0f, 0.0f}, {0.0f, 0.0f}, {0.0f, 0.0f}};  // RasterTri::bary
  float3 eye{0.0f, 0.0f, 0.0f};
  // The lit kernel's edge values at the centre of pixel (X, evY) of its
  // column: set from the edge functions once per triangle, then stepped by
  // B from row to row (exact integers, the same values as eval), so that a
  // pixel's weights cost no 64-bit multiplications (on the H100 with the
  // colour-less instance, shade_stage.cpp: milktruck_cab's shading 67.9 ->
  // 67.2 us, bigtri 44.8 -> 43.7, engine 24.6 -> 25.3; docs/journal/performance-2026-11-*.md).
  int64_t ev[3] = {0, 0, 0};
  int32_t evY = 0;
};

// The glTF shading's per-triangle part: the draw's material (the
// specification's default without one), whether a texture is sampled, which
// slots take the second coordinates, and the face normal (unnormalised) that
// tells back faces.
struct PbrTri {
  MaterialGPU m;
  int32_t textured = 0;
  uint32_t on1 = 0;
  float3 face{0.0f, 0.0f, 0.0f};
  // On host backends, with an environment: the image-based light's part that
  // depends on the material's roughness alone (the specular levels and the
  // split-sum rows, ibl_shading.h), used where no texture varies it. A GPU
  // finds it per fragment (kept out of the registers this struct holds
  // across a thread's pixels), so its PbrTri has none: 36 bytes less in each
  // team resolve's scratch entry (blending::PeelTeam), which lets a block's
  // list of 64 glTF-shaded triangles fit a CUDA block's scratch.
  std::conditional_t<kOnDevice, NoIblRough, IblRough> ibl;
};

// What the glTF shading of a frame uses, fixed when its kernel is compiled
// (pipeline/shade/pbr_fragment.h): texture coordinates (some material samples a
// texture), the environment's light, the file's punctual lights. kPbrAny:
// each read at run time (the general kernel). kPbrClearcoat: some material
// has a KHR_materials_clearcoat layer; that instance (kPbrClearcoat alone)
// reads the other three at run time, so that the rare scenes with a coat
// compile one instance more, not eight, and the others carry none of it.
// kPbrBaseTexture (with kPbrTextured only): no material samples a texture
// but its base colour (DeviceScene::baseTexturesOnly), which is then sampled
// at its own call site, without the loop over the material's slots.
enum PbrFeature : int {
  kPbrTextured = 1,
  kPbrEnv = 2,
  kPbrPunctual = 4,
  kPbrClearcoat = 8,
  kPbrBaseTexture = 16,
  kPbrAny = -1
};

struct Shade {
  // scene
  DView<DrawGPU> draws;
  DView<uint32_t> drawTriStart, indices;
  DView<DrawIndex> triDraw;  // DeviceScene::triDraw (empty: search drawTriStart)
  DView<float2> uvs;
  DView<float4> colors;
  DView<float4> tangents;  // DeviceScene::tangents (read when hasTangent)
  DView<float2> uvs1;      // DeviceScene::uvs1 (read when hasUV1)
  DView<MaterialGPU> materials;
  DView<ClearcoatGPU> clearcoats;  // DeviceScene::clearcoats (read where a material has kMaterialClearcoat)
  int32_t hasClearcoat = 0;
  DView<TextureGPU> textures;
  DView<uint32_t> texels;
  DView<float> lut;               // sRGB decode (textures)
  DView<float> unorm;             // i / 255 (linear textures: normals, metal/rough, occlusion)
  DView<PunctualGPU> punctual;    // the file's lights (the glTF model)
  int32_t numPunctual = 0;
  DView<uint32_t> encodePacked;   // sRGB encode, DeviceScene::srgbEncodePacked (packSrgb8Packed)
  uint32_t numDraws;
  int32_t hasUV, hasColor;
  int32_t hasTangent = 0, hasUV1 = 0;
  int32_t baseTexturesOnly = 0;  // DeviceScene::baseTexturesOnly (kPbrBaseTexture)
  // frame
  DView<RasterTri> tris;
  DView<uint64_t> vis;
  DView<float3> worldPos, worldNormal;
  DView<uint32_t> color;
  DView<float> depthOut;
  DView<uint32_t> primOut;
  DView<float3> normalOut;
  DView<float4> hdr, geom;  // the float film and SSAO's per-pixel geometry, when used
  DView<float> viewDepth;   // geom's depth alone, for SSAO's taps
  DView<LightGPU> lights;
  Kokkos::View<Kokkos::MinMaxScalar<float>, Mem> depthRange;  // eye depth of covered pixels (depth mode)
  int32_t width;
  SamplePattern samples;
  ShadeParams p;
  LineShade lineShade;  // fragments of points and lines (raster_lines.h)
  int32_t run, runsPerRow;  // pixels per work item along a row (kShadeRun), work items per row
  int32_t clearVis = 0;     // write kClearKey over every sample once read (FrameBuffers::visClear)
  int32_t height = 0;
  int32_t interleaved = 0;  // GPU layout of work items (ShadeInterleaved) instead of runs along rows
  DView<uint32_t> blockFrame{};  // FrameBuffers::blockFrame, read when p.blockFrames
  DView<uint32_t> opaqueDepth{};  // where set, each sample's depth bits (shadeWritesOpaqueDepth)
  // Where set, the BLEND layers' uniform blocks (ShadeBlend): blendFilm.
  DView<float4> blendComposite{};
  DView<uint32_t> blendFrags{};
  int32_t blendBlocksX = 0, blendEncode = 0, blendRaw = 0, blendStraight = 0, blendFilmless = 0;
  DView<uint32_t> blockDepth{};  // FrameBuffers::blockDepth, reset with the keys when resetBlocks
  int32_t blocksPerRow = 0, resetBlocks = 0;

  // The BLEND layers' composite over pixel (X, Y) where its block's layers
  // composite alike (ShadeBlend::composite): looked up once for a GPU
  // thread's column of pixels, which lies in one block, its two loads
  // issued together (a walked block's composite is stale, and not used).
  struct BlendAt {
    float4 o;
    int32_t over;
  };
  KOKKOS_INLINE_FUNCTION BlendAt blendAt(const int32_t X, const int32_t Y) const {
    if (!blendComposite.data()) return BlendAt{float4{0.0f, 0.0f, 0.0f, 0.0f}, 0};
    const int64_t b = blendBlockOf(X, Y, blendBlocksX);
    const uint32_t frags = blendFrags(b);
    const float4 o = blendComposite(b);
    return BlendAt{o, frags != kUniformWalk ? 1 : 0};
  }
  // Writes the film's value of pixel i shaded c: c, or that composite over
  // c, and its bytes where asked (the resolve's arithmetic, Peel::filmSample:
  // the same bits, mulRn and addRn under this file's fused multiply-adds).
  // A composited pixel whose bytes are written skips the film where nothing
  // reads it after (BlendPlan::filmless): 16 bytes a pixel, 33 MB a 1080p
  // frame, whose writes cost the H200's 8-layer BLEND frame 6% of its time.
  KOKKOS_INLINE_FUNCTION void blendFilm(const int64_t i, const BlendAt& a, const float4 c) const {
    if (!a.over) {
      hdr(i) = c;
      return;
    }
    const float4 out = overOpaque(float3{a.o.x, a.o.y, a.o.z}, a.o.w, c);
    if (blendEncode) {
      color(i) = encodeFilm(out, blendRaw != 0, blendStraight != 0, encodePacked);
      if (blendFilmless) return;
    }
    hdr(i) = out;
  }
  // With the keys cleared for the next frame, the visbuffer's depth bounds
  // are reset too (raster_visbuffer.cpp), each by its block's first pixel.
  KOKKOS_INLINE_FUNCTION void resetBlock(int32_t X, int32_t Y) const {
    constexpr int32_t kMask = (1 << kVisBlockShift) - 1;
    if (clearVis && resetBlocks && ((X | Y) & kMask) == 0)
      blockDepth(uint32_t(Y >> kVisBlockShift) * uint32_t(blocksPerRow) + uint32_t(X >> kVisBlockShift)) = kFarDepthBits;
  }

  KOKKOS_INLINE_FUNCTION float eyeDepth(float d) const {
    const float zn = 2.0f * d - 1.0f;
    const float n = p.frame(0).camera.znear, f = p.frame(0).camera.zfar;
    return 2.0f * n * f / ((f + n) - zn * (f - n));
  }

  // Barycentrics in the drawn triangle at a point (ox, oy) (1/256 pixel) from
  // the centre of pixel (X, Y): screen-space weights from the exact edge values,
  // made perspective-correct (attributes vary linearly in clip space, i.e. with
  // weight l_k / w_k), then mapped through the raster triangle's vertices
  // (clipping moved them). Points outside the triangle extrapolate the plane,
  // which is what the derivatives need.
  KOKKOS_INLINE_FUNCTION void bary(const TriFrag& t, const Edges& e, int32_t X, int32_t Y, int32_t ox, int32_t oy,
                                   float& b0, float& b1, float& b2) const {
    baryFrom(t, e.sample(0, X, Y, ox, oy), e.sample(1, X, Y, ox, oy), e.sample(2, X, Y, ox, oy), b0, b1, b2);
  }
  // The same from the exact edge values E0, E1, E2 at the point.
  KOKKOS_INLINE_FUNCTION void baryFrom(const TriFrag& t, int64_t E0, int64_t E1, int64_t E2, float& b0, float& b1,
                                       float& b2) const {
    drawnBarycentrics(E0, E1, E2, t.invArea, t.invW, t.corner, p.perspective != 0, b1, b2);
    b0 = 1.0f - b1 - b2;
  }

  KOKKOS_INLINE_FUNCTION static float2 uvAt(const TriFrag& f, float b0, float b1, float b2) {
    return {f.uv[0].x * b0 + f.uv[1].x * b1 + f.uv[2].x * b2, f.uv[0].y * b0 + f.uv[1].y * b1 + f.uv[2].y * b2};
  }

  // Looks up what shading raster triangle `index` needs, once per triangle.
  KOKKOS_INLINE_FUNCTION void prepare(uint32_t index, TriFrag& f) const {
    f.index = index;
    if (p.mode == ShadingMode::Depth || (index & kLineFlag)) return;
    f.t = &tris(index);
    const RasterTri& t = *f.t;
    f.e = Edges(t);
    f.invArea = t.invArea;
    for (int k = 0; k < 3; ++k) {
      f.invW[k] = t.invW[k];
      f.corner[k][0] = t.bary[k][0];
      f.corner[k][1] = t.bary[k][1];
    }
    f.eye = p.frame(0).camera.eye;
    const uint32_t d = drawOf(triDraw, drawTriStart, numDraws, t.prim);
    const DrawGPU& dr = draws(d);
    const uint32_t base = 3 * (dr.srcTri + (t.prim - dr.dstTri));
    const uint32_t i0 = indices(base), i1 = indices(base + 1), i2 = indices(base + 2);
    f.s0 = dr.srcVertex + i0;
    f.s1 = dr.srcVertex + i1;
    f.s2 = dr.srcVertex + i2;
    f.textured = 0;
    f.baseColor = float4{1.0f, 1.0f, 1.0f, 1.0f};
    bool wantUV = p.mode == ShadingMode::TexCoord && hasUV;
    if (p.mode != ShadingMode::TexCoord) {
      const uint32_t v[3] = {dr.dstVertex + i0, dr.dstVertex + i1, dr.dstVertex + i2};
      for (int k = 0; k < 3; ++k) {
        f.n[k] = worldNormal(v[k]);
        f.pos[k] = worldPos(v[k]);
      }
      f.material = dr.material;
      f.mirrored = dr.mirrored;
      f.draw = d;
      if (dr.material >= 0) {
        const MaterialGPU& m = materials(dr.material);
        f.baseColor = m.baseColor;
        if (m.texture >= 0 && hasUV) {
          f.textured = 1;
          f.tex = textures(m.texture);
          wantUV = true;
        }
        // The glTF model samples the material's other textures with the same coordinates.
        if (readsGltfMaterial(p.mode) && hasUV &&
            (m.mrTexture >= 0 || m.normalTexture >= 0 || m.occlusionTexture >= 0 || m.emissiveTexture >= 0 ||
             (m.flags & kMaterialClearcoat)))
          wantUV = true;
      }
      if (hasColor) {
        f.col[0] = colors(f.s0);
        f.col[1] = colors(f.s1);
        f.col[2] = colors(f.s2);
      }
    }
    if (wantUV) {
      f.uv[0] = uvs(f.s0);
      f.uv[1] = uvs(f.s1);
      f.uv[2] = uvs(f.s2);
    }
  }

  // Colour of a fragment of f's triangle at a sample of pixel (X, Y), for display:
  // linear light for the lit and depth modes (sRGB-encoded later), raw values
  // for the diagnostic modes (normals, uv, mip level).
  // kLit: the caller knows the frame is lit (Lambert or Blinn-Phong) with a
  // nearest or bilinear filter (litOnly()), and the other modes' code is left
  // out of its kernel.
  // kColor: whether the scene has vertex colours, when known at compile time
  // (-1: hasColor says). The lit kernel is built for each, so that the
  // vertex colours hold no registers where there are none.
  template <bool kLit = false, int kColor = -1>
  KOKKOS_INLINE_FUNCTION float4 shadeFragment(const TriFrag& f, int32_t X, int32_t Y, int32_t ox, int32_t oy, float depth,
                                              float3* normalOutV, float3* posOutV = nullptr) const {
    if (!kLit && p.mode == ShadingMode::Depth) {
      const float lo = depthRange().min_val, hi = depthRange().max_val;
      const float g = hi > lo ? 1.0f - (eyeDepth(depth) - lo) / (hi - lo) : 1.0f;
      return float4{g, g, g, 1.0f};
    }
    if (f.index & kLineFlag) return lineShade.color(f.index & ~kLineFlag);
    const Edges& e = f.e;
    float b0, b1, b2;
    if (kLit)  // a pixel centre (ox = oy = 0) of row f.evY (useAt)
      baryFrom(f, f.ev[0], f.ev[1], f.ev[2], b0, b1, b2);
    else
      bary(f, e, X, Y, ox, oy, b0, b1, b2);

    if (!kLit && p.mode == ShadingMode::TexCoord) {
      // Texture coordinates as raw red/green (fractional part); black without any.
      if (!hasUV) return float4{0.0f, 0.0f, 0.0f, 1.0f};
      const float2 uv = uvAt(f, b0, b1, b2);
      return float4{uv.x - ::floorf(uv.x), uv.y - ::floorf(uv.y), 0.0f, 1.0f};
    }

    const float3 N = normalize(f.n[0] * b0 + f.n[1] * b1 + f.n[2] * b2);
    const float3 P = f.pos[0] * b0 + f.pos[1] * b1 + f.pos[2] * b2;
    if (normalOutV) *normalOutV = N;
    if (posOutV) *posOutV = P;
    if (!kLit && p.mode == ShadingMode::Normals)  // encoded directly (no sRGB curve), as normal maps are
      return float4{N.x * 0.5f + 0.5f, N.y * 0.5f + 0.5f, N.z * 0.5f + 0.5f, 1.0f};
    if (!kLit && readsGltfMaterial(p.mode)) return shadePbr(f, pbrTri(f), X, Y, ox, oy, b0, b1, b2, N, P);

    float4 base4 = f.baseColor;
    float lod = 0.0f;
    if (f.textured) {
      const float2 uv = uvAt(f, b0, b1, b2);
      const TextureGPU& tex = f.tex;
      float4 tc;
      if (!kLit && (p.filter == TexFilter::Trilinear || p.mode == ShadingMode::MipLevel)) {
        // Analytic derivatives: the same plane one pixel to the right and up.
        float c0, c1, c2;
        bary(f, e, X, Y, ox + kSubOne, oy, c0, c1, c2);
        const float2 ux = uvAt(f, c0, c1, c2);
        bary(f, e, X, Y, ox, oy + kSubOne, c0, c1, c2);
        const float2 uy = uvAt(f, c0, c1, c2);
        lod = textureLod(ux.x - uv.x, ux.y - uv.y, uy.x - uv.x, uy.y - uv.y, tex.width, tex.height);
        tc = sampleTrilinear(tex, texels, lut, uv.x, uv.y, lod);
      } else if (p.filter == TexFilter::Nearest) {
        tc = sampleNearest(tex, texels, lut, uv.x, uv.y);
      } else {
        tc = sampleBilinear(tex, texels, lut, uv.x, uv.y);
      }
      base4 = base4 * tc;
    }
    if (!kLit && p.mode == ShadingMode::MipLevel) {
      const float l = lod / 8.0f;  // level 0 black, level 8 full red
      return float4{l, 0.0f, 0.0f, 1.0f};
    }
    if (kColor < 0 ? hasColor != 0 : kColor == 1) base4 = base4 * (f.col[0] * b0 + f.col[1] * b1 + f.col[2] * b2);
    return litLight(f, base4, N, P);
  }

  // The lit shading (Lambert or Blinn-Phong, nearest or bilinear texturing:
  // what litOnly() admits) of a fragment at barycentrics b0, b1, b2: the
  // same expressions as shadeFragment<true, kColor>, for callers that have
  // the barycentrics at a sample (the BLEND resolve, pipeline/blend/frag_shade.h).
  template <int kColor>
  RAST_GPU_INLINE float4 litFragment(const TriFrag& f, float b0, float b1, float b2) const {
    const float3 N = normalize(f.n[0] * b0 + f.n[1] * b1 + f.n[2] * b2);
    const float3 P = f.pos[0] * b0 + f.pos[1] * b1 + f.pos[2] * b2;
    float4 base4 = f.baseColor;
    if (f.textured) {
      const float2 uv = uvAt(f, b0, b1, b2);
      base4 = base4 * (p.filter == TexFilter::Nearest ? sampleNearest(f.tex, texels, lut, uv.x, uv.y)
                                                      : sampleBilinear(f.tex, texels, lut, uv.x, uv.y));
    }
    if (kColor == 1) base4 = base4 * (f.col[0] * b0 + f.col[1] * b1 + f.col[2] * b2);
    return litLight(f, base4, N, P);
  }

  // The lit shading's light on a fragment of colour base4, normal N, at P.
  RAST_GPU_INLINE float4 litLight(const TriFrag& f, const float4& base4, const float3& N, const float3& P) const {
    const float3 V = normalize(f.eye - P);
    float diffuse = p.ambient, spec = 0.0f;
    // The headlight (the default lighting) on a path of its own: the same
    // arithmetic as the loop's one light, without the loop's predicated light
    // loads, selects and counter (about 35 instructions a pixel for its one
    // pass, in Nsight Compute's counts for milktruck_cab).
    if (p.headlight)
      addLight(N, V, V, 1.0f - p.ambient, diffuse, spec);
    else
      for (int k = 0; k < int(lights.extent(0)); ++k) addLight(N, V, lights(k).direction, lights(k).intensity, diffuse, spec);
    const float3 rgb = float3{base4.x, base4.y, base4.z} * diffuse + float3{spec, spec, spec};
    return float4{rgb.x, rgb.y, rgb.z, base4.w};
  }

  // The glTF shading's members (pbr_fragment.h, included at the end of this
  // file): a material's textures, its coordinates, normal maps, and the
  // fragment's colour, with the scene's features fixed at compile time
  // (kFeat, PbrFeature) or read at run time (kPbrAny).
  RAST_GPU_INLINE float4 sampleTexture(const TextureGPU& tex, float2 uv, DecodeTable decode, float2 dx,
                                              float2 dy) const;
  // A set of texture coordinates at a fragment: the point, its derivatives
  // one pixel right and up (when the filter takes them) and the triangle's
  // three corners.
  struct UvSet {
    float2 uv{0.0f, 0.0f}, dx{0.0f, 0.0f}, dy{0.0f, 0.0f};
    float2 t0{0.0f, 0.0f}, t1{0.0f, 0.0f}, t2{0.0f, 0.0f};
  };
  KOKKOS_INLINE_FUNCTION static UvSet uvSet(float2 t0, float2 t1, float2 t2, const float b[3], const float bx[3],
                                            const float by[3], bool derivatives);
  // The texels of a fragment's material textures, indexed by TextureSlot
  // (left as they are where the material has no such texture, or no
  // emission), sampled in one loop: on a GPU one copy of the filter's code
  // in the kernel (docs/cuda.md).
  static constexpr int kTextureSlots = SlotEmissive + 1;
  RAST_GPU_INLINE void materialTexels(const TriFrag& f, const MaterialGPU& m, uint32_t on1, const UvSet& c0,
                                      const UvSet& c1, float4 (&tx)[kTextureSlots]) const;
  // The same with the clear coat's three textures (cc's), for the clear
  // coat's instance and the general kernel. Inlined on GCC host builds by
  // force: a template sharing materialTexels' loop was left out of line by
  // GCC despite the kernel's `flatten` (the duck's frame, 960x540, 149.5 M
  // -> 155.7 M instructions under callgrind).
  static constexpr int kCoatSlots = SlotClearcoatNormal + 1;
  RAST_TEXELS_INLINE void coatTexels(const TriFrag& f, const MaterialGPU& m, const ClearcoatGPU& cc, uint32_t on1,
                                     const UvSet& c0, const UvSet& c1, float4 (&tx)[kCoatSlots]) const;
  // Normal mapping's tangent frame at a fragment (T and B turned with a back
  // face, and Ng, the normal turned); false where there is none (Ng alone).
  RAST_GPU_INLINE bool tangentFrame(const TriFrag& f, float b0, float b1, float b2, float3 N, bool back,
                                    const UvSet& c, float3& T, float3& B, float3& Ng) const;
  RAST_GPU_INLINE float3 normalMapped(const TriFrag& f, const MaterialGPU& m, float b0, float b1, float b2,
                                      float3 N, bool back, const UvSet& c, const float4& texel) const;
  RAST_GPU_INLINE PbrTri pbrTri(const TriFrag& f) const;
  // PbrTri::textured for material m: some texture of it is sampled.
  KOKKOS_INLINE_FUNCTION bool pbrTextured(const MaterialGPU& m) const {
    return hasUV && (m.texture >= 0 || m.mrTexture >= 0 || m.normalTexture >= 0 || m.occlusionTexture >= 0 ||
                     m.emissiveTexture >= 0 || (m.flags & kMaterialClearcoat));
  }
  template <int kFeat, class Surface>
  RAST_GPU_INLINE float4 shadePbrWith(const TriFrag& f, const PbrTri& t, int32_t X, int32_t Y, int32_t ox, int32_t oy,
                                      float b0, float b1, float b2, const Surface& surface) const;
  // The same with the normal N and position P interpolated already.
  template <int kFeat = kPbrAny>
  RAST_GPU_INLINE float4 shadePbr(const TriFrag& f, const PbrTri& t, int32_t X, int32_t Y, int32_t ox, int32_t oy,
                                  float b0, float b1, float b2, const float3& N, const float3& P) const {
    return shadePbrWith<kFeat>(f, t, X, Y, ox, oy, b0, b1, b2, [&](float3& n, float3& q) {
      n = N;
      q = P;
    });
  }
  // The occlusion texture's factor on indirect light, and the emitted light,
  // of a fragment of material m (the glTF shading and its debug views).
  // (texel: the material's occlusion or emissive texel, materialTexels).
  RAST_GPU_INLINE static float occlusionAt(const MaterialGPU& m, bool textured, const float4& texel);
  RAST_GPU_INLINE static float3 emissionAt(const MaterialGPU& m, bool textured, const float4& texel);
  // One directional light L of intensity I: Lambert's term, and Blinn-Phong's
  // highlight in that mode.
  KOKKOS_INLINE_FUNCTION void addLight(const float3& N, const float3& V, const float3& L, const float I,
                                       float& diffuse, float& spec) const {
    const float ndl = dot(N, L);
    diffuse += I * (ndl > 0.0f ? ndl : 0.0f);
    if (p.mode == ShadingMode::BlinnPhong && ndl > 0.0f) {
      const float ndh = dot(N, normalize(L + V));
      spec += I * p.specular * (ndh > 0.0f ? ::powf(ndh, p.shininess) : 0.0f);
    }
  }

  template <bool kLit = false>
  KOKKOS_INLINE_FUNCTION uint32_t display(float4 c) const {
    return !kLit && isRawShading(p.mode) ? packRaw8(c) : packSrgb8Packed(c, encodePacked);
  }

  // Whether a frame may take the kernel compiled for lit shading alone
  // (ShadeInterleaved<true>): Lambert or Blinn-Phong, nearest or bilinear
  // texturing, to 8-bit colour or to the float film (BLEND's, the post
  // passes', float outputs; ids, depth and normals as asked). Every other
  // mode's code (depth, diagnostics, trilinear derivatives, SSAO's geometry)
  // is left out of that kernel. The film's frames take it too: in the
  // general kernel their shade stage took twice as long on the H100 (a BLEND
  // frame of 8 layers: 83 us against 42).
  bool litOnly() const {
    return (p.mode == ShadingMode::Lambert || p.mode == ShadingMode::BlinnPhong) && p.filter != TexFilter::Trilinear &&
           !p.wantGeom;
  }

  // SSAO's input: view-space normal and depth of the surface at the pixel (the
  // first sample's); zero where nothing was shaded with a normal.
  KOKKOS_INLINE_FUNCTION float4 viewGeometry(float3 N, float3 P) const {
    if (!(dot(N, N) > 0.0f)) return float4{0.0f, 0.0f, 0.0f, 0.0f};
    const float* m = p.frame(0).camera.view.m;
    const float3 n = normalize(float3{m[0] * N.x + m[4] * N.y + m[8] * N.z, m[1] * N.x + m[5] * N.y + m[9] * N.z,
                                      m[2] * N.x + m[6] * N.y + m[10] * N.z});
    const float d = -(m[2] * P.x + m[6] * P.y + m[10] * P.z + m[14]);
    return float4{n.x, n.y, n.z, d > 0.0f ? d : 0.0f};
  }

  KOKKOS_INLINE_FUNCTION void writeGeometry(int64_t i, float4 g) const {
    geom(i) = g;
    viewDepth(i) = g.w;
  }

  // One work item: pixels [x0, x1) of row Y, sharing the TriFrag of the last
  // triangle seen.
  // Work items number below 2^31 (kMaxFramebufferSide), so the row and column
  // are found in 32-bit arithmetic: a 64-bit division is a long software
  // routine on GPUs, paid once per pixel there.
  KOKKOS_INLINE_FUNCTION void operator()(const int64_t item) const {
    const uint32_t it = uint32_t(item), rows = uint32_t(runsPerRow);
    const int32_t Y = int32_t(it / rows);
    const int32_t x0 = int32_t(it - uint32_t(Y) * rows) * run;
    const int32_t x1 = x0 + run < width ? x0 + run : width;
    const int64_t row = int64_t(Y) * width;
    TriFrag f;
    for (int32_t X = x0; X < x1; ++X) shadePixel(row + X, X, Y, f);
  }

  // GPUs, one sample per pixel: a warp of 32 work items shades a tile 32
  // pixels wide and kShadeInterleave rows high, each work item a column of it,
  // so that each of its loads and stores is one coalesced access of the warp
  // (a row of 32 pixels) and its pixels, one above the other, mostly share a
  // triangle (its lookups, TriFrag, kept from pixel to pixel; pixels 32 apart
  // along a row rarely shared one). It loads all its keys before shading any:
  // the kernel is bound by those loads, and its register cap
  // (kShadeLaunchBounds) leaves too few warps to hide one at a time.
  static constexpr uint32_t kLanes = 32;

  KOKKOS_INLINE_FUNCTION uint32_t tileColumns() const { return (uint32_t(width) + kLanes - 1) / kLanes; }
  // Work items of a launch, for either layout.
  int64_t workItems() const {
    if (!interleaved) return int64_t(runsPerRow) * height;
    const uint32_t tileRows = (uint32_t(height) + uint32_t(kShadeInterleave) - 1) / uint32_t(kShadeInterleave);
    return int64_t(tileColumns()) * tileRows * kLanes;
  }
  // Work item w's column: its top pixel (index i, at X, Y).
  struct Column {
    uint32_t i, X, Y;
  };
  KOKKOS_INLINE_FUNCTION Column column(const uint32_t w) const {
    const uint32_t cols = tileColumns(), tile = w / kLanes, ty = tile / cols;
    const uint32_t X = (tile - ty * cols) * kLanes + w % kLanes, Y = ty * uint32_t(kShadeInterleave);
    return Column{Y * uint32_t(width) + X, X, Y};
  }
  template <bool kLit = false, int kColor = -1>
  KOKKOS_INLINE_FUNCTION void shadeInterleaved(const uint32_t w) const {
    // A key in a block the raster left alone this frame is clear: not read
    // (p.blockFrames), which saves most of the frame's reads behind a model.
    const uint32_t thisFrame = p.blockFrames ? p.frame(0).frame : 0u;
    const Column at = column(w);
    if (at.X >= uint32_t(width)) return;  // right of the frame's last column
    const uint32_t rows = uint32_t(height) - at.Y < uint32_t(kShadeInterleave) ? uint32_t(height) - at.Y
                                                                               : uint32_t(kShadeInterleave);
    // The column lies in one 8x8 block: one tag for its pixels.
    static_assert((1 << kVisBlockShift) % kShadeInterleave == 0, "a work item's column must not cross a block row");
    const bool tagged =
        !p.blockFrames ||
        blockFrame((at.Y >> kVisBlockShift) * uint32_t(blocksPerRow) + (at.X >> kVisBlockShift)) == thisFrame;
    uint64_t keys[kShadeInterleave];
    for (uint32_t k = 0; k < uint32_t(kShadeInterleave); ++k)
      keys[k] = tagged && k < rows ? vis(at.i + k * uint32_t(width)) : kClearKey;
    TriFrag f;
    for (uint32_t k = 0; k < rows; ++k) {
      // Each pixel takes keys[0], and the rest move down a place: indexed by
      // the loop's k (not unrolled, the shader being long), the keys went to
      // the stack, and selects were turned back into that.
      shadeSingle<kLit, kColor>(int64_t(at.i + k * uint32_t(width)), int32_t(at.X), int32_t(at.Y + k), f, keys[0]);
      for (uint32_t q = 0; q + 1 < uint32_t(kShadeInterleave); ++q) keys[q] = keys[q + 1];
    }
  }

  KOKKOS_INLINE_FUNCTION void use(uint32_t index, TriFrag& f) const {
    if (index != f.index) prepare(index, f);
  }
  // use() for the lit kernel at pixel (X, Y): the edge values there too
  // (TriFrag::ev), evaluated for a new triangle, else stepped from the row
  // before (a thread walks down a column).
  KOKKOS_INLINE_FUNCTION void useAt(uint32_t index, TriFrag& f, int32_t X, int32_t Y) const {
    if (index != f.index) {
      prepare(index, f);
      if (index & kLineFlag) return;
      for (int i = 0; i < 3; ++i) f.ev[i] = f.e.eval(i, X, Y);
    } else if (Y != f.evY) {
      for (int i = 0; i < 3; ++i) f.ev[i] += f.e.rows(i, Y - f.evY);
    }
    f.evY = Y;
  }

  // Outputs of every pixel: ids and depth of its first sample (as OpenGL
  // resolves integer and depth buffers: one sample).
  KOKKOS_INLINE_FUNCTION void writeIds(const int64_t i, const uint64_t key0) const {
    const uint32_t idx0 = uint32_t(key0 & 0xffffffffu);
    if (p.wantDepth) depthOut(i) = bitsFloat(uint32_t(key0 >> 32));
    if (p.wantPrimId)
      primOut(i) = idx0 == 0 ? 0 : (idx0 - 1) & kLineFlag ? lineShade.primId((idx0 - 1) & ~kLineFlag) : tris(idx0 - 1).prim + 1;
  }

  // One sample per pixel, its key already loaded.
  template <bool kLit = false, int kColor = -1>
  KOKKOS_INLINE_FUNCTION void shadeSingle(const int64_t i, const int32_t X, const int32_t Y, TriFrag& f,
                                          const uint64_t key0) const {
    // The next frame's clear, while the key is at hand (FrameBuffers::visClear);
    // background keys are clear already, and an empty pixel costs no store.
    if (clearVis && key0 != kClearKey) vis(i) = kClearKey;
    resetBlock(X, Y);
    writeIds(i, key0);
    const uint32_t idx0 = uint32_t(key0 & 0xffffffffu);
    float3 n0{0.0f, 0.0f, 0.0f}, p0{0.0f, 0.0f, 0.0f};
    if (idx0) {
      if (kLit) useAt(idx0 - 1, f, X, Y);
      else use(idx0 - 1, f);
    }
    if (p.floatOut)  // linear light, before any post pass or display encoding
      hdr(i) = idx0 ? shadeFragment<kLit, kColor>(f, X, Y, 0, 0, bitsFloat(uint32_t(key0 >> 32)), &n0, kLit ? nullptr : &p0)
                    : p.backgroundFilm;
    else
      color(i) = idx0 ? display<kLit>(shadeFragment<kLit, kColor>(f, X, Y, 0, 0, bitsFloat(uint32_t(key0 >> 32)), &n0))
                      : p.backgroundPacked;
    if (p.wantNormals) normalOut(i) = n0;
    if (!kLit && p.wantGeom) writeGeometry(i, viewGeometry(n0, p0));
  }

  KOKKOS_INLINE_FUNCTION void shadePixel(const int64_t i, const int32_t X, const int32_t Y, TriFrag& f) const {
    const int S = samples.count;
    if (S == 1) {
      shadeSingle(i, X, Y, f, vis(i));
      return;
    }
    const uint64_t key0 = vis(i * S);
    writeIds(i, key0);
    float3 n0{0.0f, 0.0f, 0.0f}, p0{0.0f, 0.0f, 0.0f};
    // Multisampling: shade once per distinct triangle among the samples, at the
    // centroid of the samples it covers (the pixel centre when it covers them
    // all; never outside the triangle, so attributes are not extrapolated),
    // weight by the samples it covers, and resolve in linear light.
    const bool raw = isRawShading(p.mode);
    float4 acc{0.0f, 0.0f, 0.0f, 0.0f};
    int background = 0;
    for (int s = 0; s < S; ++s) {
      const uint64_t key = vis(i * S + s);
      const uint32_t idx = uint32_t(key & 0xffffffffu);
      if (idx == 0) {
        ++background;
        continue;
      }
      bool seen = false;
      for (int r = 0; r < s; ++r) seen |= uint32_t(vis(i * S + r) & 0xffffffffu) == idx;
      if (seen) continue;
      int count = 1, sx = samples.ox[s], sy = samples.oy[s];
      for (int r = s + 1; r < S; ++r)
        if (uint32_t(vis(i * S + r) & 0xffffffffu) == idx) {
          ++count;
          sx += samples.ox[r];
          sy += samples.oy[r];
        }
      float3 n{0.0f, 0.0f, 0.0f}, q{0.0f, 0.0f, 0.0f};
      use(idx - 1, f);
      const float4 c = shadeFragment(f, X, Y, sx / count, sy / count, bitsFloat(uint32_t(key >> 32)), &n, &q);
      if (s == 0) {
        n0 = n;
        p0 = q;
      }
      acc = acc + c * float(count);
    }
    const float4 bg = raw ? float4{0.0f, 0.0f, 0.0f, 1.0f} : p.background;
    acc = (acc + bg * float(background)) * (1.0f / float(S));
    if (clearVis)
      for (int s = 0; s < S; ++s) vis(i * S + s) = kClearKey;
    resetBlock(X, Y);
    if (p.floatOut) hdr(i) = acc;
    else color(i) = display(acc);
    if (p.wantNormals) normalOut(i) = n0;
    if (p.wantGeom) writeGeometry(i, viewGeometry(n0, p0));
  }
};

// The interleaved layout as a kernel of its own: compiled into one kernel with
// the runs along rows, the shader spilled 400 bytes a thread under the register
// cap (152 alone).
template <bool kLit, int kColor = -1>
struct ShadeInterleaved {
  Shade k;
  KOKKOS_INLINE_FUNCTION void operator()(const int64_t item) const { k.shadeInterleaved<kLit, kColor>(uint32_t(item)); }
};

}  // namespace shading

// The shading functor for a frame: its outputs allocated (colour, the AOVs and
// film it asks for), its parameters filled by name. Used by the per-pixel
// kernel (shade_stage.cpp) and by the CPU's span and tile shading (pipeline/cpu/).
shading::Shade makeShade(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights);

}  // namespace rast

#include "pipeline/shade/pbr_fragment.h"
