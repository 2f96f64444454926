// glblend: a glTF scene's BLEND materials drawn the way engines draw them on a
// hardware rasterizer, to time and check rast's transparency against
// (docs/transparency.md, "Against the hardware rasterizer's blending"; issue
// #39). glref (../shared/tools/glref) draws every material opaque; this reuses
// its loader, EGL context and PNG writer and draws:
//   1. OPAQUE and MASK draws (MASK: discard below alphaCutoff) with the depth
//      test (LESS) and depth writes, blending off;
//   2. BLEND draws with the depth test (LESS) and no depth writes, sorted back
//      to front by the view depth of their bounding box centre (rast's
//      `--transparency sorted` key: pipeline/blend/frag_shade.h sortedKey; equal
//      depths keep submission order, so a later draw lies in front), blended
//      premultiplied "over" (glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA)) into a
//      float framebuffer (RGBA16F or RGBA32F): in linear light.
// Shading is unlit (KHR_materials_unlit): baseColorFactor x baseColorTexture x
// COLOR_0, alpha from the same product clamped to [0, 1] (NaN: 0). Lit
// materials are drawn unlit too, and counted on stdout. The sort runs on the
// host every frame, inside the timed frame, as an engine's would.
//
//   glblend SCENE.gltf|.glb [--size WxH] [--eye x,y,z --target x,y,z --up x,y,z --fovy D --near N --far F]
//           [--auto-camera] [--frames N] [--warmup N] [--film rgba16f|rgba32f] [--no-sort]
//           [--out-png F.png] [--out-pfm F.pfm] [--json F.json] [--csv F.csv] [--egl auto|device|surfaceless|default]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numeric>
#include <string>
#include <vector>

#include <epoxy/gl.h>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <tiny_gltf.h>

#include "egl_context.h"
#include "image_io.h"
#include "scene.h"

namespace {

using Clock = std::chrono::steady_clock;

struct Options {
  std::string scene;
  int width = 1920, height = 1080;
  glm::dvec3 eye{0.0, 0.0, 3.0}, target{0.0}, up{0.0, 1.0, 0.0};
  double fovy = 45.0, znear = 0.1, zfar = 1000.0;
  bool autoCamera = false, sort = true, verbose = false;
  int frames = 100, warmup = 10;
  std::string film = "rgba16f", outPng, outPfm, json, csv, egl = "auto";
  int eglDevice = -1;
};

[[noreturn]] void usage(const std::string& msg = "") {
  if (!msg.empty()) {  // one line, as rast's errors
    std::fprintf(stderr, "glblend: error: %s (glblend --help)\n", msg.c_str());
    std::exit(2);
  }
  std::fprintf(stdout,
               "usage: glblend SCENE.gltf|SCENE.glb [--size WxH] [--eye x,y,z] [--target x,y,z] [--up x,y,z]\n"
               "               [--fovy DEG] [--near N] [--far F] [--auto-camera] [--frames N] [--warmup N]\n"
               "               [--film rgba16f|rgba32f] [--no-sort] [--out-png F.png] [--out-pfm F.pfm]\n"
               "               [--json F.json] [--csv F.csv] [--egl auto|device|surfaceless|default] [--egl-device I]\n");
  std::exit(0);  // --help
}

glm::dvec3 parseVec3(const char* s) {
  double v[3];
  char tail = 0;
  if (std::sscanf(s, "%lf,%lf,%lf%c", &v[0], &v[1], &v[2], &tail) != 3) usage(std::string("expected x,y,z, got ") + s);
  return glm::dvec3(v[0], v[1], v[2]);
}

double parseNumber(const std::string& flag, const char* s) {
  char* end = nullptr;
  const double v = std::strtod(s, &end);
  if (!*s || *end || !std::isfinite(v)) usage(flag + " takes a number, got '" + s + "'");
  return v;
}

Options parseArgs(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> const char* {
      if (i + 1 >= argc) usage("missing value for " + a);
      return argv[++i];
    };
    if (a == "--size") {
      char tail = 0;
      if (std::sscanf(next(), "%dx%d%c", &o.width, &o.height, &tail) != 2 || o.width <= 0 || o.height <= 0 ||
          o.width > 16384 || o.height > 16384)
        usage("bad --size (WxH, at most 16384 a side)");
    } else if (a == "--eye") o.eye = parseVec3(next());
    else if (a == "--target") o.target = parseVec3(next());
    else if (a == "--up") o.up = parseVec3(next());
    else if (a == "--fovy") o.fovy = parseNumber(a, next());
    else if (a == "--near") o.znear = parseNumber(a, next());
    else if (a == "--far") o.zfar = parseNumber(a, next());
    else if (a == "--frames") o.frames = int(parseNumber(a, next()));
    else if (a == "--warmup") o.warmup = int(parseNumber(a, next()));
    else if (a == "--film") o.film = next();
    else if (a == "--no-sort") o.sort = false;
    else if (a == "--out-png") o.outPng = next();
    else if (a == "--out-pfm") o.outPfm = next();
    else if (a == "--json") o.json = next();
    else if (a == "--csv") o.csv = next();
    else if (a == "--auto-camera") o.autoCamera = true;
    else if (a == "--egl") o.egl = next();
    else if (a == "--egl-device") o.eglDevice = int(parseNumber(a, next()));
    else if (a == "--verbose" || a == "-v") o.verbose = true;
    else if (a == "--help" || a == "-h") usage();
    else if (!a.empty() && a[0] == '-') usage("unknown option " + a);
    else if (o.scene.empty()) o.scene = a;
    else usage("more than one scene given");
  }
  if (o.scene.empty()) usage("no scene given");
  if (o.frames < 1 || o.warmup < 0) usage("--frames must be at least 1 and --warmup at least 0");
  if (o.film != "rgba16f" && o.film != "rgba32f") usage("--film takes rgba16f or rgba32f");
  if (!(o.fovy > 0.0 && o.fovy < 180.0) || !(o.znear > 0.0 && o.zfar > o.znear)) usage("bad --fovy, --near or --far");
  if (o.egl != "auto" && o.egl != "device" && o.egl != "surfaceless" && o.egl != "default") usage("bad --egl");
  return o;
}

