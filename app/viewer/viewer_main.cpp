// rast-viewer: shows the Kokkos pipeline's frames in a GLFW window, with an
// orbit camera and a Dear ImGui overlay. See docs/viewer.md. This file holds
// the program's skeleton: the command line, the window, the main loop, each
// frame's render and display, and the screenshots. Input, the overlay and the
// action table are in their own files (viewer_app.h lists them).
//
//   rast-viewer [SCENE] [--size WxH] [camera and render options of rast render]
//               [--script FILE] [--frames N] [--screenshot F.png]
//               [--window-screenshot F.png] [--no-overlay] [--no-vsync] [--no-interop]
//
// The scene (and the script) are loaded before any window opens, so bad input
// ends in one line "rast-viewer: error: ..." on stderr and exit status 1, with
// no window shown. The error texts are rast render's.
#include "host/image/image_io.h"
#include "scenes/procedural.h"
#include "app/guarded_main.h"
#include "app/viewer/viewer_app.h"

#include <CLI/CLI.hpp>
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace rast {
namespace {

std::string g_glfwError;
void onGlfwError(int code, const char* text) {
  g_glfwError = std::string(text ? text : "unknown") + " (GLFW error " + std::to_string(code) + ")";
}

}  // namespace

Viewer::Viewer(const ViewerOptions& o, const Scene& scene, const Camera& cam, const RenderSettings& rs,
               std::vector<ScriptEvent> script)
    : opts_(o), renderer_(scene, o.scene.memoryBudget()), rs_(rs), orbit_(cam), script_(std::move(script)) {
  viewerActions();  // checks the action table here, before any window opens, not in a key callback
  scene.worldBounds(boundsLo_, boundsHi_);
  prim_ = rs.polygon == PolygonMode::Line ? PrimMode::Wireframe : rs.polygon == PolygonMode::Point ? PrimMode::Points
                                                                                                  : PrimMode::Triangles;
  for (size_t i = 0; i < scene.cameras.size(); ++i) {
    fileCameras_.push_back(fileCamera(scene, std::to_string(i)));
    fileCameraNames_.push_back(std::to_string(i) + (scene.cameras[i].name.empty() ? "" : " " + scene.cameras[i].name));
  }
  environments_ = {"", "none"};
  if (!rs.environment.empty() && rs.environment != "none") environments_.push_back(rs.environment);
  if (scene.rig && !scene.rig->animations.empty()) {
    posed_ = scene;
    animated_ = true;
    animTime_ = scene.poseTime;
    if (scene.poseAnimation >= 0) animation_ = scene.poseAnimation;
    playing_ = !o.scene.time;  // --time shows that pose, paused
    lastTick_ = Clock::now();
  }
  std::istringstream dd(deviceDescription());
  for (std::string l; std::getline(dd, l);) {
    if (l.rfind("backend: ", 0) == 0) backend_ = l.substr(9);
    else if (l.rfind("concurrency: ", 0) == 0) concurrency_ = l.substr(13);
    else if (l.rfind("device: ", 0) == 0) device_ = l.substr(8);
  }
}

Viewer::~Viewer() { closeWindow(); }

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

  installInputCallbacks();  // viewer_input.cpp; before ImGui's backend, which chains to them

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

void Viewer::renderPipeline() {
  const auto t0 = Clock::now();
  const Camera cam = currentCamera();
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

double Viewer::animStart() const {
  if (!animated_) return 0.0;
  const auto& list = posed_.rig->animations;
  if (animation_ >= 0) return list[size_t(animation_)].start;
  double t = list[0].start;
  for (const Animation& a : list) t = std::min(t, a.start);
  return t;
}

double Viewer::animEnd() const {
  if (!animated_) return 0.0;
  const auto& list = posed_.rig->animations;
  if (animation_ >= 0) return list[size_t(animation_)].end;
  double t = list[0].end;
  for (const Animation& a : list) t = std::max(t, a.end);
  return t;
}

void Viewer::setAnimationTime(double t) {
  if (!animated_) return;
  animTime_ = t;
  poseScene(posed_, PoseRequest{t, animation_}, /*skinOnHost=*/false);  // the vertex stage skins
  renderer_.updatePose(posed_);
  dirty_ = true;
}

void Viewer::advanceAnimation() {
  const Clock::time_point now = Clock::now();
  const double dt = std::chrono::duration<double>(now - lastTick_).count();
  lastTick_ = now;
  if (!animated_ || !playing_) return;
  const double a = animStart(), b = animEnd();
  double t = animTime_ + dt * speed_;
  if (t > b) t = loop_ && b > a ? a + std::fmod(t - a, b - a) : b;
  setAnimationTime(t);
}

void Viewer::frame() {
  // Render every frame, changed or not: the overlay's times are the pipeline's.
  advanceAnimation();
  renderPipeline();
  present();
  recordFrameTimes();
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
  if (framesShown_ > 1) printSummary();
  return 0;
}

namespace {

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
  Scene scene = loadSceneArg(o.scene.scene, o.scene.loadOptions());
  o.scene.pose(scene);  // --time/--animation: the pose to start from
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
