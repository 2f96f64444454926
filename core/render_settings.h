// What a frame is asked to do: size, culling, shading, filtering, raster method
// and the optional outputs (AOVs).
#pragma once

#include "vec.h"

#include <string>
#include <vector>

namespace rast {

enum class CullMode { None, Back };
enum class ShadingMode { Lambert, BlinnPhong, Normals, Depth, TexCoord };
enum class TexFilter { Nearest, Bilinear };
enum class RasterMethod { Auto, Naive, VisBuffer, Binned };

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
  RasterMethod raster = RasterMethod::Auto;
  // Empty: one headlight at the eye (per fragment, towards the eye), as glref shades.
  std::vector<DirectionalLight> lights;
  float ambient = 0.15f;
  float specular = 0.35f, shininess = 32.0f;  // Blinn-Phong only
  float4 background{0.0f, 0.0f, 0.0f, 1.0f};  // linear
  bool wantDepth = false, wantPrimId = false, wantNormals = false;
};

const char* toString(ShadingMode m);
const char* toString(RasterMethod m);
const char* toString(TexFilter f);
const char* toString(CullMode c);
// Parsers for the command line; throw Error on unknown names.
ShadingMode parseShading(const std::string& s);
RasterMethod parseRaster(const std::string& s);
TexFilter parseFilter(const std::string& s);
CullMode parseCull(const std::string& s);
std::vector<RasterMethod> allRasterMethods();  // every concrete method (not Auto)

}  // namespace rast