// What glref's loader leaves out: each material's alphaMode and cutoff, and
// whether it is unlit. glref keeps one Scene::materials entry per glTF
// material, in order, so the indices agree.
struct AlphaInfo {
  int mode = 0;  // 0 OPAQUE, 1 MASK, 2 BLEND
  float cutoff = 0.5f;
  bool unlit = false;
};

bool loadAlpha(const std::string& path, std::vector<AlphaInfo>& out, std::string& err) {
  tinygltf::TinyGLTF loader;
  tinygltf::Model m;
  std::string warn;
  const bool glb = path.size() >= 4 && (path.compare(path.size() - 4, 4, ".glb") == 0 ||
                                        path.compare(path.size() - 4, 4, ".GLB") == 0);
  const bool ok = glb ? loader.LoadBinaryFromFile(&m, &err, &warn, path) : loader.LoadASCIIFromFile(&m, &err, &warn, path);
  if (!ok) return false;
  for (const auto& gm : m.materials) {
    AlphaInfo a;
    a.mode = gm.alphaMode == "BLEND" ? 2 : gm.alphaMode == "MASK" ? 1 : 0;
    a.cutoff = std::isfinite(gm.alphaCutoff) ? float(gm.alphaCutoff) : 0.0f;
    a.unlit = gm.extensions.count("KHR_materials_unlit") > 0;
    out.push_back(a);
  }
  return true;
}

const char* kVertexShader = R"(#version 330 core
layout(location = 0) in vec3 aPos;
layout(location = 2) in vec2 aUV;
layout(location = 3) in vec4 aCol;
uniform mat4 uMVP;
out vec2 vUV;
out vec4 vCol;
void main() {
  vUV = aUV;
  vCol = aCol;
  gl_Position = uMVP * vec4(aPos, 1.0);
}
)";

// uMode: 0 opaque, 1 mask (discard below uCutoff), 2 blend (premultiplied out).
const char* kFragmentShader = R"(#version 330 core
in vec2 vUV;
in vec4 vCol;
uniform sampler2D uTex;
uniform vec4 uBaseColor;
uniform int uMode;
uniform float uCutoff;
layout(location = 0) out vec4 oColor;
void main() {
  vec4 c = uBaseColor * texture(uTex, vUV) * vCol;
  float a = isnan(c.a) ? 0.0 : clamp(c.a, 0.0, 1.0);
  if (uMode == 1 && a < uCutoff) discard;
  oColor = uMode == 2 ? vec4(c.rgb * a, a) : vec4(c.rgb, 1.0);
}
)";

