// Line and point coverage of rast against the OpenGL rasterizer of this machine
// (Mesa llvmpipe here) through EGL, with the EGL set-up of ../shared/tools/glref.
// Random width-1 segments (any slope, sub-pixel endpoints; and pixel-centre to
// pixel-centre) and points of sizes 1-5 are drawn by both in window
// coordinates (identity transform) with the depth test LESS at one depth, so
// the first primitive drawn keeps a pixel in both; the per-pixel ids are
// compared. Prints the agreement; exits 1 below --min (default 0: measure
// only), 77 when no OpenGL context can be made.
#include "pipeline/frame/renderer.h"
#include "egl_context.h"

#include <epoxy/gl.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

using namespace rast;

namespace {

const char* kVS = R"(#version 330 core
layout(location = 0) in vec2 aPos;
uniform float uSize;
void main() { gl_Position = vec4(aPos, 0.0, 1.0); gl_PointSize = uSize; }
)";
const char* kFS = R"(#version 330 core
uniform uint uBase;
layout(location = 0) out uint oId;
void main() { oId = uBase + uint(gl_PrimitiveID) + 1u; }
)";

GLuint shader(GLenum type, const char* src) {
  GLuint s = glCreateShader(type);
  glShaderSource(s, 1, &src, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    std::fprintf(stderr, "gl_lines_agreement: shader failed\n");
    std::exit(1);
  }
  return s;
}

struct Batch {
  bool points;
  float size;
  std::vector<float> ndc;  // x, y per vertex
};

// GL ids of the primitives of every batch, drawn in order; bottom row first.
std::vector<uint32_t> drawGl(int W, int H, const std::vector<Batch>& batches) {
  GLuint fbo, rb[2];
  glGenFramebuffers(1, &fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glGenRenderbuffers(2, rb);
  glBindRenderbuffer(GL_RENDERBUFFER, rb[0]);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_R32UI, W, H);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, rb[0]);
  glBindRenderbuffer(GL_RENDERBUFFER, rb[1]);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, W, H);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, rb[1]);
  glViewport(0, 0, W, H);
  const GLuint zero[4] = {0, 0, 0, 0};
  glClearBufferuiv(GL_COLOR, 0, zero);
  glClearDepth(1.0);
  glClear(GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glEnable(GL_PROGRAM_POINT_SIZE);
  GLuint prog = glCreateProgram();
  glAttachShader(prog, shader(GL_VERTEX_SHADER, kVS));
  glAttachShader(prog, shader(GL_FRAGMENT_SHADER, kFS));
  glLinkProgram(prog);
  glUseProgram(prog);
  GLuint vao, vbo;
  glGenVertexArrays(1, &vao);
  glBindVertexArray(vao);
  glGenBuffers(1, &vbo);
  glBindBuffer(GL_ARRAY_BUFFER, vbo);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
  uint32_t base = 0;
  for (const Batch& b : batches) {
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(b.ndc.size() * sizeof(float)), b.ndc.data(), GL_STATIC_DRAW);
    glUniform1ui(glGetUniformLocation(prog, "uBase"), base);
    glUniform1f(glGetUniformLocation(prog, "uSize"), b.size);
    const GLsizei n = GLsizei(b.ndc.size() / 2);
    glDrawArrays(b.points ? GL_POINTS : GL_LINES, 0, n);
    base += uint32_t(b.points ? n : n / 2);
  }
  std::vector<uint32_t> ids(size_t(W) * H);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, W, H, GL_RED_INTEGER, GL_UNSIGNED_INT, ids.data());
  return ids;
}

// The same primitives through rast: one draw per batch (segments or points
// number in draw order only when all batches have one kind, so each kind is
// compared on its own).
std::vector<uint32_t> drawRast(int W, int H, const std::vector<Batch>& batches) {
  Scene s;
  s.name = "gl-agreement";
  s.materials.push_back(Material{});
  float size = 1.0f;
  for (const Batch& b : batches) {
    std::vector<rast::float3> pos;
    std::vector<uint32_t> idx;
    for (size_t i = 0; i < b.ndc.size(); i += 2) {
      pos.push_back({b.ndc[i], b.ndc[i + 1], 0.0f});
      idx.push_back(uint32_t(idx.size()));
    }
    s.draws.push_back(Draw{addLinePrim(s, pos, nullptr, b.points ? std::vector<uint32_t>{} : idx,
                                       b.points ? idx : std::vector<uint32_t>{}, 0),
                           glm::dmat4(1.0)});
    size = b.size;
  }
  Renderer r(s);
  Camera cam;
  cam.viewProjOverride = glm::dmat4(1.0);
  RenderSettings rs;
  rs.width = W;
  rs.height = H;
  rs.wantPrimId = true;
  rs.pointSize = size;
  r.render(cam, rs);
  return r.primIdsBottomUp();
}

struct Agreement {
  size_t lit = 0, same = 0;
};

