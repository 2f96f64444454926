// The feature probes (scenes/material_probes.h): each scene small, lit only by
// its KHR_lights_punctual lights, its textures a few texels magnified on
// screen (so that both renderers sample level 0 and mip selection, which
// legitimately differs, plays no part), its camera its own.
#include "scenes/material_probes.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

namespace rast {
namespace {

uint32_t rgba(int r, int g, int b, int a = 255) {
  return uint32_t(r) | uint32_t(g) << 8 | uint32_t(b) << 16 | uint32_t(a) << 24;
}

float3 normalized(float3 v) {
  const float n = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
  return v * (1.0f / n);
}
float3 cross3(float3 a, float3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
float dot3(float3 a, float3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

int32_t addMaterial(Scene& s, const Material& m) {
  s.materials.push_back(m);
  return int32_t(s.materials.size() - 1);
}

int32_t addTexture(Scene& s, Texture t) {
  s.textures.push_back(std::move(t));
  return int32_t(s.textures.size() - 1);
}

Material matte(float4 base, float roughness = 1.0f, float metallic = 0.0f) {
  Material m;
  m.baseColorFactor = base;
  m.roughness = roughness;
  m.metallic = metallic;
  return m;
}

// A quad centred at c spanning c +- U +- V, facing N = U x V (counter-clockwise
// seen from there); uv[k] at the corners (-U-V, +U-V, +U+V, -U+V). Returns the
// primitive. World coordinates: the draw's matrix is the identity.
uint32_t addQuad(Scene& s, float3 c, float3 U, float3 V, const float2 (&uv)[4], int32_t mat) {
  const float3 N = normalized(cross3(U, V));
  std::vector<float3> p = {c - U - V, c + U - V, c + U + V, c - U + V};
  std::vector<float3> n(4, N);
  std::vector<float2> t(uv, uv + 4);
  std::vector<uint32_t> idx = {0, 1, 2, 0, 2, 3};
  const uint32_t prim = addPrim(s, p, &n, &t, nullptr, idx, mat);
  s.draws.push_back(Draw{prim, glm::dmat4(1.0)});
  return prim;
}

const float2 kUnitUv[4] = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};

// A UV sphere of radius r at c (seg x rings), counter-clockwise from outside.
void addSphere(Scene& s, float3 c, float r, int32_t mat, int seg = 40, int rings = 20) {
  std::vector<float3> p, n;
  std::vector<float2> uv;
  std::vector<uint32_t> idx;
  for (int i = 0; i <= rings; ++i)
    for (int k = 0; k <= seg; ++k) {
      const double th = M_PI * i / rings, ph = 2 * M_PI * k / seg;
      const float3 d{float(std::sin(th) * std::cos(ph)), float(std::cos(th)), float(-std::sin(th) * std::sin(ph))};
      p.push_back(c + d * r);
      n.push_back(d);
      uv.push_back({float(k) / seg, float(i) / rings});
    }
  for (int i = 0; i < rings; ++i)
    for (int k = 0; k < seg; ++k) {
      const uint32_t a = i * (seg + 1) + k, b = a + seg + 1;
      idx.insert(idx.end(), {a, b, a + 1, a + 1, b, b + 1});
    }
  s.draws.push_back(Draw{addPrim(s, p, &n, &uv, nullptr, idx, mat), glm::dmat4(1.0)});
}

PunctualLight light(LightType type, float3 color, float intensity, float3 position, float3 direction) {
  PunctualLight l;
  l.type = type;
  l.color = color;
  l.intensity = intensity;
  l.position = position;
  l.direction = normalized(direction);
  return l;
}

void finish(Scene& s, glm::dvec3 eye, glm::dvec3 target, double fovy) {
  SceneCamera cam;
  cam.eye = eye;
  cam.target = target;
  cam.fovyDeg = fovy;
  cam.znear = 0.1;
  cam.zfar = 50.0;
  s.camera = cam;
  s.look.background = float4{0.0f, 0.0f, 0.0f, 1.0f};
  s.look.gltfMaterials = true;
  s.validate();
}

// 5 x 5 spheres: metallic 0 .. 1 left to right, roughness 0.2 .. 1 top to
// bottom (0 would make the highlight of a punctual light a single texel-sized
// spike, all aliasing), one orange base colour, under a directional light.
Scene spheres() {
  Scene s;
  for (int row = 0; row < 5; ++row)
    for (int col = 0; col < 5; ++col) {
      const int32_t m = addMaterial(s, matte({0.9f, 0.55f, 0.2f, 1.0f}, 0.2f + 0.2f * row, 0.25f * col));
      addSphere(s, {1.0f * (col - 2), 1.0f * (2 - row), 0.0f}, 0.42f, m);
    }
  s.lights.push_back(light(LightType::Directional, {1, 1, 1}, 3.0f, {0, 0, 0}, {-0.4f, -0.6f, -0.7f}));
  finish(s, {0, 0, 8.2}, {0, 0, 0}, 40);
  return s;
}

// Bumps as a tangent-space normal texture (n x n texels, `bumps` across).
Texture bumpNormals(int n, int bumps) {
  Texture t;
  t.width = t.height = n;
  t.rgba.resize(size_t(n) * n);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      // Height h = sin(2 pi b u) * sin(2 pi b v); the normal (-dh/du, dh/dv, 1) up the image.
      const double u = (x + 0.5) / n, v = (y + 0.5) / n, w = 2 * M_PI * bumps;
      const double dhu = 0.12 * w * std::cos(w * u) * std::sin(w * v), dhv = 0.12 * w * std::sin(w * u) * std::cos(w * v);
      const double nx = -dhu, ny = dhv, nz = 1.0, len = std::sqrt(nx * nx + ny * ny + nz * nz);
      const auto byte = [](double c) { return int(std::lround((c * 0.5 + 0.5) * 255.0)); };
      t.rgba[size_t(y) * n + x] = rgba(byte(nx / len), byte(ny / len), byte(nz / len));
    }
  return t;
}

// Two normal-mapped squares facing the camera, lit from the left at a grazing
// angle: the left with scale 1, the right with scale 2 and its coordinates
// turned by 90 degrees (another tangent frame); the file carries TANGENT.
Scene normalMap() {
  Scene s;
  const int32_t tex = addTexture(s, bumpNormals(24, 3));
  Material left = matte({0.8f, 0.8f, 0.8f, 1.0f}, 0.5f);
  left.normalTexture = tex;
  Material right = left;
  right.normalScale = 2.0f;
  const float2 turned[4] = {{1, 1}, {1, 0}, {0, 0}, {0, 1}};
  const float3 U{0.9f, 0, 0}, V{0, 0.9f, 0};
  addQuad(s, {-1.0f, 0, 0}, U, V, kUnitUv, addMaterial(s, left));
  addQuad(s, {1.0f, 0, 0}, U, V, turned, addMaterial(s, right));
  // Tangents: T = dP/du, w so that w N x T = -dP/dv (glTF's bitangent points up the image).
  s.tangents.assign(s.positions.size(), float4{0, 0, 0, 0});
  for (const MeshPrim& p : s.prims) {
    const float3* P = &s.positions[p.firstVertex];
    const float2* T = &s.uvs[p.firstVertex];
    const float3 e1 = P[1] - P[0], e2 = P[3] - P[0];
    const float du1 = T[1].x - T[0].x, dv1 = T[1].y - T[0].y, du2 = T[3].x - T[0].x, dv2 = T[3].y - T[0].y;
    const float det = du1 * dv2 - du2 * dv1;
    const float3 dPdu = normalized((e1 * dv2 - e2 * dv1) * (1.0f / det));
    const float3 dPdv = (e2 * du1 - e1 * du2) * (1.0f / det);
    const float3 N = s.normals[p.firstVertex];
    const float w = dot3(cross3(N, dPdu), dPdv * -1.0f) >= 0.0f ? 1.0f : -1.0f;
    for (uint32_t k = 0; k < p.vertexCount; ++k) s.tangents[p.firstVertex + k] = float4{dPdu.x, dPdu.y, dPdu.z, w};
  }
  s.lights.push_back(light(LightType::Directional, {1, 1, 1}, 3.0f, {0, 0, 0}, {1.0f, -0.25f, -0.45f}));
  finish(s, {0, 0, 4.2}, {0, 0, 0}, 40);
  return s;
}

// An sRGB texture of n x n texels: bands of colour, values scaled by `gain`.
Texture bands(int n, double gain) {
  Texture t;
  t.width = t.height = n;
  t.rgba.resize(size_t(n) * n);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const int k = (x + 2 * y) % 4;
      const int c[4][3] = {{250, 60, 40}, {40, 220, 90}, {50, 90, 250}, {240, 240, 240}};
      t.rgba[size_t(y) * n + x] = rgba(int(c[k][0] * gain), int(c[k][1] * gain), int(c[k][2] * gain));
    }
  t.magFilter = 9728;  // nearest: crisp texels
  t.minFilter = 9728;
  return t;
}

// Four squares, dark base colours under a dim light: emissive factor alone;
// an emissive texture; a dark emissive texture times KHR_materials_emissive_strength
// 2.5; emission on a lit, textured base colour.
Scene emissive() {
  Scene s;
  const int32_t bright = addTexture(s, bands(4, 1.0)), dark = addTexture(s, bands(4, 0.55));
  Material a = matte({0.15f, 0.15f, 0.15f, 1.0f}, 0.7f);
  a.emissive = {1.0f, 0.45f, 0.1f};
  Material b = a;
  b.emissive = {1.0f, 1.0f, 1.0f};
  b.emissiveTexture = bright;
  Material c = b;
  c.emissiveTexture = dark;
  c.emissive = {2.5f, 2.5f, 2.5f};  // factor 1 x strength 2.5
  Material d = matte({1, 1, 1, 1}, 0.6f);
  d.texture = bright;
  d.emissive = {0.0f, 0.1f, 0.3f};
  const float3 U{0.42f, 0, 0}, V{0, 0.42f, 0};
  addQuad(s, {-0.5f, 0.5f, 0}, U, V, kUnitUv, addMaterial(s, a));
  addQuad(s, {0.5f, 0.5f, 0}, U, V, kUnitUv, addMaterial(s, b));
  addQuad(s, {-0.5f, -0.5f, 0}, U, V, kUnitUv, addMaterial(s, c));
  addQuad(s, {0.5f, -0.5f, 0}, U, V, kUnitUv, addMaterial(s, d));
  s.lights.push_back(light(LightType::Directional, {1, 1, 1}, 0.8f, {0, 0, 0}, {-0.2f, -0.3f, -1.0f}));
  finish(s, {0, 0, 3.0}, {0, 0, 0}, 40);
  return s;
}

// 8 x 8 texels, alpha k/7 in column k, colours by row; nearest filtering so
// that every texel's alpha is exact.
Texture alphaSteps() {
  Texture t;
  t.width = t.height = 8;
  t.rgba.resize(64);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x)
      t.rgba[size_t(y) * 8 + x] = rgba(80 + 20 * y, 230 - 20 * y, 120, int(std::lround(255.0 * x / 7)));
  t.magFilter = 9728;
  t.minFilter = 9728;
  return t;
}

