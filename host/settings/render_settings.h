// What a frame is asked to do: size, culling, shading, filtering, raster method
// and the optional outputs (AOVs).
#pragma once

#include "host/settings/post_settings.h"
#include "base/vec.h"

#include <string>
#include <vector>

namespace rast {

enum class CullMode { None, Back };
// Pbr: the glTF 2.0 metallic-roughness model with the file's punctual lights
// (pipeline/shade/pbr_shading.h); Lambert and BlinnPhong: base colour under a
// headlight or --light, as glref and the seed rasterizers shade.
// Pbr: the glTF material model. BaseColor .. ShadingNormals: its debug views,
// one input of the glTF shading each (base colour, metallic/roughness,
// occlusion, emission, the normal it shades with) instead of the lit colour.
enum class ShadingMode {
  Lambert, BlinnPhong, Normals, Depth, TexCoord, MipLevel, Pbr,
  BaseColor, MetalRough, Occlusion, Emissive, ShadingNormals
};
// Auto: the glTF samplers' own filters under the glTF shading (--shading pbr),
// bilinear otherwise.
enum class TexFilter { Nearest, Bilinear, Trilinear, Auto };
enum class RasterMethod { Auto, Naive, VisBuffer, Binned };
// How glTF BLEND surfaces are composited (docs/transparency.md): every fragment
// kept and sorted (exact), the k nearest exact and the rest merged (kbuffer),
// weighted blended OIT (weighted), draws sorted by their centre's depth as
// most engines do (sorted), or chosen from the scene's depth complexity (auto).
enum class Transparency { Auto, Exact, KBuffer, Weighted, Sorted };
// How triangles are drawn (glPolygonMode): filled, as their edges, or as their corners.
enum class PolygonMode { Fill, Line, Point };
// Triangle edges drawn over the filled triangles: always on top, or depth-tested
// against the fill with a small bias so that hidden edges stay hidden.
enum class Wireframe { Off, On, Hidden };

// Diagnostic modes whose colours are data (normals, texture coordinates, mip
// level, the glTF material's data channels), stored as raw bytes rather than
// sRGB-encoded light.
KOKKOS_INLINE_FUNCTION bool isRawShading(ShadingMode m) {
  return m == ShadingMode::Normals || m == ShadingMode::TexCoord || m == ShadingMode::MipLevel ||
         m == ShadingMode::MetalRough || m == ShadingMode::Occlusion || m == ShadingMode::ShadingNormals;
}

// The modes that read the glTF material model (its textures, samplers,
// double-sidedness): the glTF shading and its debug views.
KOKKOS_INLINE_FUNCTION bool readsGltfMaterial(ShadingMode m) {
  return m == ShadingMode::Pbr || m == ShadingMode::BaseColor || m == ShadingMode::MetalRough ||
         m == ShadingMode::Occlusion || m == ShadingMode::Emissive || m == ShadingMode::ShadingNormals;
}

struct DirectionalLight {
  float3 direction{0.0f, 0.0f, 1.0f};  // world space, pointing towards the light
  float intensity = 0.85f;
  bool operator==(const DirectionalLight& o) const {
    return direction.x == o.direction.x && direction.y == o.direction.y && direction.z == o.direction.z &&
           intensity == o.intensity;
  }
  bool operator!=(const DirectionalLight& o) const { return !(*this == o); }
};

struct RenderSettings {
  int width = 1920, height = 1080;
  CullMode cull = CullMode::None;
  ShadingMode shading = ShadingMode::Lambert;
  TexFilter filter = TexFilter::Bilinear;
  // Anisotropic filtering's most taps (1..16) where a glTF sampler filters
  // linearly between mipmap levels, under --filter auto and the glTF shading.
  // An option, off by default: the sampler's own filter is what the file
  // asks for, and 16 taps cost the textured models' frames up to twice their
  // shading (docs/performance.md); --anisotropy 16 gives the Sample
  // Renderer's WebGL setting (docs/quality.md charts its error and cost).
  int anisotropy = 1;
  // Image-based light of the glTF shading (pipeline/shade/environment.h):
  // "" the built-in neutral environment, "none" none, else a Radiance .hdr
  // file; its intensity and rotation about +Y (degrees).
  std::string environment;
  float envIntensity = 1.0f, envRotation = 90.0f;
  RasterMethod raster = RasterMethod::Auto;
  // Empty: one headlight at the eye (per fragment, towards the eye), as glref shades.
  std::vector<DirectionalLight> lights;
  float ambient = 0.15f;
  float specular = 0.35f, shininess = 32.0f;  // Blinn-Phong only
  float4 background{0.0f, 0.0f, 0.0f, 1.0f};  // linear
  bool wantDepth = false, wantPrimId = false, wantNormals = false;
  // The frame ends with its raster: no shading, the visibility keys left in
  // the frame's buffers for the caller to read (rast::lib::rasterize, which
  // writes its own outputs from them).
  bool keysOnly = false;
  // Anti-aliasing. msaa: samples per pixel for coverage and depth (1, 2, 4, 8),
  // shaded once per pixel per covered triangle. ssaa: k x k shaded samples per
  // pixel (1, 2, 4). reference: 16x16 stratified samples with bilinear
  // texturing, the slow ground truth (see docs/quality.md).
  int msaa = 1;
  int ssaa = 1;
  bool reference = false;
  int referenceGrid = 16;    // samples per pixel side in reference mode
  uint32_t referenceSeed = 1;
  bool perspectiveCorrect = true;  // false: affine (screen-space) interpolation, for comparison
  PostSettings post;  // exposure, tone mapping, bloom, SSAO, HDR output (core/post/)
  // Points and lines (docs/points-lines.md): glTF point/line primitives, and
  // triangles drawn as edges or corners.
  PolygonMode polygon = PolygonMode::Fill;
  Wireframe wireframe = Wireframe::Off;
  float lineWidth = 1.0f;  // pixels, 1..64 (1: diamond-exit rule; wider: parallelogram)
  float pointSize = 1.0f;  // pixels, 1..64 (square points)
  Transparency transparency = Transparency::Auto;
  int blendK = 8;  // kbuffer: fragments kept exact per sample (1..64)
};

// Every field's bytes, as one string: two settings give the same string
// exactly when they are equal. Recorded frames are kept
// per settings (backends/frame_graphs.h).
std::string settingsKey(const RenderSettings& rs);

PolygonMode parsePolygon(const std::string& s);
Wireframe parseWireframe(const std::string& s);
const char* toString(PolygonMode m);
const char* toString(Wireframe w);

// "none", "ssaa2", "ssaa4", "msaa2", "msaa4", "msaa8" -> rs.msaa / rs.ssaa.
void parseAA(const std::string& s, RenderSettings& rs);
std::string aaName(const RenderSettings& rs);

const char* toString(ShadingMode m);
const char* toString(RasterMethod m);
const char* toString(TexFilter f);
const char* toString(CullMode c);
const char* toString(Transparency t);
Transparency parseTransparency(const std::string& s);
// Parsers for the command line; throw Error on unknown names.
ShadingMode parseShading(const std::string& s);
RasterMethod parseRaster(const std::string& s);
TexFilter parseFilter(const std::string& s);
CullMode parseCull(const std::string& s);
std::vector<RasterMethod> allRasterMethods();  // every concrete method (not Auto)

// Splits "1,2.5,-3" into finite numbers; false (out unspecified) when an item is
// empty, not a number or not finite. Callers word their own error for their flag.
bool parseFiniteList(const std::string& s, std::vector<double>& out);

}  // namespace rast
