#include "host/settings/render_settings.h"

#include "host/scene/scene.h"

#include <cmath>
#include <cstdlib>
#include <sstream>

namespace rast {
namespace {

template <class E, size_t N>
E parseEnum(const std::string& s, const std::pair<const char*, E> (&table)[N], const char* what) {
  std::string names;
  for (const auto& kv : table) {
    if (s == kv.first) return kv.second;
    names += names.empty() ? kv.first : std::string("|") + kv.first;
  }
  throw Error(std::string("unknown ") + what + " '" + s + "' (expected " + names + ")");
}

template <class E, size_t N>
const char* nameOf(E v, const std::pair<const char*, E> (&table)[N]) {
  for (const auto& kv : table)
    if (kv.second == v) return kv.first;
  return "?";
}

const std::pair<const char*, ShadingMode> kShading[] = {{"lambert", ShadingMode::Lambert},
                                                        {"blinn-phong", ShadingMode::BlinnPhong},
                                                        {"normals", ShadingMode::Normals},
                                                        {"depth", ShadingMode::Depth},
                                                        {"uv", ShadingMode::TexCoord},
                                                        {"miplevel", ShadingMode::MipLevel},
                                                        {"pbr", ShadingMode::Pbr},
                                                        {"basecolor", ShadingMode::BaseColor},
                                                        {"metalrough", ShadingMode::MetalRough},
                                                        {"occlusion", ShadingMode::Occlusion},
                                                        {"emissive", ShadingMode::Emissive},
                                                        {"shading-normals", ShadingMode::ShadingNormals}};
const std::pair<const char*, RasterMethod> kRaster[] = {
    {"auto", RasterMethod::Auto},
    {"naive", RasterMethod::Naive},
    {"visbuffer", RasterMethod::VisBuffer},
    {"binned", RasterMethod::Binned}};
const std::pair<const char*, TexFilter> kFilter[] = {
    {"nearest", TexFilter::Nearest}, {"bilinear", TexFilter::Bilinear}, {"trilinear", TexFilter::Trilinear},
    {"auto", TexFilter::Auto}};
const std::pair<const char*, Transparency> kTransparency[] = {{"auto", Transparency::Auto},
                                                              {"exact", Transparency::Exact},
                                                              {"kbuffer", Transparency::KBuffer},
                                                              {"weighted", Transparency::Weighted},
                                                              {"sorted", Transparency::Sorted}};
const std::pair<const char*, CullMode> kCull[] = {{"none", CullMode::None}, {"back", CullMode::Back}};
const std::pair<const char*, PolygonMode> kPolygon[] = {
    {"fill", PolygonMode::Fill}, {"line", PolygonMode::Line}, {"point", PolygonMode::Point}};
const std::pair<const char*, Wireframe> kWireframe[] = {
    {"off", Wireframe::Off}, {"on", Wireframe::On}, {"hidden", Wireframe::Hidden}};

}  // namespace

const char* toString(ShadingMode m) { return nameOf(m, kShading); }
const char* toString(RasterMethod m) { return nameOf(m, kRaster); }
const char* toString(TexFilter f) { return nameOf(f, kFilter); }
const char* toString(CullMode c) { return nameOf(c, kCull); }
const char* toString(Transparency t) { return nameOf(t, kTransparency); }
Transparency parseTransparency(const std::string& s) { return parseEnum(s, kTransparency, "transparency method"); }
ShadingMode parseShading(const std::string& s) { return parseEnum(s, kShading, "shading"); }
RasterMethod parseRaster(const std::string& s) { return parseEnum(s, kRaster, "raster method"); }
TexFilter parseFilter(const std::string& s) { return parseEnum(s, kFilter, "filter"); }
CullMode parseCull(const std::string& s) { return parseEnum(s, kCull, "cull mode"); }
PolygonMode parsePolygon(const std::string& s) { return parseEnum(s, kPolygon, "polygon mode"); }
Wireframe parseWireframe(const std::string& s) { return parseEnum(s, kWireframe, "wireframe mode"); }
const char* toString(PolygonMode m) { return nameOf(m, kPolygon); }
const char* toString(Wireframe w) { return nameOf(w, kWireframe); }

void parseAA(const std::string& s, RenderSettings& rs) {
  rs.msaa = rs.ssaa = 1;
  if (s == "none") return;
  if (s == "ssaa2") rs.ssaa = 2;
  else if (s == "ssaa4") rs.ssaa = 4;
  else if (s == "msaa2") rs.msaa = 2;
  else if (s == "msaa4") rs.msaa = 4;
  else if (s == "msaa8") rs.msaa = 8;
  else throw Error("unknown anti-aliasing '" + s + "' (expected none|ssaa2|ssaa4|msaa2|msaa4|msaa8)");
}

std::string aaName(const RenderSettings& rs) {
  if (rs.reference) return "reference";
  if (rs.ssaa > 1) return "ssaa" + std::to_string(rs.ssaa);
  if (rs.msaa > 1) return "msaa" + std::to_string(rs.msaa);
  return "none";
}

std::vector<RasterMethod> allRasterMethods() {
  std::vector<RasterMethod> out;
  for (const auto& kv : kRaster)
    if (kv.second != RasterMethod::Auto) out.push_back(kv.second);
  return out;
}

bool parseFiniteList(const std::string& s, std::vector<double>& out) {
  out.clear();
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) {
    char* end = nullptr;
    const double d = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0' || !std::isfinite(d)) return false;
    out.push_back(d);
  }
  return true;
}

}  // namespace rast