// Over a grey backdrop (so that a discarded fragment shows it, not the
// background): MASK at cutoff 0.5; MASK at 0.2; MASK at 0.5 with
// baseColorFactor alpha 0.6; OPAQUE with the same texture (alpha ignored);
// then two squares seen from behind: single-sided (culled) and double-sided
// (lit with its normal turned).
Scene mask() {
  Scene s;
  const int32_t tex = addTexture(s, alphaSteps());
  addQuad(s, {0, 0, -0.6f}, {3.5f, 0, 0}, {0, 3.5f, 0}, kUnitUv, addMaterial(s, matte({0.35f, 0.35f, 0.4f, 1.0f})));
  Material m = matte({1, 1, 1, 1}, 0.8f);
  m.texture = tex;
  m.alphaMode = AlphaMode::Mask;
  Material low = m;
  low.alphaCutoff = 0.2f;
  Material faded = m;
  faded.baseColorFactor.w = 0.6f;
  Material opaque = m;
  opaque.alphaMode = AlphaMode::Opaque;
  Material single = matte({0.9f, 0.3f, 0.3f, 1.0f}, 0.8f), twoSided = single;
  twoSided.doubleSided = true;
  const float3 U{0.42f, 0, 0}, V{0, 0.42f, 0};
  addQuad(s, {-1.0f, 0.5f, 0}, U, V, kUnitUv, addMaterial(s, m));
  addQuad(s, {0.0f, 0.5f, 0}, U, V, kUnitUv, addMaterial(s, low));
  addQuad(s, {1.0f, 0.5f, 0}, U, V, kUnitUv, addMaterial(s, faded));
  addQuad(s, {-1.0f, -0.5f, 0}, U, V, kUnitUv, addMaterial(s, opaque));
  // Facing away from the camera (-z): U x V = -z.
  addQuad(s, {0.0f, -0.5f, 0}, V, U, kUnitUv, addMaterial(s, single));
  addQuad(s, {1.0f, -0.5f, 0}, V, U, kUnitUv, addMaterial(s, twoSided));
  s.lights.push_back(light(LightType::Directional, {1, 1, 1}, 2.5f, {0, 0, 0}, {0.2f, -0.3f, -1.0f}));
  finish(s, {0, 0, 3.6}, {0, 0, 0}, 40);
  return s;
}

