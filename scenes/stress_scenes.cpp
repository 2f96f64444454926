// The stability suite: procedural scenes aimed at the places where
// rasterisation methods are known to fail. Each is `builtin:<name>[?k=v&...]`
// and carries its own camera (eye (0,0,5) looking at the origin unless noted),
// so every renderer given the same flags sees the same frame. At that camera
// the plane z = 0 shows x in about [-3.7, 3.7] and y in [-2.07, 2.07] (16:9).
#include "scenes/stress_scenes.h"
#include "scenes/transparency_scenes.h"

#include <cmath>
#include <limits>
#include <sstream>

namespace rast {
namespace {

constexpr double kHalfH = 2.0710678;  // 5 * tan(22.5 deg)
constexpr double kHalfW = kHalfH * 16.0 / 9.0;

float4 hue(int i, int n) {
  const double h = 6.0 * (double(i) / std::max(n, 1));
  const double r = std::fabs(h - 3.0) - 1.0, g = 2.0 - std::fabs(h - 2.0), b = 2.0 - std::fabs(h - 4.0);
  auto c = [](double v) { return float(0.15 + 0.85 * std::min(std::max(v, 0.0), 1.0)); };
  return {c(r), c(g), c(b), 1.0f};
}

struct Builder {
  Scene s;
  explicit Builder(const std::string& name) {
    s.name = "builtin:" + name;
    s.camera = SceneCamera{};
  }
  int32_t material(float4 c) {
    s.materials.push_back(Material{c, -1});
    return int32_t(s.materials.size() - 1);
  }
  // One primitive drawn once, flat-shaded unless normals are given.
  void add(const std::vector<float3>& p, const std::vector<uint32_t>& idx, int32_t mat,
           const std::vector<float3>* n = nullptr, const glm::dmat4& m = glm::dmat4(1.0)) {
    s.draws.push_back(Draw{addPrim(s, p, n, nullptr, nullptr, idx, mat), m});
  }
  // An axis-aligned quad in the plane z, counter-clockwise seen from +z.
  void quad(double x0, double y0, double x1, double y1, double z, int32_t mat) {
    const float fz = float(z);
    std::vector<float3> n(4, float3{0, 0, 1});
    add({{float(x0), float(y0), fz}, {float(x1), float(y0), fz}, {float(x1), float(y1), fz}, {float(x0), float(y1), fz}},
        {0, 1, 2, 0, 2, 3}, mat, &n);
  }
  // A grid of cells x cells quads over [x0,x1]x[y0,y1] at depth z: closed (no
  // holes) and watertight, so any hole or double hit is a rasteriser bug.
  // `colour`, when given, colours each vertex from its (u, v) in [0,1]^2.
  // Rows [row0, row1) of cells only (distributed runs generate their part).
  void grid(int cells, double x0, double y0, double x1, double y1, double z, int32_t mat,
            float4 (*colour)(double u, double v) = nullptr, int row0 = 0, int row1 = -1) {
    // 2 x 8192^2 = 134M triangles; more is a typo (n=1e12), not a test scene.
    // Generated in parts, the whole may be larger (kMaxPartCells).
    if (cells > 8192 && row1 < 0) throw Error(s.name + ": at most 8192x8192 grid cells (about 134M triangles)");
    if (row1 < 0) row1 = cells;
    std::vector<float3> p, n;
    std::vector<float4> c;
    std::vector<uint32_t> idx;
    for (int j = row0; j <= row1; ++j)
      for (int i = 0; i <= cells; ++i) {
        p.push_back({float(x0 + (x1 - x0) * i / cells), float(y0 + (y1 - y0) * j / cells), float(z)});
        n.push_back({0, 0, 1});
        if (colour) c.push_back(colour(double(i) / cells, double(j) / cells));
      }
    for (int j = row0; j < row1; ++j)
      for (int i = 0; i < cells; ++i) {
        const uint32_t a = (j - row0) * (cells + 1) + i, b = a + 1, c = a + cells + 1, d = c + 1;
        idx.insert(idx.end(), {a, b, d, a, d, c});
      }
    s.draws.push_back(Draw{addPrim(s, p, &n, nullptr, colour ? &c : nullptr, idx, mat), glm::dmat4(1.0)});
  }
};

using Params = std::map<std::string, std::string>;

double num(const Params& p, const char* key, double def) {
  auto it = p.find(key);
  if (it == p.end()) return def;
  char* end = nullptr;
  const double v = std::strtod(it->second.c_str(), &end);
  if (it->second.empty() || *end || !std::isfinite(v)) throw Error(std::string("builtin scene parameter ") + key + ": '" + it->second + "' is not a number");
  return v;
}

// A count parameter within [lo, hi] (a double outside int's range would be
// undefined behaviour to convert, and a huge count an out-of-memory).
int count(const Params& p, const char* key, double def, double lo, double hi) {
  const double v = num(p, key, def);
  if (!(v >= lo && v <= hi))
    throw Error(std::string("builtin scene parameter ") + key + ": " + p.at(key) + " is outside " +
                std::to_string(int64_t(lo)) + ".." + std::to_string(int64_t(hi)));
  return int(v);
}

Scene bigtri(const Params& p) {
  // Triangles covering the whole screen and reaching far beyond it: the naive
  // method walks millions of pixels in one thread; clipping must keep the
  // fixed-point range safe.
  Builder b("bigtri");
  const double s = num(p, "scale", 1000.0);
  const float S = float(s);
  b.add({{-S, -S, 0}, {S, -S, 0}, {0, S, 0}}, {0, 1, 2}, b.material({0.9f, 0.5f, 0.2f, 1}));
  b.add({{-S, S, -1}, {S, S, -1}, {0, -S, -1}}, {0, 2, 1}, b.material({0.2f, 0.5f, 0.9f, 1}));  // behind, clockwise
  return b.s;
}

// Generated in parts (distributed runs, one part per rank), builtin:tiny may
// reach 2 x 30000^2 = 1.8 G triangles: global ids stay below 2^31.
constexpr int kMaxPartCells = 30000;

float4 tinyColour(double u, double v) {
  const double x = (u - 0.5) * 16.0 / 9.0, y = v - 0.5;
  const double angle = std::atan2(y, x) / (2.0 * M_PI) + 0.5, radius = std::sqrt(x * x + y * y);
  const float4 c = hue(int(angle * 3600.0), 3600);
  const float ring = float(0.7 + 0.3 * std::cos(radius * 40.0));
  return float4{c.x * ring, c.y * ring, c.z * ring, 1.0f};
}

int tinyCells(const Params& p, bool part) {
  const double n = count(p, "n", 1000000.0, 1, part ? 2.0 * kMaxPartCells * kMaxPartCells : 2.0 * 8192 * 8192);
  return std::max(1, int(std::sqrt(n / 2.0)));
}

// Rows [row0, row1) of the grid (row1 < 0: all of it).
Scene tinyRows(const Params& p, int row0, int row1) {
  // About n sub-pixel to pixel-sized triangles tiling the view (at 1920x1080
  // and n = 1M, two triangles share about two pixels).
  // Vertex colours (a hue wheel with rings) show that the sub-pixel triangles
  // are there: one flat colour would render as an empty grey frame.
  Builder b("tiny");
  const int cells = tinyCells(p, row1 >= 0);
  b.grid(cells, -kHalfW, -kHalfH, kHalfW, kHalfH, 0.0, b.material({1, 1, 1, 1}), tinyColour, row0, row1);
  return b.s;
}

Scene tiny(const Params& p) { return tinyRows(p, 0, -1); }

Scene overdraw(const Params& p) {
  // Full-screen layers at distinct depths: every method pays per layer; the
  // naive and visibility-buffer methods pay in atomics on the same pixels.
  Builder b("overdraw");
  const int layers = count(p, "layers", 64, 1, 65536);
  const bool frontToBack = p.count("order") && p.at("order") == "front";
  if (p.count("order") && p.at("order") != "front" && p.at("order") != "back")
    throw Error("builtin:overdraw order must be front or back");
  for (int k = 0; k < layers; ++k) {
    const int layer = frontToBack ? k : layers - 1 - k;  // layer 0 is the nearest
    const double z = -0.05 * layer;
    const double grow = 1.0 + 0.01 * layer;  // farther layers still fill the screen
    b.quad(-kHalfW * 1.1 * grow, -kHalfH * 1.1 * grow, kHalfW * 1.1 * grow, kHalfH * 1.1 * grow, z, b.material(hue(layer, layers)));
  }
  return b.s;
}

Scene slivers(const Params& p) {
  // Needles from a common centre (fan with tiny angles) and horizontal slivers
  // a fraction of a pixel tall spanning the screen.
  Builder b("slivers");
  const int n = count(p, "n", 2000, 3, 1 << 24);
  std::vector<float3> fan = {{0, 0, 0}};
  std::vector<uint32_t> fi;
  for (int k = 0; k <= n; ++k) {
    const double a = 2.0 * M_PI * k / n;
    fan.push_back({float(2.0 * std::cos(a)), float(2.0 * std::sin(a)), 0});
  }
  for (int k = 0; k < n; ++k) fi.insert(fi.end(), {0u, uint32_t(k + 1), uint32_t(k + 2)});
  b.add(fan, fi, b.material({0.9f, 0.9f, 0.3f, 1}));
  std::vector<float3> sl;
  std::vector<uint32_t> si;
  const double h = 2.0 * kHalfH / 1080.0 * 0.3;  // 0.3 pixel at 1080 rows
  for (int k = 0; k < 200; ++k) {
    const double y = -kHalfH + 2.0 * kHalfH * (k + 0.5) / 200.0;
    const uint32_t base = uint32_t(sl.size());
    sl.push_back({float(-kHalfW), float(y), 0.5f});
    sl.push_back({float(kHalfW), float(y + h * (k % 7) / 7.0), 0.5f});
    sl.push_back({float(-kHalfW), float(y + h), 0.5f});
    si.insert(si.end(), {base, base + 1, base + 2});
  }
  b.add(sl, si, b.material({0.3f, 0.9f, 0.9f, 1}));
  return b.s;
}

Scene nearplane(const Params&) {
  // A floor and a wall crossing the near plane (reaching behind the camera),
  // and triangles wholly behind it, which must draw nothing.
  Builder b("nearplane");
  b.s.camera->eye = {0, 0, 0};
  b.s.camera->target = {0, -0.3, -1};
  b.s.camera->znear = 0.1;
  b.grid(16, -4, -12, 4, 8, 0, b.material({0.8f, 0.8f, 0.8f, 1}));  // placed by the transform below
  b.s.draws.back().model = glm::dmat4(1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0, 0, -1, 0, 1);  // floor y = -1, z in [-8, 12]
  b.add({{1.5f, -1, 3}, {1.5f, -1, -6}, {1.5f, 2, -6}, {1.5f, 2, 3}}, {0, 1, 2, 0, 2, 3}, b.material({0.9f, 0.4f, 0.3f, 1}));
  b.add({{-1, -1, 2}, {1, -1, 2}, {0, 1, 2}, {-1, 0, 0.05f}, {1, 0, 0.05f}, {0, 1, 0.05f}}, {0, 1, 2, 3, 4, 5},
        b.material({0.2f, 0.9f, 0.2f, 1}));  // behind the eye, and between the eye and the near plane
  return b.s;
}

Scene degenerate(const Params&) {
  // Zero-area, repeated-vertex and non-finite triangles around two good ones.
  Builder b("degenerate");
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  b.s.materials.push_back(Material{{0.9f, 0.6f, 0.2f, 1}, -1});
  const std::vector<float3> p = {{-2, -1, 0}, {2, -1, 0},  {0, 1.5f, 0},   // good
                                 {-3, -2, 0}, {0, 0, 0},   {3, 2, 0},      // collinear
                                 {1, 1, 0},   {1, 1, 0},   {2, 0, 0},      // repeated vertex
                                 {nan, 0, 0}, {1, 1, 0},   {0, 1, 0},      // NaN
                                 {inf, 0, 0}, {1, -1, 0},  {0, -1, 0},     // +Inf
                                 {-inf, -inf, 0}, {inf, inf, 0}, {0, 0, 0},  // infinite extent
                                 {-1, -1.5f, 0.5f}, {1, -1.5f, 0.5f}, {0, -0.5f, 0.5f}};  // good
  // Positions go in as they are: the loader refuses non-finite files, but the
  // pipeline must survive such geometry from any other source.
  MeshPrim prim{0, uint32_t(p.size()), 0, uint32_t(p.size() / 3), 0};
  b.s.positions = p;
  b.s.normals.assign(p.size(), float3{0, 0, 1});
  for (uint32_t i = 0; i < p.size(); ++i) b.s.indices.push_back(i);
  b.s.prims.push_back(prim);
  b.s.draws.push_back(Draw{0, glm::dmat4(1.0)});
  return b.s;
}

Scene extreme(const Params& p) {
  // The same content at a scale around 1e6 or 1e-6 (camera scaled alike):
  // large coordinates stress the guard band and snapping, small ones depth.
  const double s = num(p, "scale", 1e6);
  if (!(s > 0)) throw Error("builtin:extreme scale must be positive");
  Builder b("extreme");
  b.grid(32, -3, -2, 3, 2, 0, b.material({0.7f, 0.7f, 0.9f, 1}));
  b.add({{-1, -1, 0.5f}, {1, -1, 0.5f}, {0, 1, 0.5f}}, {0, 1, 2}, b.material({0.9f, 0.3f, 0.3f, 1}));
  for (Draw& d : b.s.draws) d.model = glm::dmat4(s, 0, 0, 0, 0, s, 0, 0, 0, 0, s, 0, 0, 0, 0, 1);
  b.s.camera->eye *= s;
  b.s.camera->znear *= s;
  b.s.camera->zfar *= s;
  return b.s;
}

Scene zfight(const Params&) {
  // Coplanar pairs with different triangulations and colours, and two planes
  // crossing each other: the winner must not depend on scheduling.
  Builder b("zfight");
  b.grid(7, -3, -2, 3, 2, 0, b.material({0.9f, 0.2f, 0.2f, 1}));
  b.grid(5, -3, -2, 3, 2, 0, b.material({0.2f, 0.9f, 0.2f, 1}));
  b.quad(-2, -1.5, 2, 1.5, 0, b.material({0.2f, 0.2f, 0.9f, 1}));
  b.add({{-3, -2, -1}, {3, -2, 1}, {3, 2, 1}, {-3, 2, -1}}, {0, 1, 2, 0, 2, 3}, b.material({0.9f, 0.9f, 0.2f, 1}));
  return b.s;
}

Scene gridScene(const Params& p) {
  // A square grid mesh (2 n^2 triangles, side 2) for the triangle-size sweep:
  // move the camera (--eye 0,0,d) to make the same mesh tiny or huge on screen.
  Builder b("grid");
  const int n = count(p, "n", 256, 1, 8192);
  b.grid(n, -1, -1, 1, 1, 0, b.material({0.8f, 0.8f, 0.6f, 1}));
  return b.s;
}

// splitmix64 in [0, 1): the same scene on every machine.
struct Rng {
  uint64_t s;
  double next() {
    uint64_t z = (s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return double((z ^ (z >> 31)) >> 11) / double(1ull << 53);
  }
};

Scene linesScene(const Params& p) {
  // n line segments (default 1M) over the view at depths in [-1, 1]: most a
  // few to a few tens of pixels long at 1920x1080, one in a thousand spanning
  // the screen (the bounded-work case), coloured per vertex; and a quad at
  // z = 0 that hides the segments behind it.
  Builder b("lines");
  const int64_t n = std::max<int64_t>(1, int64_t(num(p, "n", 1000000.0)));
  if (n > 100000000) throw Error("builtin:lines n must be at most 1e8");
  Rng r{12345};
  std::vector<float3> pos;
  std::vector<float4> col;
  std::vector<uint32_t> seg;
  pos.reserve(size_t(2 * n));
  for (int64_t i = 0; i < n; ++i) {
    const double x = (r.next() * 2 - 1) * kHalfW, y = (r.next() * 2 - 1) * kHalfH, z = r.next() * 2 - 1;
    const double len = (i % 1000 == 0) ? 2 * kHalfW : 0.01 + 0.12 * r.next() * r.next();
    const double a = r.next() * 6.283185307179586;
    pos.push_back({float(x), float(y), float(z)});
    pos.push_back({float(x + len * std::cos(a)), float(y + len * std::sin(a)), float(z)});
    col.push_back(hue(int(i % 97), 97));
    col.push_back(hue(int(i % 97), 97));
    seg.push_back(uint32_t(2 * i));
    seg.push_back(uint32_t(2 * i + 1));
  }
  b.quad(-1.0, -1.0, 1.0, 1.0, 0.0, b.material({0.5f, 0.5f, 0.5f, 1}));
  b.s.draws.push_back(Draw{addLinePrim(b.s, pos, &col, seg, {}, b.material({1, 1, 1, 1})), glm::dmat4(1.0)});
  return b.s;
}

Scene pointsScene(const Params& p) {
  // n points (default 1M) over the view at depths in [-1, 1], coloured per
  // vertex, and the same occluding quad as builtin:lines.
  Builder b("points");
  const int64_t n = std::max<int64_t>(1, int64_t(num(p, "n", 1000000.0)));
  if (n > 100000000) throw Error("builtin:points n must be at most 1e8");
  Rng r{54321};
  std::vector<float3> pos;
  std::vector<float4> col;
  std::vector<uint32_t> pts;
  for (int64_t i = 0; i < n; ++i) {
    pos.push_back({float((r.next() * 2 - 1) * kHalfW), float((r.next() * 2 - 1) * kHalfH), float(r.next() * 2 - 1)});
    col.push_back(hue(int(i % 97), 97));
    pts.push_back(uint32_t(i));
  }
  b.quad(-1.0, -1.0, 1.0, 1.0, 0.0, b.material({0.5f, 0.5f, 0.5f, 1}));
  b.s.draws.push_back(Draw{addLinePrim(b.s, pos, &col, {}, pts, b.material({1, 1, 1, 1})), glm::dmat4(1.0)});
  return b.s;
}

Params parseParams(const std::string& q) {
  Params p;
  std::stringstream ss(q);
  std::string kv;
  while (std::getline(ss, kv, '&')) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos) throw Error("builtin scene parameter '" + kv + "' is not key=value");
    p[kv.substr(0, eq)] = kv.substr(eq + 1);
  }
  return p;
}

// One row per scene: its name, what it is for, and how it is built.
struct StressSceneRow {
  StressSceneInfo info;
  Scene (*build)(const Params&);
};

const std::vector<StressSceneRow>& stressSceneTable() {
  static const std::vector<StressSceneRow> rows = {
      {{"bigtri", "two triangles far larger than the screen (?scale=)"}, bigtri},
      {{"tiny", "a million sub-pixel triangles, vertex-coloured (?n=)"}, tiny},
      {{"overdraw", "64 full-screen layers (?layers=&order=front|back)"}, overdraw},
      {{"slivers", "needle fan and sub-pixel-thin slivers"}, slivers},
      {{"nearplane", "floor and wall crossing the near plane, eye inside"}, nearplane},
      {{"degenerate", "zero-area, NaN and infinite triangles among good ones"}, degenerate},
      {{"extreme", "the same content at 1e6 or 1e-6 scale (?scale=)"}, extreme},
      {{"zfight", "coplanar and crossing planes: ties in depth"}, zfight},
      {{"grid", "a 2n^2-triangle grid for triangle-size sweeps (?n=)"}, gridScene},
      {{"lines", "a million line segments, vertex-coloured, and an occluding quad (?n=)"}, linesScene},
      {{"points", "a million points, vertex-coloured, and an occluding quad (?n=)"}, pointsScene},
      {{"layers", "BLEND layers over an opaque backdrop (?n=&alpha=&mixed=&unlit=&back=&order=&cross=&equal=&occluder=&near_alpha=&tex=)"},
       transparencyLayers},
      {{"cutout", "a MASK quad, COLOR_0 alpha 0 to 1, over an opaque backdrop (?cutoff=&blend=)"}, transparencyCutout},
  };
  return rows;
}

}  // namespace