namespace rast {

namespace {
// The value's bytes: a key is built every frame, so no formatting.
template <class T>
void put(std::string& s, T v) {
  s.append(reinterpret_cast<const char*>(&v), sizeof v);
}
}  // namespace

// A field added to RenderSettings or PostSettings must be added here too, or
// frames with different values of it would share a recording. The sizes below
// (LP64) make the compiler point here when either struct changes.
static_assert(sizeof(void*) != 8 || sizeof(PostSettings) == 40, "PostSettings changed: update settingsKey()");
static_assert(sizeof(void*) != 8 || sizeof(RenderSettings) == 216, "RenderSettings changed: update settingsKey()");

std::string settingsKey(const RenderSettings& rs) {
  std::string s;
  s.reserve(512);
  for (long long v : {(long long)rs.width, (long long)rs.height, (long long)rs.cull, (long long)rs.shading,
                      (long long)rs.filter, (long long)rs.anisotropy, (long long)rs.raster, (long long)rs.wantDepth, (long long)rs.wantPrimId,
                      (long long)rs.keysOnly,
                      (long long)rs.wantNormals, (long long)rs.msaa, (long long)rs.ssaa, (long long)rs.reference,
                      (long long)rs.referenceGrid, (long long)rs.referenceSeed, (long long)rs.perspectiveCorrect,
                      (long long)rs.polygon, (long long)rs.wireframe, (long long)rs.transparency,
                      (long long)rs.blendK})
    put(s, v);
  for (double v : {rs.ambient, rs.specular, rs.shininess, rs.background.x, rs.background.y, rs.background.z,
                   rs.background.w, rs.lineWidth, rs.pointSize})
    put(s, v);
  put(s, (long long)rs.environment.size());
  s += rs.environment;
  for (double v : {rs.envIntensity, rs.envRotation}) put(s, v);
  put(s, (long long)rs.lights.size());
  for (const DirectionalLight& l : rs.lights)
    for (double v : {l.direction.x, l.direction.y, l.direction.z, l.intensity}) put(s, v);
  const PostSettings& p = rs.post;
  for (long long v : {(long long)p.tonemap, (long long)p.bloom, (long long)p.bloomRadius, (long long)p.ssao,
                      (long long)p.ssaoSamples, (long long)p.floatOutput})
    put(s, v);
  for (double v : {p.exposure, p.bloomThreshold, p.bloomStrength, p.ssaoRadius}) put(s, v);
  return s;
}

}  // namespace rast