void checkGl(const char* where) {
  const GLenum e = glGetError();
  if (e != GL_NO_ERROR) {
    std::fprintf(stderr, "glblend: error: GL error 0x%04x at %s\n", e, where);
    std::exit(1);
  }
}

GLuint compileShader(GLenum type, const char* src) {
  const GLuint s = glCreateShader(type);
  glShaderSource(s, 1, &src, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[4096];
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    std::fprintf(stderr, "glblend: error: shader compile failed: %s\n", log);
    std::exit(1);
  }
  return s;
}

GLuint buildProgram() {
  const GLuint vs = compileShader(GL_VERTEX_SHADER, kVertexShader);
  const GLuint fs = compileShader(GL_FRAGMENT_SHADER, kFragmentShader);
  const GLuint p = glCreateProgram();
  glAttachShader(p, vs);
  glAttachShader(p, fs);
  glLinkProgram(p);
  GLint ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    std::fprintf(stderr, "glblend: error: program link failed\n");
    std::exit(1);
  }
  glDeleteShader(vs);
  glDeleteShader(fs);
  return p;
}

struct DrawGl {
  float mvp[16];
  float baseColor[4];
  GLuint texture;
  int mode;
  float cutoff;
  GLsizei indexCount;
  size_t indexOffsetBytes;
  GLint baseVertex;
  glm::vec3 centreWorld;  // the primitive's bounding box centre through the model matrix (float, as rast)
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

bool writePfmRgb(const std::string& path, int w, int h, const std::vector<float>& rgbaBottomUp) {
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return false;
  std::fprintf(f, "PF\n%d %d\n-1.0\n", w, h);
  std::vector<float> rgb(size_t(w) * h * 3);
  for (size_t i = 0; i < size_t(w) * h; ++i)
    for (int c = 0; c < 3; ++c) rgb[i * 3 + c] = rgbaBottomUp[i * 4 + c];
  const bool ok = std::fwrite(rgb.data(), sizeof(float), rgb.size(), f) == rgb.size();
  return std::fclose(f) == 0 && ok;
}

uint8_t srgb8(float c) {
  c = std::isnan(c) ? 0.0f : std::min(std::max(c, 0.0f), 1.0f);
  const float s = c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
  return uint8_t(std::lround(s * 255.0f));
}

}  // namespace

