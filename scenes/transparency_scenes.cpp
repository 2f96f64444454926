// The alpha-mode scenes (transparency_scenes.h): where blending methods are
// known to fail (many layers, mixed alphas, intersecting and coplanar layers,
// strong layers in front) and the MASK cut-out, each with the stress suite's
// camera (eye (0,0,5) looking at the origin; the plane z = 0 shows x in about
// [-3.7, 3.7] and y in [-2.07, 2.07]).
#include "scenes/transparency_scenes.h"

#include <cmath>
#include <cstdlib>

namespace rast {
namespace {

using Params = std::map<std::string, std::string>;
constexpr double kHalfH = 2.0710678, kHalfW = kHalfH * 16.0 / 9.0;

double param(const Params& p, const char* key, double def, double lo, double hi) {
  auto it = p.find(key);
  if (it == p.end()) return def;
  char* end = nullptr;
  const double v = std::strtod(it->second.c_str(), &end);
  if (it->second.empty() || *end || !std::isfinite(v) || v < lo || v > hi)
    throw Error(std::string("builtin scene parameter ") + key + ": '" + it->second + "' is not a number in " +
                std::to_string(lo) + ".." + std::to_string(hi));
  return v;
}

int32_t material(Scene& s, float4 c, AlphaMode mode, bool unlit, float cutoff = 0.5f) {
  Material m;
  m.baseColorFactor = c;
  m.alphaMode = mode;
  m.alphaCutoff = cutoff;
  m.unlit = unlit;
  s.materials.push_back(m);
  return int32_t(s.materials.size() - 1);
}

// A quad over [x0,x1]x[y0,y1], its corners' depths z (lower left, lower right,
// upper right, upper left), counter-clockwise seen from +z.
// uv: texture coordinates 0..1 across it.
void quad(Scene& s, double x0, double y0, double x1, double y1, const double (&z)[4], int32_t mat,
          const std::vector<float4>* col = nullptr, bool uv = false) {
  const std::vector<float3> p = {{float(x0), float(y0), float(z[0])}, {float(x1), float(y0), float(z[1])},
                                 {float(x1), float(y1), float(z[2])}, {float(x0), float(y1), float(z[3])}};
  const std::vector<float3> n(4, float3{0, 0, 1});
  const std::vector<float2> t = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
  s.draws.push_back(Draw{addPrim(s, p, &n, uv ? &t : nullptr, col, {0, 1, 2, 0, 2, 3}, mat), glm::dmat4(1.0)});
}

Scene start(const char* name) {
  Scene s;
  s.name = std::string("builtin:") + name;
  s.camera = SceneCamera{};
  return s;
}

}  // namespace

Scene transparencyLayers(const Params& p) {
  Scene s = start("layers");
  const int n = int(param(p, "n", 8, 0, 4096));  // 0: the opaque backdrop alone
  const float alpha = float(param(p, "alpha", 0.5, -1e30, 1e30));
  const bool mixed = param(p, "mixed", 0, 0, 1) != 0, unlit = param(p, "unlit", 1, 0, 1) != 0;
  const bool back = param(p, "back", 1, 0, 1) != 0, cross = param(p, "cross", 0, 0, 1) != 0;
  const bool equal = param(p, "equal", 0, 0, 1) != 0;
  // tex: the layers' base colour textured (2x2 texels, grey to white): no
  // layer has one colour.
  const bool tex = param(p, "tex", 0, 0, 1) != 0;
  if (tex) s.textures.push_back(Texture{2, 2, {0xff808080u, 0xffffffffu, 0xffffffffu, 0xff808080u}});
  // An opaque quad among the layers, its edges across 8x8 blocks: the layers
  // behind it hidden, those in front over it.
  const bool occluder = param(p, "occluder", 0, 0, 1) != 0;
  const double nearest = param(p, "near_alpha", -1, -1, 1);  // >= 0: the nearest layer's alpha (a strong layer in front)
  const bool front = p.count("order") && p.at("order") == "front";
  if (p.count("order") && !front && p.at("order") != "back") throw Error("builtin:layers order must be back or front");
  if (back) {
    const double z[4] = {-1.0, -1.0, -1.0, -1.0};
    quad(s, -kHalfW * 1.5, -kHalfH * 1.5, kHalfW * 1.5, kHalfH * 1.5, z, material(s, {1, 0, 0, 1}, AlphaMode::Opaque, unlit));
  }
  if (occluder) {
    const double z[4] = {-0.42, -0.42, -0.42, -0.42};
    quad(s, -kHalfW * 0.43, -kHalfH * 0.37, kHalfW * 0.31, kHalfH * 0.29, z, material(s, {0, 1, 0, 1}, AlphaMode::Opaque, unlit));
  }
  for (int k = 0; k < n; ++k) {
    const int layer = front ? k : n - 1 - k;  // layer 0 is the nearest
    const double zc = equal ? 0.0 : -0.9 * double(layer) / double(n);
    float4 c{0, 0, 1, alpha};
    if (mixed) {
      const double h = 6.0 * double(layer) / double(n);
      c = float4{float(std::fabs(std::fmod(h, 2.0) - 1.0)), float(layer % 3) / 2.0f, float(1 - layer % 2),
                 float(0.2 + 0.7 * std::fmod(layer * 0.618034, 1.0))};
    }
    if (layer == 0 && nearest >= 0.0) c.w = float(nearest);
    // Neighbours tilted opposite ways about the vertical axis cross mid-screen.
    const double t = cross ? (layer % 2 ? 0.08 : -0.08) : 0.0;
    const double z[4] = {zc - t, zc + t, zc + t, zc - t};
    const int32_t mat = material(s, c, AlphaMode::Blend, unlit);
    if (tex) s.materials[size_t(mat)].texture = 0;
    quad(s, -kHalfW * 1.2, -kHalfH * 1.2, kHalfW * 1.2, kHalfH * 1.2, z, mat, nullptr, tex);
  }
  return s;
}

Scene transparencyCutout(const Params& p) {
  Scene s = start("cutout");
  const float cutoff = float(param(p, "cutoff", 0.5, -1e30, 1e30));
  const bool blend = param(p, "blend", 0, 0, 1) != 0;
  const double zb[4] = {-1.0, -1.0, -1.0, -1.0}, zf[4] = {0.0, 0.0, 0.0, 0.0};
  quad(s, -kHalfW * 1.5, -kHalfH * 1.5, kHalfW * 1.5, kHalfH * 1.5, zb, material(s, {1, 0, 0, 1}, AlphaMode::Opaque, true));
  const std::vector<float4> col = {{1, 1, 1, 0}, {1, 1, 1, 1}, {1, 1, 1, 1}, {1, 1, 1, 0}};
  quad(s, -2.0, -1.5, 2.0, 1.5, zf, material(s, {0, 1, 0, 1}, blend ? AlphaMode::Blend : AlphaMode::Mask, true, cutoff),
       &col);
  return s;
}

}  // namespace rast