Agreement compare(const std::vector<uint32_t>& a, const std::vector<uint32_t>& b) {
  Agreement g;
  for (size_t i = 0; i < a.size(); ++i) {
    if (!a[i] && !b[i]) continue;
    ++g.lit;
    g.same += a[i] == b[i];
  }
  return g;
}

}  // namespace

int main(int argc, char** argv) {
  double minAgree = 0.0;
  std::string skipDir;  // where a skip leaves its reason (tests/support/skip_report.cmake)
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::string(argv[i]) == "--min") minAgree = std::atof(argv[i + 1]);
    if (std::string(argv[i]) == "--skip-dir") skipDir = argv[i + 1];
  }
  Kokkos::ScopeGuard kokkos(argc, argv);
  glref::EglContext egl;
  std::string err;
  if (!egl.create("auto", -1, false, err)) {
    std::printf("SKIPPED: no EGL/OpenGL context: %s\n", err.c_str());
    if (!skipDir.empty()) {
      std::error_code ec;
      std::filesystem::create_directories(skipDir, ec);
      if (FILE* f = std::fopen((skipDir + "/gl_lines_agreement.txt").c_str(), "w")) {
        std::fprintf(f, "no EGL/OpenGL context: %s\n", err.c_str());
        std::fclose(f);
      }
    }
    return 77;
  }
  std::printf("GL: %s | %s\n", reinterpret_cast<const char*>(glGetString(GL_RENDERER)),
              reinterpret_cast<const char*>(glGetString(GL_VERSION)));
  const int W = 256, H = 256;
  auto ndcX = [&](double x) { return float(x / W * 2.0 - 1.0); };
  auto ndcY = [&](double y) { return float(y / H * 2.0 - 1.0); };
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  double worst = 1.0;
  auto report = [&](const char* what, const std::vector<Batch>& batches) {
    const Agreement g = compare(drawGl(W, H, batches), drawRast(W, H, batches));
    const double f = g.lit ? double(g.same) / double(g.lit) : 1.0;
    worst = f < worst ? f : worst;
    std::printf("%-44s %7zu pixels lit by either, %7zu agree: %.4f\n", what, g.lit, g.same, f);
  };
  {  // sub-pixel endpoints, any slope, up to 40 pixels long
    Batch b{false, 1.0f, {}};
    for (int i = 0; i < 400; ++i) {
      const double x = 20 + U(rng) * (W - 40), y = 20 + U(rng) * (H - 40), a = U(rng) * 6.283185307, l = 2 + U(rng) * 38;
      b.ndc.insert(b.ndc.end(), {ndcX(x), ndcY(y), ndcX(x + l * std::cos(a)), ndcY(y + l * std::sin(a))});
    }
    report("lines, sub-pixel endpoints, width 1", {b});
  }
  {  // pixel centre to pixel centre, any slope (including diagonals)
    Batch b{false, 1.0f, {}};
    for (int i = 0; i < 400; ++i) {
      const int x = 20 + int(U(rng) * (W - 40)), y = 20 + int(U(rng) * (H - 40));
      const int dx = int(U(rng) * 41) - 20, dy = (i % 4 == 0) ? dx : int(U(rng) * 41) - 20;
      b.ndc.insert(b.ndc.end(), {ndcX(x + 0.5), ndcY(y + 0.5), ndcX(x + dx + 0.5), ndcY(y + dy + 0.5)});
    }
    report("lines, pixel centre to pixel centre, width 1", {b});
    if (std::getenv("GL_LINES_DETAIL")) {  // the differing lines one by one, for study
      int shown = 0;
      for (size_t i = 0; i < b.ndc.size() && shown < 12; i += 4) {
        Batch one{false, 1.0f, {b.ndc.begin() + long(i), b.ndc.begin() + long(i) + 4}};
        const auto g = drawGl(W, H, {one}), r = drawRast(W, H, {one});
        if (g == r) continue;
        ++shown;
        std::printf("(%g,%g)->(%g,%g): gl-only", (one.ndc[0] + 1) * W / 2, (one.ndc[1] + 1) * H / 2,
                    (one.ndc[2] + 1) * W / 2, (one.ndc[3] + 1) * H / 2);
        for (size_t p = 0; p < g.size(); ++p)
          if (g[p] && !r[p]) std::printf(" (%zu,%zu)", p % W, p / W);
        std::printf(" rast-only");
        for (size_t p = 0; p < g.size(); ++p)
          if (r[p] && !g[p]) std::printf(" (%zu,%zu)", p % W, p / W);
        std::printf("\n");
      }
    }
  }
  for (int size = 1; size <= 5; ++size) {
    Batch b{true, float(size), {}};
    for (int i = 0; i < 300; ++i) b.ndc.insert(b.ndc.end(), {ndcX(8 + U(rng) * (W - 16)), ndcY(8 + U(rng) * (H - 16))});
    char what[64];
    std::snprintf(what, sizeof what, "points, size %d, sub-pixel positions", size);
    report(what, {b});
  }
  egl.destroy();
  if (worst < minAgree) {
    std::printf("FAILED: agreement %.4f below --min %.4f\n", worst, minAgree);
    return 1;
  }
  return 0;
}