// A 4 x 4 texture no symmetry maps onto itself: a hue ramp along u, a value
// ramp along v, a white corner texel at (0, 0).
Texture asymmetric() {
  Texture t;
  t.width = t.height = 4;
  t.rgba.resize(16);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) t.rgba[size_t(y) * 4 + x] = rgba(60 + 60 * x, 40 + 50 * y, 200 - 40 * x);
  t.rgba[0] = rgba(255, 255, 255);
  t.magFilter = 9728;
  t.minFilter = 9728;
  return t;
}

// Six squares, coordinates -1 .. 2 (three periods): wrap REPEAT, CLAMP_TO_EDGE
// and MIRRORED_REPEAT on both axes (top row); REPEAT x CLAMP, MIRRORED x
// REPEAT, and REPEAT with linear magnification (bottom row; the others nearest).
Scene wrap() {
  Scene s;
  const int32_t modes[6][2] = {{WrapRepeat, WrapRepeat}, {WrapClamp, WrapClamp}, {WrapMirror, WrapMirror},
                               {WrapRepeat, WrapClamp},  {WrapMirror, WrapRepeat}, {WrapRepeat, WrapRepeat}};
  const float2 uv[4] = {{-1, 2}, {2, 2}, {2, -1}, {-1, -1}};
  const float3 U{0.44f, 0, 0}, V{0, 0.44f, 0};
  for (int k = 0; k < 6; ++k) {
    Texture t = asymmetric();
    t.wrapS = modes[k][0];
    t.wrapT = modes[k][1];
    if (k == 5) {
      t.magFilter = 9729;
      t.minFilter = 9729;
    }
    Material m = matte({1, 1, 1, 1}, 1.0f);
    m.texture = addTexture(s, t);
    addQuad(s, {1.0f * (k % 3 - 1), k < 3 ? 0.5f : -0.5f, 0}, U, V, uv, addMaterial(s, m));
  }
  s.lights.push_back(light(LightType::Directional, {1, 1, 1}, 3.0f, {0, 0, 0}, {0, 0, -1}));
  finish(s, {0, 0, 3.4}, {0, 0, 0}, 40);
  return s;
}