int main(int argc, char** argv) {
  Options opt = parseArgs(argc, argv);
  const int W = opt.width, H = opt.height;

  glref::Scene scene;
  std::string err;
  if (!glref::loadGltf(opt.scene, scene, err, opt.verbose)) {
    std::fprintf(stderr, "glblend: error: cannot load %s: %s\n", opt.scene.c_str(), err.c_str());
    return 1;
  }
  std::vector<AlphaInfo> alpha;
  if (!loadAlpha(opt.scene, alpha, err) || alpha.size() != scene.materials.size()) {
    std::fprintf(stderr, "glblend: error: cannot read the materials' alpha modes of %s: %s\n", opt.scene.c_str(),
                 err.c_str());
    return 1;
  }

  if (opt.autoCamera) {  // glref's and rast's framing (host/scene/camera.cpp autoFrame)
    const glm::dvec3 lo = scene.bboxValid ? scene.bboxMin : glm::dvec3(-1.0);
    const glm::dvec3 hi = scene.bboxValid ? scene.bboxMax : glm::dvec3(1.0);
    double r = 0.5 * glm::length(hi - lo);
    if (!(r > 0.0)) r = 1.0;
    const double d = r / std::sin(glm::radians(opt.fovy) * 0.5);
    opt.target = 0.5 * (lo + hi);
    opt.eye = opt.target + glm::normalize(glm::dvec3(0.0, 0.25, 1.0)) * d;
    opt.up = glm::dvec3(0.0, 1.0, 0.0);
    opt.znear = d / 100.0;
    opt.zfar = d * 100.0;
  }
  char camera[512];
  {  // the printed decimals are the camera used, so another renderer can be given the same
    std::snprintf(camera, sizeof camera,
                  "--eye %.9g,%.9g,%.9g --target %.9g,%.9g,%.9g --up %.9g,%.9g,%.9g --fovy %.9g --near %.9g --far %.9g",
                  opt.eye.x, opt.eye.y, opt.eye.z, opt.target.x, opt.target.y, opt.target.z, opt.up.x, opt.up.y,
                  opt.up.z, opt.fovy, opt.znear, opt.zfar);
    std::sscanf(camera, "--eye %lf,%lf,%lf --target %lf,%lf,%lf --up %lf,%lf,%lf --fovy %lf --near %lf --far %lf",
                &opt.eye.x, &opt.eye.y, &opt.eye.z, &opt.target.x, &opt.target.y, &opt.target.z, &opt.up.x, &opt.up.y,
                &opt.up.z, &opt.fovy, &opt.znear, &opt.zfar);
    std::printf("glblend: camera%s %s\n", opt.autoCamera ? " (auto)" : "", camera);
  }
  const glm::dmat4 view = glm::lookAt(opt.eye, opt.target, opt.up);
  const glm::dmat4 viewProj = glm::perspective(glm::radians(opt.fovy), double(W) / double(H), opt.znear, opt.zfar) * view;
  const glm::mat4 viewF(view);

  glref::EglContext egl;
  if (!egl.create(opt.egl, opt.eglDevice, opt.verbose, err)) {
    std::fprintf(stderr, "glblend: error: no EGL/OpenGL context: %s\n", err.c_str());
    return 1;
  }
  const char* rendererC = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const std::string renderer = rendererC ? rendererC : "(null)";
  std::printf("glblend: egl %s\nglblend: GL_RENDERER=%s\n", egl.description.c_str(), renderer.c_str());
  if (epoxy_gl_version() < 33) {
    std::fprintf(stderr, "glblend: error: need OpenGL 3.3\n");
    return 1;
  }

  // ---- Upload, once ----
  GLuint vao, vbo, ebo;
  glGenVertexArrays(1, &vao);
  glBindVertexArray(vao);
  glGenBuffers(1, &vbo);
  glBindBuffer(GL_ARRAY_BUFFER, vbo);
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(scene.vertices.size() * sizeof(glref::Vertex)), scene.vertices.data(),
               GL_STATIC_DRAW);
  glGenBuffers(1, &ebo);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ebo);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(scene.indices.size() * sizeof(uint32_t)), scene.indices.data(),
               GL_STATIC_DRAW);
  const GLsizei stride = sizeof(glref::Vertex);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, (void*)offsetof(glref::Vertex, pos));
  glEnableVertexAttribArray(2);
  glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, stride, (void*)offsetof(glref::Vertex, uv));
  glEnableVertexAttribArray(3);
  glVertexAttribPointer(3, 4, GL_FLOAT, GL_FALSE, stride, (void*)offsetof(glref::Vertex, col));
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  std::vector<GLuint> textures(scene.textures.size());
  for (size_t i = 0; i < scene.textures.size(); ++i) {  // as glref: sRGB, trilinear, the sampler's wrap modes
    const auto& t = scene.textures[i];
    const auto& im = scene.images[t.image];
    glGenTextures(1, &textures[i]);
    glBindTexture(GL_TEXTURE_2D, textures[i]);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_SRGB8_ALPHA8, im.width, im.height, 0, GL_RGBA, GL_UNSIGNED_BYTE, im.rgba.data());
    glGenerateMipmap(GL_TEXTURE_2D);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, t.wrapS);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, t.wrapT);
  }
  GLuint white;
  {
    const uint8_t px[4] = {255, 255, 255, 255};
    glGenTextures(1, &white);
    glBindTexture(GL_TEXTURE_2D, white);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_SRGB8_ALPHA8, 1, 1, 0, GL_RGBA, GL_UNSIGNED_BYTE, px);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  }
  checkGl("upload");

  const GLuint prog = buildProgram();
  glUseProgram(prog);
  const GLint uMVP = glGetUniformLocation(prog, "uMVP"), uBaseColor = glGetUniformLocation(prog, "uBaseColor");
  const GLint uMode = glGetUniformLocation(prog, "uMode"), uCutoff = glGetUniformLocation(prog, "uCutoff");
  glUniform1i(glGetUniformLocation(prog, "uTex"), 0);

  std::vector<DrawGl> opaque, blend;
  int litMaterials = 0;
  for (const auto& a : alpha) litMaterials += a.unlit ? 0 : 1;
  for (const auto& d : scene.draws) {
    const auto& p = scene.primitives[d.primitive];
    DrawGl u{};
    const glm::mat4 mvp(viewProj * d.model);
    std::memcpy(u.mvp, glm::value_ptr(mvp), sizeof u.mvp);
    glm::vec4 bc(1.0f);
    u.texture = white;
    u.mode = 0;
    u.cutoff = 0.5f;
    if (p.material >= 0) {
      const auto& m = scene.materials[p.material];
      bc = m.baseColorFactor;
      if (m.baseColorTexture >= 0) u.texture = textures[m.baseColorTexture];
      u.mode = alpha[p.material].mode;
      u.cutoff = alpha[p.material].cutoff;
    }
    std::memcpy(u.baseColor, glm::value_ptr(bc), sizeof u.baseColor);
    u.indexCount = GLsizei(p.indexCount);
    u.indexOffsetBytes = size_t(p.firstIndex) * sizeof(uint32_t);
    u.baseVertex = GLint(p.baseVertex);
    glm::vec3 lo(0.0f), hi(0.0f);
    for (uint32_t k = 0; k < p.vertexCount; ++k) {
      const float* v = scene.vertices[size_t(p.baseVertex) + k].pos;
      const glm::vec3 q(v[0], v[1], v[2]);
      lo = k ? glm::min(lo, q) : q;
      hi = k ? glm::max(hi, q) : q;
    }
    u.centreWorld = glm::vec3(glm::mat4(d.model) * glm::vec4(0.5f * (lo + hi), 1.0f));
    (u.mode == 2 ? blend : opaque).push_back(u);
  }
  std::printf("glblend: scene=%s draws=%zu opaque_draws=%zu blend_draws=%zu tris=%llu lit_materials_drawn_unlit=%d\n",
              opt.scene.c_str(), scene.draws.size(), opaque.size(), blend.size(),
              (unsigned long long)scene.triangleCount, litMaterials);

  // ---- Targets: a float colour buffer (linear light) and a 32-bit float depth buffer ----
  GLuint fbo, color, depth;
  glGenFramebuffers(1, &fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glGenRenderbuffers(1, &color);
  glBindRenderbuffer(GL_RENDERBUFFER, color);
  glRenderbufferStorage(GL_RENDERBUFFER, opt.film == "rgba32f" ? GL_RGBA32F : GL_RGBA16F, W, H);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color);
  glGenRenderbuffers(1, &depth);
  glBindRenderbuffer(GL_RENDERBUFFER, depth);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, W, H);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    std::fprintf(stderr, "glblend: error: framebuffer %s incomplete\n", opt.film.c_str());
    return 1;
  }
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);
  glDisable(GL_DITHER);
  glDisable(GL_SCISSOR_TEST);
  glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA);  // premultiplied "over"
  glActiveTexture(GL_TEXTURE0);
  glFinish();
  checkGl("setup");

  // ---- Frames ----
  const float clear[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  const float far = 1.0f;
  std::vector<uint32_t> order(blend.size());
  std::vector<float> key(blend.size());
  auto draw = [&](const DrawGl& u, GLuint& bound) {
    glUniformMatrix4fv(uMVP, 1, GL_FALSE, u.mvp);
    glUniform4fv(uBaseColor, 1, u.baseColor);
    glUniform1i(uMode, u.mode);
    glUniform1f(uCutoff, u.cutoff);
    if (u.texture != bound) {
      glBindTexture(GL_TEXTURE_2D, u.texture);
      bound = u.texture;
    }
    glDrawElementsBaseVertex(GL_TRIANGLES, u.indexCount, GL_UNSIGNED_INT, (void*)u.indexOffsetBytes, u.baseVertex);
  };
  auto frame = [&]() {
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, W, H);
    glDepthMask(GL_TRUE);
    glClearBufferfv(GL_COLOR, 0, clear);
    glClearBufferfv(GL_DEPTH, 0, &far);
    GLuint bound = 0;
    glDisable(GL_BLEND);
    for (const auto& u : opaque) draw(u, bound);
    if (blend.empty()) return;
    // Back to front by the centre's view depth (-z in view space), computed in
    // float as rast's sortedKey; ties keep submission order (a later draw in front).
    std::iota(order.begin(), order.end(), 0u);
    if (opt.sort) {
      for (size_t i = 0; i < blend.size(); ++i) {
        const glm::vec3& c = blend[i].centreWorld;
        const float* v = glm::value_ptr(viewF);
        key[i] = -(v[2] * c.x + v[6] * c.y + v[10] * c.z + v[14]);
      }
      std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return key[a] > key[b]; });
    }
    glEnable(GL_BLEND);
    glDepthMask(GL_FALSE);
    for (uint32_t i : order) draw(blend[i], bound);
  };
  std::vector<double> times;
  for (int i = 0; i < opt.warmup + opt.frames; ++i) {
    const auto t0 = Clock::now();
    frame();
    glFinish();
    const auto t1 = Clock::now();
    if (i >= opt.warmup) times.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
  }
  checkGl("frames");

  // ---- Read back: linear RGBA floats, bottom row first ----
  std::vector<float> rgba(size_t(W) * H * 4);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, W, H, GL_RGBA, GL_FLOAT, rgba.data());
  checkGl("readback");
  int rc = 0;
  if (!opt.outPfm.empty() && !writePfmRgb(opt.outPfm, W, H, rgba)) {
    std::fprintf(stderr, "glblend: error: cannot write %s\n", opt.outPfm.c_str());
    rc = 1;
  }
  if (!opt.outPng.empty()) {
    std::vector<uint8_t> px(rgba.size());
    for (size_t i = 0; i < rgba.size(); ++i) px[i] = (i % 4 == 3) ? 255 : srgb8(rgba[i]);
    if (!glref::writePng(opt.outPng, W, H, px)) {
      std::fprintf(stderr, "glblend: error: cannot write %s\n", opt.outPng.c_str());
      rc = 1;
    }
  }

  const double med = median(times), mn = *std::min_element(times.begin(), times.end());
  double mean = 0.0;
  for (double t : times) mean += t;
  mean /= double(times.size());
  if (!opt.json.empty()) {
    FILE* f = std::fopen(opt.json.c_str(), "w");
    if (!f) {
      std::fprintf(stderr, "glblend: error: cannot write %s\n", opt.json.c_str());
      rc = 1;
    } else {
      std::string r;
      for (char ch : renderer) r += (ch == '"' || ch == '\\') ? '_' : ch;
      std::fprintf(f,
                   "{\"scene\": \"%s\", \"renderer\": \"%s\", \"film\": \"%s\", \"sorted\": %s, \"width\": %d, "
                   "\"height\": %d, \"frames\": %d, \"warmup\": %d, \"total_median_ms\": %.6f, \"total_min_ms\": %.6f, "
                   "\"total_mean_ms\": %.6f, \"draws_opaque\": %zu, \"draws_blend\": %zu, \"triangles\": %llu, "
                   "\"lit_materials_drawn_unlit\": %d, \"camera\": \"%s\"}\n",
                   opt.scene.c_str(), r.c_str(), opt.film.c_str(), opt.sort ? "true" : "false", W, H, opt.frames,
                   opt.warmup, med, mn, mean, opaque.size(), blend.size(), (unsigned long long)scene.triangleCount,
                   litMaterials, camera);
      std::fclose(f);
    }
  }
  if (!opt.csv.empty()) {
    FILE* f = std::fopen(opt.csv.c_str(), "w");
    if (!f) {
      std::fprintf(stderr, "glblend: error: cannot write %s\n", opt.csv.c_str());
      rc = 1;
    } else {
      std::string r;
      for (char ch : renderer) r += (ch == ',' || ch == '"') ? ' ' : ch;
      std::fprintf(f, "scene,renderer,film,sorted,width,height,frames,total_median_ms,total_min_ms,draws_opaque,draws_blend\n");
      std::fprintf(f, "%s,%s,%s,%d,%d,%d,%d,%.6f,%.6f,%zu,%zu\n", opt.scene.c_str(), r.c_str(), opt.film.c_str(),
                   opt.sort ? 1 : 0, W, H, opt.frames, med, mn, opaque.size(), blend.size());
      std::fclose(f);
    }
  }
  egl.destroy();
  std::printf("glblend: renderer=%s film=%s size=%dx%d frames=%d median_ms=%.4f min_ms=%.4f mean_ms=%.4f\n",
              renderer.c_str(), opt.film.c_str(), W, H, opt.frames, med, mn, mean);
  return rc;
}
