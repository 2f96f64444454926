// rast-viewer: shows the Kokkos pipeline's frames in a GLFW window, with an
// orbit camera and a Dear ImGui overlay. See docs/viewer.md.
//
//   rast-viewer [SCENE] [--size WxH] [camera and render options of rast render]
//               [--script FILE] [--frames N] [--screenshot F.png]
//               [--window-screenshot F.png] [--no-overlay] [--no-vsync] [--no-interop]
//
// The scene (and the script) are loaded before any window opens, so bad input
// ends in one line "rast-viewer: error: ..." on stderr and exit status 1, with
// no window shown. The error texts are rast render's.
#include "../../backends/stage_timer.h"
#include "../../core/image_io.h"
#include "../../core/renderer.h"
#include "../../models/procedural.h"
#include "../cli_options.h"
#include "../guarded_main.h"
#include "gl_display.h"
#include "orbit_camera.h"
#include "viewer_script.h"

#include <CLI/CLI.hpp>
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <deque>
#include <fstream>
#include <initializer_list>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <unistd.h>  // sysconf, for the resident set size

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace rast {
namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

double median(std::vector<double> v) {  // by value: sorts a copy
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Per-frame times, bounded: a soak of 100,000 frames must not grow the heap,
// so each series keeps the last kKeep samples (medians are of those).
constexpr size_t kKeep = 16384;
struct Series {
  std::vector<double> v;
  size_t next = 0;
  void push(double x) {
    if (v.size() < kKeep) v.push_back(x);
    else v[next] = x;
    next = (next + 1) % kKeep;
  }
  double median() const { return rast::median(v); }
};

// Resident set size of this process in bytes (Linux /proc; 0 elsewhere).
size_t residentBytes() {
  std::ifstream f("/proc/self/statm");
  size_t pages = 0, rss = 0;
  if (!(f >> pages >> rss)) return 0;
  return rss * size_t(sysconf(_SC_PAGESIZE));
}

std::string g_glfwError;
void onGlfwError(int code, const char* text) {
  g_glfwError = std::string(text ? text : "unknown") + " (GLFW error " + std::to_string(code) + ")";
}

const char* kControls[][2] = {
    {"left drag", "orbit around the target"},
    {"right drag", "pan"},
    {"wheel / middle drag", "zoom"},
    {"F", "frame the scene"},
    {"1 / 2 / 3", "triangles / wireframe / points"},
    {"C", "back-face culling on/off"},
    {"M / Shift+M", "next / previous raster method"},
    {"L / Shift+L", "next / previous shading: lambert, blinn-phong, then debug views"},
    {"T / Shift+T", "texture filter: bilinear, nearest (, trilinear)"},
    {"P", "bloom on/off (post-processing: overlay)"},
    {"F12", "screenshot (rast-viewer-NNN.png + -window.png)"},
    {"O", "overlay on/off"},
    {"H", "help"},
    {"Esc / Q", "quit"},
};

struct ViewerOptions {
  SceneOptions scene;
  std::string script, screenshot, windowScreenshot;
  int frames = 0;
  bool noOverlay = false, noVsync = false, noInterop = false;
};

// The modes this build knows (asked by name, so that modes the pipeline gains
// or lacks need no change here), in the order the keys cycle through them.
template <class T>
std::vector<T> knownModes(T (*parse)(const std::string&), std::initializer_list<const char*> names) {
  std::vector<T> out;
  for (const char* n : names) {
    try {
      out.push_back(parse(n));
    } catch (const Error&) {
      // not in this build
    }
  }
  return out;
}
// L: the lighting models first, then the debug views.
std::vector<ShadingMode> shadingModes() {
  return knownModes<ShadingMode>(parseShading, {"lambert", "blinn-phong", "normals", "depth", "uv", "miplevel"});
}
// T: bilinear <-> nearest first, then the rest.
std::vector<TexFilter> filterModes() { return knownModes<TexFilter>(parseFilter, {"bilinear", "nearest", "trilinear"}); }

enum class PrimMode { Triangles, Wireframe, Points };
const char* toString(PrimMode m) {
  return m == PrimMode::Triangles ? "triangles" : m == PrimMode::Wireframe ? "wireframe" : "points";
}

class Viewer {
 public:
  Viewer(const ViewerOptions& o, const Scene& scene, const Camera& cam, const RenderSettings& rs,
         std::vector<ScriptEvent> script)
      : opts_(o), renderer_(scene, o.scene.memoryBudget()), rs_(rs), orbit_(cam), script_(std::move(script)) {
    scene.worldBounds(boundsLo_, boundsHi_);
    prim_ = rs.polygon == PolygonMode::Line ? PrimMode::Wireframe : rs.polygon == PolygonMode::Point ? PrimMode::Points
                                                                                                    : PrimMode::Triangles;
    std::istringstream dd(deviceDescription());
    for (std::string l; std::getline(dd, l);) {
      if (l.rfind("backend: ", 0) == 0) backend_ = l.substr(9);
      else if (l.rfind("concurrency: ", 0) == 0) concurrency_ = l.substr(13);
      else if (l.rfind("device: ", 0) == 0) device_ = l.substr(8);
    }
  }
  ~Viewer() { closeWindow(); }

  void openWindow();
  int run();

 private:
  // Input, from GLFW callbacks and from scripts alike.
  void onKey(int key, int mods);
  void onDrag(int button, double dx, double dy);
  void onScroll(double dy);
  void setRenderSize(int w, int h);
  void notice(const std::string& text);

  void renderPipeline();   // one pipeline frame with the current camera and settings
  void present(const std::string& windowShot = "");  // display it, overlay, swap
  void frame();            // both, timed
  void ensureRendered() {
    if (dirty_) renderPipeline();
  }
  void drawOverlay();
  void drawPostControls();  // exposure, tone mapping, bloom, SSAO with live parameters
  void applyScriptEvent(const ScriptEvent& e);
  void saveScreenshot(const std::string& path);
  void saveWindowScreenshot(const std::string& path);
  void takeRequestedShots();
  std::string stateLine() const;
  std::string nextScreenshotName() const;
  void closeWindow();

  static Viewer* self(GLFWwindow* w) { return static_cast<Viewer*>(glfwGetWindowUserPointer(w)); }

  ViewerOptions opts_;
  Renderer renderer_;
  RenderSettings rs_;
  OrbitCamera orbit_;
  glm::dvec3 boundsLo_{}, boundsHi_{};
  std::vector<ScriptEvent> script_;
  std::string backend_ = "?", concurrency_ = "?", device_;

  GLFWwindow* win_ = nullptr;
  std::unique_ptr<GlDisplay> display_;
  bool imgui_ = false, overlay_ = true, help_ = false, quit_ = false, dirty_ = true, shotRequested_ = false;
  PrimMode prim_ = PrimMode::Triangles;  // follows rs_.polygon
  std::string notice_;
  Clock::time_point noticeAt_{};

  // Mouse state of real input.
  bool buttonDown_[3] = {false, false, false};
  double lastX_ = 0, lastY_ = 0;

  // Statistics.
  StageTimer timer_;
  FrameStats stats_;
  std::vector<std::pair<std::string, double>> stages_;
  double renderMs_ = 0, uploadMs_ = 0, copyOutMs_ = 0;  // upload includes the copy out of the pipeline
  double drawMs_ = 0, overlayMs_ = 0, swapMs_ = 0;     // present(): the quad, ImGui, glfwSwapBuffers
  std::deque<double> recentFrameMs_;
  Series frameMs_, renderMsAll_, uploadMsAll_, copyOutMsAll_, drawMsAll_, overlayMsAll_, swapMsAll_;
  Clock::time_point lastFrameEnd_{};
  int framesShown_ = 0;
};

void Viewer::openWindow() {
  glfwSetErrorCallback(onGlfwError);
  if (!glfwInit()) throw Error("cannot open a window: " + (g_glfwError.empty() ? std::string("glfwInit failed") : g_glfwError));
  // A compatibility context (the default): the image is drawn with
  // fixed-function GL, the overlay with ImGui's OpenGL 3 backend (GLSL 130).
  const std::string title = "rast-viewer: " + (opts_.scene.scene.empty() ? std::string("default scene") : opts_.scene.scene);
  win_ = glfwCreateWindow(rs_.width, rs_.height, title.c_str(), nullptr, nullptr);
  if (!win_) {
    glfwTerminate();
    throw Error("cannot open a window: " + (g_glfwError.empty() ? std::string("glfwCreateWindow failed") : g_glfwError));
  }
  glfwMakeContextCurrent(win_);
  glfwSwapInterval(opts_.noVsync ? 0 : 1);
  glfwSetWindowUserPointer(win_, this);
  display_ = std::make_unique<GlDisplay>();

  // Our callbacks first: ImGui's backend chains to them.
  glfwSetKeyCallback(win_, [](GLFWwindow* w, int key, int, int action, int mods) {
    if (action != GLFW_PRESS && action != GLFW_REPEAT) return;
    Viewer* v = self(w);
    if (v->imgui_ && ImGui::GetIO().WantCaptureKeyboard) return;
    v->onKey(key, mods);
  });
  glfwSetMouseButtonCallback(win_, [](GLFWwindow* w, int button, int action, int) {
    Viewer* v = self(w);
    if (button < 0 || button > 2) return;
    if (action == GLFW_PRESS) {
      if (v->imgui_ && ImGui::GetIO().WantCaptureMouse) return;
      v->buttonDown_[button] = true;
      glfwGetCursorPos(w, &v->lastX_, &v->lastY_);
    } else if (action == GLFW_RELEASE) {
      v->buttonDown_[button] = false;
    }
  });
  glfwSetCursorPosCallback(win_, [](GLFWwindow* w, double x, double y) {
    Viewer* v = self(w);
    const double dx = x - v->lastX_, dy = y - v->lastY_;
    v->lastX_ = x;
    v->lastY_ = y;
    // Drags are measured in window coordinates; the camera wants framebuffer
    // pixels (they differ on high-DPI screens).
    int ww = 1, wh = 1, fw = 1, fh = 1;
    glfwGetWindowSize(w, &ww, &wh);
    glfwGetFramebufferSize(w, &fw, &fh);
    const double sx = ww > 0 ? double(fw) / ww : 1.0, sy = wh > 0 ? double(fh) / wh : 1.0;
    for (int b = 0; b < 3; ++b)
      if (v->buttonDown_[b]) v->onDrag(b, dx * sx, dy * sy);
  });
  glfwSetScrollCallback(win_, [](GLFWwindow* w, double, double dy) {
    Viewer* v = self(w);
    if (v->imgui_ && ImGui::GetIO().WantCaptureMouse) return;
    v->onScroll(dy);
  });
  glfwSetFramebufferSizeCallback(win_, [](GLFWwindow* w, int fw, int fh) { self(w)->setRenderSize(fw, fh); });

  int fw = 0, fh = 0;
  glfwGetFramebufferSize(win_, &fw, &fh);
  setRenderSize(fw, fh);

  overlay_ = !opts_.noOverlay;
  if (!opts_.noOverlay) {
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini in the working directory
    ImGui::StyleColorsDark();
    ImGui::GetStyle().Alpha = 0.92f;
    if (!ImGui_ImplGlfw_InitForOpenGL(win_, true) || !ImGui_ImplOpenGL3_Init("#version 130"))
      throw Error("cannot initialise the Dear ImGui overlay (needs OpenGL 3.0)");
    imgui_ = true;
  }
  std::printf("rast-viewer: %dx%d window, backend %s, GL %s\n", rs_.width, rs_.height, backend_.c_str(),
              reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
  std::fflush(stdout);
}

void Viewer::closeWindow() {
  if (imgui_) {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    imgui_ = false;
  }
  display_.reset();  // needs the context
  if (win_) {
    glfwDestroyWindow(win_);
    win_ = nullptr;
    glfwTerminate();
  }
}

void Viewer::setRenderSize(int w, int h) {
  if (w < 1 || h < 1) return;  // minimised: keep the last size
  w = std::min(w, 16384);
  h = std::min(h, 16384);
  if (w != rs_.width || h != rs_.height) {
    rs_.width = w;
    rs_.height = h;
    dirty_ = true;
  }
}

void Viewer::notice(const std::string& text) {
  notice_ = text;
  noticeAt_ = Clock::now();
  std::printf("rast-viewer: %s\n", text.c_str());
  std::fflush(stdout);
}

void Viewer::onKey(int key, int mods) {
  const bool shift = (mods & GLFW_MOD_SHIFT) != 0;
  switch (key) {
    case GLFW_KEY_1:
    case GLFW_KEY_2:
    case GLFW_KEY_3:
      // Triangles filled, as their edges (polygon mode line) or as their corners.
      prim_ = key == GLFW_KEY_1 ? PrimMode::Triangles : key == GLFW_KEY_2 ? PrimMode::Wireframe : PrimMode::Points;
      rs_.polygon = key == GLFW_KEY_1 ? PolygonMode::Fill : key == GLFW_KEY_2 ? PolygonMode::Line : PolygonMode::Point;
      notice(std::string("mode ") + toString(prim_));
      break;
    case GLFW_KEY_C:
      rs_.cull = rs_.cull == CullMode::Back ? CullMode::None : CullMode::Back;
      notice(std::string("cull ") + toString(rs_.cull));
      break;
    case GLFW_KEY_M: {
      const std::vector<RasterMethod> ms = allRasterMethods();
      const RasterMethod cur = renderer_.resolveMethod(rs_);
      size_t i = size_t(std::find(ms.begin(), ms.end(), cur) - ms.begin());
      if (i >= ms.size()) i = 0;
      i = shift ? (i + ms.size() - 1) % ms.size() : (i + 1) % ms.size();
      rs_.raster = ms[i];
      notice(std::string("raster ") + toString(rs_.raster));
      break;
    }
    case GLFW_KEY_L: {
      const std::vector<ShadingMode> order = shadingModes();
      size_t i = size_t(std::find(order.begin(), order.end(), rs_.shading) - order.begin());
      if (i >= order.size()) i = 0;
      rs_.shading = order[shift ? (i + order.size() - 1) % order.size() : (i + 1) % order.size()];
      notice(std::string("shading ") + toString(rs_.shading));
      break;
    }
    case GLFW_KEY_T: {
      const std::vector<TexFilter> order = filterModes();
      size_t i = size_t(std::find(order.begin(), order.end(), rs_.filter) - order.begin());
      if (i >= order.size()) i = 0;
      rs_.filter = order[shift ? (i + order.size() - 1) % order.size() : (i + 1) % order.size()];
      notice(std::string("filter ") + toString(rs_.filter));
      break;
    }
    case GLFW_KEY_F:
      orbit_.frame(boundsLo_, boundsHi_);
      notice("framed the scene");
      break;
    case GLFW_KEY_P:
      rs_.post.bloom = !rs_.post.bloom;
      notice(std::string("bloom ") + (rs_.post.bloom ? "on" : "off"));
      break;
    case GLFW_KEY_F12:
      shotRequested_ = true;  // taken between frames, never inside the overlay's frame
      return;
    case GLFW_KEY_H:
      help_ = !help_;
      if (help_) {
        std::printf("rast-viewer controls:\n");
        for (const auto& c : kControls) std::printf("  %-20s %s\n", c[0], c[1]);
        std::fflush(stdout);
      }
      break;
    case GLFW_KEY_O:
      overlay_ = !overlay_;
      break;
    case GLFW_KEY_ESCAPE:
    case GLFW_KEY_Q:
      quit_ = true;
      break;
    default:
      return;
  }
  dirty_ = true;
}

void Viewer::onDrag(int button, double dx, double dy) {
  if (button == 0) orbit_.orbit(dx, dy);
  else if (button == 1) orbit_.pan(dx, dy, rs_.height);
  else orbit_.zoomDrag(dy);
  dirty_ = true;
}

void Viewer::onScroll(double dy) {
  orbit_.zoomSteps(dy);
  dirty_ = true;
}

void Viewer::renderPipeline() {
  const auto t0 = Clock::now();
  const Camera cam = orbit_.camera();
  renderer_.enqueue(cam, rs_, &timer_);
  stages_ = timer_.finish();
  if (!renderer_.lastFrameFit(&stats_)) {
    // Buffers grew: render again (the stage times above are of the first try).
    const int attempts = stats_.attempts;
    stats_ = renderer_.render(cam, rs_);
    stats_.attempts += attempts;
  }
  renderMs_ = msSince(t0);
  const auto t1 = Clock::now();
  copyOutMs_ = 0.0;
  // The cheapest way to the texture this build has (gl_display.h): device to
  // device, straight from host memory, or a copy out of the device.
  if (!Renderer::colorOnDevice()) {
    display_->uploadHost(renderer_.colorData(), rs_.width, rs_.height, /*topDown=*/false, DisplayPath::HostDirect);
  } else if (opts_.noInterop || !display_->uploadDevice(renderer_.colorData(), rs_.width, rs_.height)) {
    const std::vector<uint32_t> px = renderer_.colorTopDown();
    copyOutMs_ = msSince(t1);
    display_->uploadHost(px.data(), rs_.width, rs_.height, /*topDown=*/true, DisplayPath::HostCopy);
  }
  uploadMs_ = msSince(t1);
  dirty_ = false;
}

void Viewer::drawOverlay() {
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  if (overlay_) {
    ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
    ImGui::Begin("rast", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
    double avg = 0;
    for (double v : recentFrameMs_) avg += v;
    avg = recentFrameMs_.empty() ? 0.0 : avg / recentFrameMs_.size();
    ImGui::Text("FPS %.1f   frame %.2f ms", avg > 0 ? 1000.0 / avg : 0.0, avg);
    ImGui::Text("render %.2f ms   upload %.2f ms", renderMs_, uploadMs_);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("upload: copy out of the pipeline %.2f ms + GL texture", copyOutMs_);
    if (ImGui::BeginTable("stages", 2, ImGuiTableFlags_SizingFixedFit)) {
      for (const auto& s : stages_) {
        ImGui::TableNextRow();
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(s.first.c_str());
        ImGui::TableNextColumn();
        ImGui::Text("%8.3f ms", s.second);
      }
      ImGui::EndTable();
    }
    ImGui::Text("triangles %u in, %u visible", stats_.trianglesIn, stats_.rasterTris);
    ImGui::Text("method %s%s", toString(stats_.method), rs_.raster == RasterMethod::Auto ? " (auto)" : "");
    ImGui::Text("backend %s (%s threads)", backend_.c_str(), concurrency_.c_str());
    if (!device_.empty()) ImGui::TextUnformatted(device_.c_str());
    ImGui::Text("resolution %dx%d", rs_.width, rs_.height);
    ImGui::Text("display: %s", display_->pathDescription().c_str());
    ImGui::Separator();

    int prim = int(prim_);
    bool primChanged = ImGui::RadioButton("triangles (1)", &prim, 0);
    ImGui::SameLine();
    primChanged |= ImGui::RadioButton("wireframe (2)", &prim, 1);
    ImGui::SameLine();
    primChanged |= ImGui::RadioButton("points (3)", &prim, 2);
    if (primChanged) onKey(GLFW_KEY_1 + prim, 0);

    bool cull = rs_.cull == CullMode::Back;
    if (ImGui::Checkbox("back-face culling (C)", &cull)) onKey(GLFW_KEY_C, 0);

    auto combo = [&](const char* label, int current, const std::vector<std::string>& names) -> int {
      int sel = current;
      if (ImGui::BeginCombo(label, names[size_t(current)].c_str())) {
        for (size_t i = 0; i < names.size(); ++i)
          if (ImGui::Selectable(names[i].c_str(), int(i) == current)) sel = int(i);
        ImGui::EndCombo();
      }
      return sel;
    };
    ImGui::PushItemWidth(140);
    {
      std::vector<RasterMethod> ms = allRasterMethods();
      ms.insert(ms.begin(), RasterMethod::Auto);
      std::vector<std::string> names;
      int cur = 0;
      for (size_t i = 0; i < ms.size(); ++i) {
        names.push_back(toString(ms[i]));
        if (ms[i] == rs_.raster) cur = int(i);
      }
      const int sel = combo("raster method (M)", cur, names);
      if (sel != cur) {
        rs_.raster = ms[size_t(sel)];
        notice(std::string("raster ") + toString(rs_.raster));
        dirty_ = true;
      }
    }
    {
      const std::vector<ShadingMode> modes = shadingModes();
      std::vector<std::string> names;
      int cur = 0;
      for (size_t i = 0; i < modes.size(); ++i) {
        names.push_back(toString(modes[i]));
        if (modes[i] == rs_.shading) cur = int(i);
      }
      const int sel = combo("lighting (L)", cur, names);
      if (sel != cur) {
        rs_.shading = modes[size_t(sel)];
        notice(std::string("shading ") + toString(rs_.shading));
        dirty_ = true;
      }
    }
    {
      const std::vector<TexFilter> modes = filterModes();
      std::vector<std::string> names;
      int cur = 0;
      for (size_t i = 0; i < modes.size(); ++i) {
        names.push_back(toString(modes[i]));
        if (modes[i] == rs_.filter) cur = int(i);
      }
      const int sel = combo("texture filter (T)", cur, names);
      if (sel != cur) {
        rs_.filter = modes[size_t(sel)];
        notice(std::string("filter ") + toString(rs_.filter));
        dirty_ = true;
      }
    }
    drawPostControls();
    ImGui::PopItemWidth();
    if (ImGui::Button("frame scene (F)")) onKey(GLFW_KEY_F, 0);
    ImGui::SameLine();
    if (ImGui::Button("screenshot (F12)")) onKey(GLFW_KEY_F12, 0);
    ImGui::SameLine();
    if (ImGui::Button("help (H)")) help_ = !help_;
    if (!notice_.empty() && msSince(noticeAt_) < 4000.0) {
      ImGui::Separator();
      ImGui::TextWrapped("%s", notice_.c_str());
    }
    ImGui::End();
  }
  if (help_) {
    // Bottom right, clear of the statistics window at the top left.
    const ImVec2 size = ImGui::GetIO().DisplaySize;
    ImGui::SetNextWindowPos(ImVec2(size.x - 10.0f, size.y - 10.0f), ImGuiCond_Always, ImVec2(1.0f, 1.0f));
    ImGui::Begin("controls", &help_, ImGuiWindowFlags_AlwaysAutoResize);
    if (ImGui::BeginTable("keys", 2, ImGuiTableFlags_SizingFixedFit | ImGuiTableFlags_RowBg)) {
      for (const auto& c : kControls) {
        ImGui::TableNextRow();
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(c[0]);
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(c[1]);
      }
      ImGui::EndTable();
    }
    ImGui::End();
  }
  ImGui::Render();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

void Viewer::present(const std::string& windowShot) {
  int fw = 0, fh = 0;
  glfwGetFramebufferSize(win_, &fw, &fh);
  // Host-side times of each part (GL queues work; the swap is where the host
  // waits for it, and under Xvfb where the frame is copied to the X server).
  auto t = Clock::now();
  display_->draw(fw, fh);
  drawMs_ = msSince(t);
  t = Clock::now();
  if (imgui_) drawOverlay();
  overlayMs_ = msSince(t);
  if (!windowShot.empty()) {
    writePng(windowShot, fw, fh, GlDisplay::readWindow(fw, fh));
    std::printf("rast-viewer: wrote %s (window, %dx%d)\n", windowShot.c_str(), fw, fh);
    std::fflush(stdout);
  }
  t = Clock::now();
  glfwSwapBuffers(win_);
  swapMs_ = msSince(t);
}

void Viewer::frame() {
  // Render every frame, changed or not: the overlay's times are the pipeline's.
  renderPipeline();
  present();
  drawMsAll_.push(drawMs_);
  overlayMsAll_.push(overlayMs_);
  swapMsAll_.push(swapMs_);
  uploadMsAll_.push(uploadMs_);
  copyOutMsAll_.push(copyOutMs_);
  const auto now = Clock::now();
  if (framesShown_ > 0) {
    const double ms = std::chrono::duration<double, std::milli>(now - lastFrameEnd_).count();
    frameMs_.push(ms);
    recentFrameMs_.push_back(ms);
    if (recentFrameMs_.size() > 30) recentFrameMs_.pop_front();
  }
  renderMsAll_.push(renderMs_);
  lastFrameEnd_ = now;
  ++framesShown_;
}

std::string Viewer::nextScreenshotName() const {
  for (int i = 1;; ++i) {
    char b[64];
    std::snprintf(b, sizeof b, "rast-viewer-%03d", i);
    if (!std::ifstream(std::string(b) + ".png")) return b;
  }
}

void Viewer::saveScreenshot(const std::string& path) {
  ensureRendered();
  writePng(path, rs_.width, rs_.height, renderer_.colorTopDown());
  std::printf("rast-viewer: wrote %s (%dx%d, %s)\n", path.c_str(), rs_.width, rs_.height, stateLine().c_str());
  std::fflush(stdout);
}

void Viewer::saveWindowScreenshot(const std::string& path) {
  ensureRendered();
  present(path);
}

void Viewer::takeRequestedShots() {
  if (!shotRequested_) return;
  shotRequested_ = false;
  const std::string base = nextScreenshotName();
  saveScreenshot(base + ".png");
  saveWindowScreenshot(base + "-window.png");
}

void Viewer::drawPostControls() {
  PostSettings p = rs_.post;
  ImGui::Separator();
  ImGui::TextUnformatted("post-processing");
  ImGui::SliderFloat("exposure (EV)", &p.exposure, -6.0f, 6.0f, "%.2f");
  int tm = int(p.tonemap);
  const char* names[] = {"none", "reinhard", "aces"};
  ImGui::Combo("tone map", &tm, names, 3);
  p.tonemap = ToneMap(tm);
  ImGui::Checkbox("bloom (P)", &p.bloom);
  if (p.bloom) {
    ImGui::SliderFloat("threshold", &p.bloomThreshold, 0.0f, 4.0f, "%.2f");
    ImGui::SliderFloat("strength", &p.bloomStrength, 0.0f, 4.0f, "%.2f");
    ImGui::SliderInt("radius (px)", &p.bloomRadius, 2, 128);
  }
  ImGui::Checkbox("SSAO", &p.ssao);
  if (p.ssao) {
    // 0 is automatic (5% of the distance to the orbit target).
    const float diag = float(glm::length(boundsHi_ - boundsLo_));
    ImGui::SliderFloat("AO radius (0 auto)", &p.ssaoRadius, 0.0f, diag > 0.0f ? 0.5f * diag : 1.0f, "%.3g");
    ImGui::SliderInt("AO samples", &p.ssaoSamples, 1, 64);
  }
  const PostSettings& o = rs_.post;
  if (p.exposure != o.exposure || p.tonemap != o.tonemap || p.bloom != o.bloom || p.bloomThreshold != o.bloomThreshold ||
      p.bloomStrength != o.bloomStrength || p.bloomRadius != o.bloomRadius || p.ssao != o.ssao ||
      p.ssaoRadius != o.ssaoRadius || p.ssaoSamples != o.ssaoSamples) {
    rs_.post = p;
    dirty_ = true;
  }
}

std::string Viewer::stateLine() const {
  char b[256];
  std::snprintf(b, sizeof b, "--size %dx%d --cull %s --shading %s --filter %s --raster %s --polygon %s method=%s mode=%s bloom=%s",
                rs_.width, rs_.height, toString(rs_.cull), toString(rs_.shading), toString(rs_.filter),
                toString(rs_.raster), toString(rs_.polygon), toString(renderer_.resolveMethod(rs_)), toString(prim_),
                rs_.post.bloom ? "on" : "off");
  return b;
}

void Viewer::applyScriptEvent(const ScriptEvent& e) {
  using K = ScriptEvent::Kind;
  switch (e.kind) {
    case K::Frame:
      for (int i = 0; i < e.count && !quit_; ++i) {
        glfwPollEvents();
        frame();
      }
      break;
    case K::Key: onKey(e.key, e.shift ? GLFW_MOD_SHIFT : 0); break;
    case K::Drag: onDrag(e.button, e.dx, e.dy); break;
    case K::Scroll: onScroll(e.dy); break;
    case K::Resize: {
      glfwSetWindowSize(win_, e.width, e.height);
      // The window system answers asynchronously; wait (briefly) for it.
      int fw = 0, fh = 0;
      const auto t0 = Clock::now();
      do {
        glfwWaitEventsTimeout(0.01);
        glfwGetFramebufferSize(win_, &fw, &fh);
      } while ((fw != e.width || fh != e.height) && msSince(t0) < 2000.0);
      if (fw != e.width || fh != e.height)
        std::fprintf(stderr, "rast-viewer: warning: asked for %dx%d, the window is %dx%d\n", e.width, e.height, fw, fh);
      setRenderSize(fw, fh);
      break;
    }
    case K::Screenshot: saveScreenshot(e.path); break;
    case K::WindowScreenshot: saveWindowScreenshot(e.path); break;
    case K::PrintCamera:
      std::printf("camera: %s\n", orbit_.camera().flags().c_str());
      std::fflush(stdout);
      break;
    case K::PrintState:
      ensureRendered();
      std::printf("state: %s triangles=%u visible=%u\n", stateLine().c_str(), stats_.trianglesIn, stats_.rasterTris);
      std::fflush(stdout);
      break;
    case K::PrintMemory: {
      const DeviceMemory dm = deviceMemory();
      std::printf("memory: frame %d rss %.1f MiB renderer %.1f MiB", framesShown_, residentBytes() / 1048576.0,
                  renderer_.deviceBytes() / 1048576.0);
      if (dm.known)
        std::printf(" device-used %.1f MiB of %.1f MiB", (dm.totalBytes - dm.freeBytes) / 1048576.0,
                    dm.totalBytes / 1048576.0);
      std::printf("\n");
      std::fflush(stdout);
      break;
    }
    case K::Quit: quit_ = true; break;
  }
}

int Viewer::run() {
  const bool scripted = !opts_.script.empty();
  size_t next = 0;
  while (!quit_ && !glfwWindowShouldClose(win_)) {
    if (scripted && next < script_.size()) {
      glfwPollEvents();
      applyScriptEvent(script_[next++]);
      takeRequestedShots();
      continue;
    }
    // Interactive, or after the script: frames until --frames is reached.
    if ((scripted || opts_.frames > 0) && framesShown_ >= opts_.frames) break;
    glfwPollEvents();
    frame();
    takeRequestedShots();
  }
  if (!opts_.screenshot.empty()) saveScreenshot(opts_.screenshot);
  if (!opts_.windowScreenshot.empty()) saveWindowScreenshot(opts_.windowScreenshot);
  if (framesShown_ > 1) {
    // Medians of the last kKeep frames. "without the swap" is what the viewer
    // itself costs per frame, whatever the window system adds.
    const double fm = frameMs_.median(), sw = swapMsAll_.median();
    const double own = renderMsAll_.median() + uploadMsAll_.median() + drawMsAll_.median() + overlayMsAll_.median();
    std::printf("rast-viewer: %d frames at %dx%d, median frame %.3f ms (%.1f fps): render %.3f ms, upload %.3f ms "
                "(copy-out %.3f ms), draw %.3f ms, overlay %.3f ms, swap %.3f ms; without the swap %.3f ms (%.0f fps); "
                "display %s; method %s, backend %s\n",
                framesShown_, rs_.width, rs_.height, fm, fm > 0 ? 1000.0 / fm : 0.0, renderMsAll_.median(),
                uploadMsAll_.median(), copyOutMsAll_.median(), drawMsAll_.median(), overlayMsAll_.median(), sw, own,
                own > 0 ? 1000.0 / own : 0.0, display_->pathDescription().c_str(),
                toString(renderer_.resolveMethod(rs_)), backend_.c_str());
  }
  return 0;
}

int run(int argc, char** argv) {
  CLI::App app{"rast-viewer: shows a glTF scene (or a built-in one) rendered by the Kokkos pipeline in a window",
               "rast-viewer"};
  ViewerOptions o;
  o.scene.size = "1280x720";
  o.scene.addTo(app);
  app.add_option("--script", o.script, "replay input events from FILE (see docs/viewer.md), then exit");
  app.add_option("--frames", o.frames, "show N frames (after the script, if any), then exit");
  app.add_option("--screenshot", o.screenshot, "at exit, write the pipeline's colour buffer to this PNG");
  app.add_option("--window-screenshot", o.windowScreenshot, "at exit, write the window (with the overlay) to this PNG");
  app.add_flag("--no-overlay", o.noOverlay, "no Dear ImGui overlay");
  app.add_flag("--no-vsync", o.noVsync, "do not wait for the display's refresh");
  app.add_flag("--no-interop", o.noInterop,
               "GPU builds: copy each frame through the host instead of device to device (to compare the paths)");
  if (const std::optional<int> status = parseCommandLine(app, "rast-viewer", argc, argv)) return *status;
  if (o.frames < 0) throw Error("--frames must be >= 0");

  // Everything that can fail on bad input happens before the window opens.
  RenderSettings rs = o.scene.settings();
  const Scene scene = loadSceneArg(o.scene.scene, o.scene.loadOptions());
  const Camera cam = o.scene.camera(scene);
  o.scene.applySceneLook(scene, rs, /*still=*/false);
  std::vector<ScriptEvent> script;
  if (!o.script.empty()) script = loadScript(o.script);
  if (!o.scene.cameraGiven()) std::printf("rast-viewer: camera (%s) %s\n", cameraOrigin(scene), cam.flags().c_str());

  Viewer v(o, scene, cam, rs, std::move(script));
  v.openWindow();
  return v.run();
}

}  // namespace
}  // namespace rast

int main(int argc, char** argv) {
#if defined(__GLIBC__)
  // Every frame copies the colour buffer out of the pipeline into fresh
  // vectors (Renderer::colorTopDown). glibc would hand such multi-megabyte
  // blocks back to the kernel on free and fault them in again on the next
  // frame, which costs tens of milliseconds per frame in a VM; keep them in the
  // heap instead.
  mallopt(M_MMAP_THRESHOLD, 256 << 20);
  mallopt(M_TRIM_THRESHOLD, 512 << 20);
#endif
  return rast::guardedMain("rast-viewer", argc, argv, rast::run);
}