// A floor and a sphere under every light type: a dim blue directional light,
// a red point light with a range of 1.6 (its window's edge a circle on the
// floor), a green spot light with inner and outer cones of 0.25 and 0.5 rad,
// and a white point light without range.
Scene lights() {
  Scene s;
  addQuad(s, {0, 0, 0}, {3.0f, 0, 0}, {0, 0, -3.0f}, kUnitUv, addMaterial(s, matte({0.8f, 0.8f, 0.8f, 1.0f}, 0.9f)));
  addSphere(s, {0, 0.45f, 0}, 0.45f, addMaterial(s, matte({0.9f, 0.9f, 0.9f, 1.0f}, 0.5f)));
  s.lights.push_back(light(LightType::Directional, {0.4f, 0.5f, 1.0f}, 0.5f, {0, 0, 0}, {0.3f, -1.0f, -0.2f}));
  PunctualLight point = light(LightType::Point, {1.0f, 0.3f, 0.2f}, 2.0f, {-1.3f, 0.5f, 0.4f}, {0, 0, -1});
  point.range = 1.6f;
  s.lights.push_back(point);
  PunctualLight spot = light(LightType::Spot, {0.3f, 1.0f, 0.4f}, 6.0f, {1.3f, 1.5f, 0.2f}, {0.0f, -1.0f, -0.25f});
  spot.innerConeAngle = 0.25f;
  spot.outerConeAngle = 0.5f;
  s.lights.push_back(spot);
  s.lights.push_back(light(LightType::Point, {1, 1, 1}, 1.5f, {0.0f, 1.6f, 1.6f}, {0, 0, -1}));
  const char* names[4] = {"sun", "point_range", "spot", "point"};
  for (int k = 0; k < 4; ++k) s.lights[size_t(k)].name = names[k];
  finish(s, {0, 3.2, 3.6}, {0, 0.1, 0}, 45);
  return s;
}