bool makeStressScenePart(const std::string& nameAndParams, uint64_t t0, uint64_t t1, Scene& out, uint64_t& first,
                         uint64_t& total) {
  const auto q = nameAndParams.find('?');
  if (nameAndParams.substr(0, q) != "tiny") return false;
  const Params p = parseParams(q == std::string::npos ? "" : nameAndParams.substr(q + 1));
  const uint64_t cells = uint64_t(tinyCells(p, true)), perRow = 2 * cells;
  total = perRow * cells;
  t1 = std::min(t1, total);
  t0 = std::min(t0, t1);
  const uint64_t row0 = t0 / perRow, row1 = t0 == t1 ? row0 : (t1 + perRow - 1) / perRow;
  first = row0 * perRow;
  out = tinyRows(p, int(row0), int(row1));
  out.name = "builtin:" + nameAndParams;
  return true;
}

const std::vector<StressSceneInfo>& stressScenes() {
  static const std::vector<StressSceneInfo> infos = [] {
    std::vector<StressSceneInfo> v;
    for (const StressSceneRow& r : stressSceneTable()) v.push_back(r.info);
    return v;
  }();
  return infos;
}

std::vector<std::string> stressSceneNames() {
  std::vector<std::string> v;
  for (const StressSceneInfo& i : stressScenes()) v.push_back(i.name);
  return v;
}

bool makeStressScene(const std::string& nameAndParams, Scene& out) {
  const auto q = nameAndParams.find('?');
  const std::string name = nameAndParams.substr(0, q);
  for (const StressSceneRow& r : stressSceneTable()) {
    if (name != r.info.name) continue;
    Scene s = r.build(parseParams(q == std::string::npos ? "" : nameAndParams.substr(q + 1)));
    s.name = "builtin:" + nameAndParams;
    out = std::move(s);
    return true;
  }
  return false;
}

}  // namespace rast
