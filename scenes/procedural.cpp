#include "scenes/procedural.h"

#include "host/gltf/gltf_loader.h"
#include "scenes/material_probes.h"
#include "scenes/skinned_scenes.h"
#include "scenes/stress_scenes.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

namespace rast {
namespace {

uint32_t rgba(int r, int g, int b) { return uint32_t(r) | uint32_t(g) << 8 | uint32_t(b) << 16 | 0xff000000u; }

Texture checkerTexture(int size, int squares, uint32_t a, uint32_t b) {
  Texture t;
  t.width = t.height = size;
  t.rgba.resize(size_t(size) * size);
  const int cell = size / squares;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) t.rgba[size_t(y) * size + x] = ((x / cell + y / cell) & 1) ? a : b;
  return t;
}

Texture stripeTexture(int w, int h) {
  Texture t;
  t.width = w;
  t.height = h;
  t.rgba.resize(size_t(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const bool band = ((y * 8) / h) & 1;
      const bool tick = ((x * 16) / w) & 1;
      t.rgba[size_t(y) * w + x] = band ? (tick ? rgba(240, 200, 40) : rgba(220, 90, 30)) : rgba(30, 90, 200);
    }
  t.wrapS = WrapRepeat;
  t.wrapT = WrapClamp;
  return t;
}

int32_t addMaterial(Scene& s, float4 base, int32_t tex) {
  s.materials.push_back(Material{base, tex});
  return int32_t(s.materials.size() - 1);
}

void addGround(Scene& s) {
  s.textures.push_back(checkerTexture(256, 8, rgba(235, 235, 235), rgba(40, 40, 48)));
  const int32_t mat = addMaterial(s, {1, 1, 1, 1}, int32_t(s.textures.size() - 1));
  const float e = 2.6f, rep = 3.0f;
  std::vector<float3> p = {{-e, 0, e}, {e, 0, e}, {e, 0, -e}, {-e, 0, -e}};
  std::vector<float3> n(4, float3{0, 1, 0});
  std::vector<float2> uv = {{0, rep}, {rep, rep}, {rep, 0}, {0, 0}};
  std::vector<uint32_t> idx = {0, 1, 2, 0, 2, 3};
  s.draws.push_back(Draw{addPrim(s, p, &n, &uv, nullptr, idx, mat), glm::dmat4(1.0)});
}

void addColouredCube(Scene& s) {
  std::vector<float3> p, n;
  std::vector<float4> c;
  std::vector<uint32_t> idx;
  const float3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const float4 corner[4] = {{1, 0.2f, 0.2f, 1}, {0.2f, 1, 0.2f, 1}, {0.2f, 0.3f, 1, 1}, {1, 1, 0.2f, 1}};
  for (int a = 0; a < 3; ++a)
    for (int sgn = -1; sgn <= 1; sgn += 2) {
      const float3 N = axes[a] * float(sgn);
      const float3 U = axes[(a + 1) % 3], V = axes[(a + 2) % 3];
      const uint32_t b = uint32_t(p.size());
      const float su[4] = {-1, 1, 1, -1}, sv[4] = {-1, -1, 1, 1};
      for (int k = 0; k < 4; ++k) {
        p.push_back((N + U * su[k] + V * sv[k]) * 0.5f);
        n.push_back(N);
        c.push_back(corner[k]);
      }
      // Counter-clockwise seen from outside.
      if (sgn > 0) idx.insert(idx.end(), {b, b + 1, b + 2, b, b + 2, b + 3});
      else idx.insert(idx.end(), {b, b + 2, b + 1, b, b + 3, b + 2});
    }
  const int32_t mat = addMaterial(s, {1, 1, 1, 1}, -1);
  glm::dmat4 m = glm::translate(glm::dmat4(1.0), glm::dvec3(-1.3, 0.6, 0.2));
  m = glm::rotate(m, glm::radians(35.0), glm::dvec3(0, 1, 0));
  m = glm::scale(m, glm::dvec3(1.2));
  s.draws.push_back(Draw{addPrim(s, p, &n, nullptr, &c, idx, mat), m});
}

void addSphere(Scene& s) {
  s.textures.push_back(stripeTexture(128, 64));
  const int32_t mat = addMaterial(s, {1, 1, 1, 1}, int32_t(s.textures.size() - 1));
  const int seg = 48, rings = 24;
  std::vector<float3> p, n;
  std::vector<float2> uv;
  std::vector<uint32_t> idx;
  for (int r = 0; r <= rings; ++r)
    for (int k = 0; k <= seg; ++k) {
      const double th = M_PI * r / rings, ph = 2 * M_PI * k / seg;
      const float3 d{float(std::sin(th) * std::cos(ph)), float(std::cos(th)), float(-std::sin(th) * std::sin(ph))};
      p.push_back(d * 0.75f);
      n.push_back(d);
      uv.push_back({float(k) / seg, float(r) / rings});
    }
  for (int r = 0; r < rings; ++r)
    for (int k = 0; k < seg; ++k) {
      const uint32_t a = r * (seg + 1) + k, b = a + seg + 1;
      idx.insert(idx.end(), {a, b, a + 1, a + 1, b, b + 1});
    }
  s.draws.push_back(Draw{addPrim(s, p, &n, &uv, nullptr, idx, mat), glm::translate(glm::dmat4(1.0), glm::dvec3(1.3, 0.75, -0.4))});
}

void addPyramid(Scene& s) {
  std::vector<float3> p = {{-0.5f, 0, 0.5f}, {0.5f, 0, 0.5f}, {0.5f, 0, -0.5f}, {-0.5f, 0, -0.5f}, {0, 0.9f, 0}};
  std::vector<uint32_t> idx = {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4, 0, 3, 2, 0, 2, 1};
  const int32_t mat = addMaterial(s, {0.85f, 0.35f, 0.75f, 1}, -1);
  s.draws.push_back(Draw{addPrim(s, p, nullptr, nullptr, nullptr, idx, mat),
                         glm::translate(glm::dmat4(1.0), glm::dvec3(0.2, 0.0, 1.4))});
}

}  // namespace

Scene defaultScene() {
  Scene s;
  s.name = "builtin:default";
  addGround(s);
  addColouredCube(s);
  addSphere(s);
  addPyramid(s);
  // Framed by hand rather than by the bounding sphere (which leaves most of a
  // 16:9 frame empty), under a sky-blue background, with 4x MSAA for the
  // single image `rast render` writes.
  SceneCamera cam;
  cam.eye = {2.0, 2.2, 4.6};
  cam.target = {0.0, 0.45, 0.1};
  cam.fovyDeg = 40.0;
  cam.znear = 0.1;
  cam.zfar = 100.0;
  s.camera = cam;
  s.look.background = float4{0.22f, 0.30f, 0.42f, 1.0f};
  // A key light from the upper left and a fill from the front right, fixed in
  // the world so that every view (and the viewer's orbit) is lit alike.
  s.look.lights = {float4{-0.4f, 0.8f, 0.5f, 0.75f}, float4{0.6f, 0.3f, 0.8f, 0.35f}};
  s.look.msaa = 4;
  s.validate();
  return s;
}

std::vector<std::string> builtinSceneNames() {
  std::vector<std::string> n;
  for (const BuiltinSceneInfo& b : builtinScenes()) n.push_back(b.name);
  return n;
}

const std::vector<BuiltinSceneInfo>& builtinScenes() {
  static const std::vector<BuiltinSceneInfo> all = [] {
    std::vector<BuiltinSceneInfo> v = {{"default", "checkered ground, vertex-coloured cube, textured sphere, pyramid"}};
    for (const StressSceneInfo& st : stressScenes()) v.push_back({st.name, st.description});
    for (const ProbeSceneInfo& p : probeScenes()) v.push_back({p.name, p.description});
    for (const MotionSceneInfo& ms : motionScenes()) v.push_back({ms.name, ms.description});
    return v;
  }();
  return all;
}

Scene builtinScene(const std::string& spec) {
  const std::string name = spec.substr(spec.find(':') + 1);
  if (name == "default") return defaultScene();
  Scene s;
  if (makeStressScene(name, s)) return s;
  if (makeProbeScene(name, s)) return s;
  if (makeMotionScene(name, s)) return s;
  std::string names;
  for (const auto& n : builtinSceneNames()) names += " " + n;
  throw Error("unknown builtin scene '" + name + "' (available:" + names + ")");
}

Scene loadSceneArg(const std::string& arg, const LoadOptions& options) {
  if (arg.empty()) return defaultScene();
  if (arg.rfind("builtin:", 0) == 0) return builtinScene(arg);
  return loadGltf(arg, options);
}

}  // namespace rast