// Four squares with one nearest-filtered texture and plain coordinates 0 .. 1:
// rast keeps no KHR_texture_transform (it bakes it into the coordinates at
// load), so the golden's file gets its transforms from the test's edit of the
// export (tests/support/probe_files.py: offset, rotation, scale, all three).
Scene transform() {
  Scene s;
  Texture t = asymmetric();
  t.wrapS = t.wrapT = WrapMirror;
  const int32_t tex = addTexture(s, t);
  const float3 U{0.42f, 0, 0}, V{0, 0.42f, 0};
  for (int k = 0; k < 4; ++k) {
    Material m = matte({1, 1, 1, 1}, 1.0f);
    m.texture = tex;
    addQuad(s, {k % 2 ? 0.5f : -0.5f, k < 2 ? 0.5f : -0.5f, 0}, U, V, kUnitUv, addMaterial(s, m));
  }
  s.lights.push_back(light(LightType::Directional, {1, 1, 1}, 3.0f, {0, 0, 0}, {0, 0, -1}));
  finish(s, {0, 0, 3.0}, {0, 0, 0}, 40);
  return s;
}

// Stripes for a clear coat's textures (linear data, nearest), 8 x 4 texels:
// R (the coat) 255 and 0 in alternate columns (45 degrees of a sphere's
// longitude each), G (its roughness) 255 and 128 in alternate rows.
Texture coatStripes() {
  Texture t;
  t.width = 8;
  t.height = 4;
  t.rgba.resize(32);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 8; ++x) t.rgba[size_t(y) * 8 + x] = rgba(x % 2 ? 0 : 255, y % 2 ? 128 : 255, 0);
  t.magFilter = 9728;
  t.minFilter = 9728;
  return t;
}

// KHR_materials_clearcoat over one blue, fairly rough base, under a
// directional light from the upper left: a sphere without a coat; a coat of
// factor 1 and roughness 0.2 (a second, sharp highlight, and the base dimmed
// by its Fresnel term towards the rim); a coat of roughness 0.5 (a broad
// lobe) whose factor and roughness follow a striped texture (R and G); and a
// square whose coat (roughness 0.35) has its own normal map (bumps) over a
// flat base (the file carries TANGENT).
Scene clearcoat() {
  Scene s;
  const int32_t stripes = addTexture(s, coatStripes()), bumps = addTexture(s, bumpNormals(24, 3));
  const Material base = matte({0.1f, 0.15f, 0.6f, 1.0f}, 0.6f);
  Material coat = base;
  coat.clearcoat = 1.0f;
  coat.clearcoatRoughness = 0.2f;
  Material textured = coat;
  textured.clearcoatTexture = stripes;
  textured.clearcoatRoughness = 0.5f;
  textured.clearcoatRoughnessTexture = stripes;
  Material normal = coat;
  normal.clearcoatRoughness = 0.35f;
  normal.clearcoatNormalTexture = bumps;
  addSphere(s, {-0.55f, 0.5f, 0}, 0.42f, addMaterial(s, base));
  addSphere(s, {0.55f, 0.5f, 0}, 0.42f, addMaterial(s, coat));
  addSphere(s, {-0.55f, -0.5f, 0}, 0.42f, addMaterial(s, textured));
  const uint32_t quad = addQuad(s, {0.55f, -0.5f, 0}, {0.42f, 0, 0}, {0, 0.42f, 0}, kUnitUv, addMaterial(s, normal));
  // The square's tangents (T = +x: u grows along U; v grows down the image,
  // against V: w = +1), none on the spheres.
  s.tangents.assign(s.positions.size(), float4{0, 0, 0, 0});
  const MeshPrim& q = s.prims[quad];
  for (uint32_t k = 0; k < q.vertexCount; ++k) s.tangents[q.firstVertex + k] = float4{1, 0, 0, 1};
  s.lights.push_back(light(LightType::Directional, {1, 1, 1}, 3.0f, {0, 0, 0}, {0.45f, -0.5f, -0.75f}));
  finish(s, {0, 0, 3.6}, {0, 0, 0}, 40);
  return s;
}

struct ProbeRow {
  ProbeSceneInfo info;
  Scene (*build)();
};

const std::vector<ProbeRow>& probeTable() {
  static const std::vector<ProbeRow> rows = {
      {{"probe-spheres", "glTF probe: 5x5 spheres, metallic x roughness, one directional light"}, spheres},
      {{"probe-normalmap", "glTF probe: normal-mapped squares (scale 1 and 2, two tangent frames)"}, normalMap},
      {{"probe-emissive", "glTF probe: emissive factor, texture and KHR_materials_emissive_strength"}, emissive},
      {{"probe-mask", "glTF probe: alphaMode MASK cutoffs, OPAQUE alpha, single- and double-sided"}, mask},
      {{"probe-wrap", "glTF probe: REPEAT, CLAMP_TO_EDGE, MIRRORED_REPEAT, nearest and linear"}, wrap},
      {{"probe-transform", "glTF probe: textured squares for KHR_texture_transform (added to the export by the test)"},
       transform},
      {{"probe-lights", "glTF probe: directional, point (with and without range) and spot lights"}, lights},
      {{"probe-clearcoat", "glTF probe: KHR_materials_clearcoat factor, roughness, textures and normal map"}, clearcoat},
  };
  return rows;
}

}  // namespace

const std::vector<ProbeSceneInfo>& probeScenes() {
  static const std::vector<ProbeSceneInfo> infos = [] {
    std::vector<ProbeSceneInfo> v;
    for (const ProbeRow& r : probeTable()) v.push_back(r.info);
    return v;
  }();
  return infos;
}

bool makeProbeScene(const std::string& name, Scene& out) {
  for (const ProbeRow& r : probeTable()) {
    if (name != r.info.name) continue;
    out = r.build();
    out.name = "builtin:" + name;
    return true;
  }
  return false;
}

}  // namespace rast
