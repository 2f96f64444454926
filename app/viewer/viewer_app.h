// The Viewer class of rast-viewer, shared by the files the viewer is split
// into by job, so that each stays small enough to read in one sitting:
//   viewer_main.cpp     command line, window, main loop, frames, screenshots;
//   viewer_input.cpp    keyboard and mouse callbacks, script events;
//   viewer_overlay.cpp  the Dear ImGui panel, the help window, statistics;
//   viewer_actions.cpp  the one table of actions (keys, script keys, widgets).
// All four work on the state declared here; the action table reaches it as a
// friend (viewerActions()), so that a new action is one row there.
#pragma once

#include "backends/stage_timer.h"
#include "pipeline/frame/renderer.h"
#include "app/cli_options.h"
#include "app/viewer/gl_display.h"
#include "app/viewer/orbit_camera.h"
#include "app/viewer/viewer_actions.h"
#include "app/viewer/viewer_script.h"

#include <chrono>
#include <cstddef>
#include <deque>
#include <memory>
#include <string>
#include <utility>
#include <vector>

struct GLFWwindow;

namespace rast {

using Clock = std::chrono::steady_clock;
inline double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// Per-frame times, bounded: a soak of 100,000 frames must not grow the heap,
// so each series keeps the last kKeep samples (medians are of those).
struct FrameSeries {
  static constexpr size_t kKeep = 16384;
  std::vector<double> v;
  size_t next = 0;
  void push(double x) {
    if (v.size() < kKeep) v.push_back(x);
    else v[next] = x;
    next = (next + 1) % kKeep;
  }
  double median() const;  // viewer_overlay.cpp
};

struct ViewerOptions {
  SceneOptions scene;
  std::string script, screenshot, windowScreenshot;
  int frames = 0;
  bool noOverlay = false, noVsync = false, noInterop = false;
};

enum class PrimMode { Triangles, Wireframe, Points };
inline const char* toString(PrimMode m) {
  return m == PrimMode::Triangles ? "triangles" : m == PrimMode::Wireframe ? "wireframe" : "points";
}

class Viewer {
 public:
  Viewer(const ViewerOptions& o, const Scene& scene, const Camera& cam, const RenderSettings& rs,
         std::vector<ScriptEvent> script);
  ~Viewer();

  void openWindow();
  int run();

 private:
  friend const std::vector<ViewerAction>& viewerActions();  // the table changes the state below

  // Input, from GLFW callbacks and from scripts alike (viewer_input.cpp).
  void installInputCallbacks();
  void onKey(int key, int mods);
  void onDrag(int button, double dx, double dy);
  void onScroll(double dy);
  void runAction(const ViewerAction& a, int option);  // from a key, a script or the overlay
  void applyScriptEvent(const ScriptEvent& e);

  // Window and frames (viewer_main.cpp).
  void setRenderSize(int w, int h);
  void renderPipeline();                             // one pipeline frame with the current camera and settings
  void present(const std::string& windowShot = "");  // display it, overlay, swap
  void frame();                                      // both, timed
  void ensureRendered() {
    if (dirty_) renderPipeline();
  }
  void saveScreenshot(const std::string& path);
  void saveWindowScreenshot(const std::string& path);
  void takeRequestedShots();
  std::string nextScreenshotName() const;
  void closeWindow();

  // Animation playback (docs/animation.md; viewer_main.cpp): the scene's pose
  // advanced by the wall clock times the speed while playing, each new pose
  // sent to the renderer (matrices, joints, morphed vertices) before the frame.
  void advanceAnimation();
  void setAnimationTime(double t);
  double animStart() const;
  double animEnd() const;

  // Overlay and statistics (viewer_overlay.cpp).
  void drawOverlay();
  void drawActionWidgets(Widget w);  // the table's rows shown as w, in table order
  void drawPostControls();           // exposure, tone mapping, bloom, SSAO with live parameters
  void drawHelpWindow();
  void printHelp() const;            // the help table on stdout
  void notice(const std::string& text);
  void recordFrameTimes();           // after each frame()
  void printState();                 // script print-state
  void printMemory() const;          // script print-memory
  void printSummary() const;         // the line at exit
  std::string stateLine() const;

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
  FrameSeries frameMs_, renderMsAll_, uploadMsAll_, copyOutMsAll_, drawMsAll_, overlayMsAll_, swapMsAll_;
  Clock::time_point lastFrameEnd_{};
  int framesShown_ = 0;

  // The glTF file's cameras (Scene::cameras, as the scene was posed when the
  // viewer started) and the one in use, -1 for the orbit camera. A drag, the
  // wheel or F leaves a file camera for the orbit camera at its pose (an
  // orthographic one becomes a perspective orbit).
  std::vector<Camera> fileCameras_;
  std::vector<std::string> fileCameraNames_;
  int camera_ = -1;
  Camera currentCamera() const { return camera_ >= 0 ? fileCameras_[size_t(camera_)] : orbit_.camera(); }
  void leaveFileCamera() {
    if (camera_ >= 0) orbit_.reset(fileCameras_[size_t(camera_)]);
    camera_ = -1;
  }
  // The glTF shading's environments E cycles: the built-in one (""), none,
  // and the --env file when one was given.
  std::vector<std::string> environments_;

  // Animation: a copy of the scene to pose (only when it has animations).
  Scene posed_;
  bool animated_ = false, playing_ = false, loop_ = true;
  int animation_ = kAllAnimations;
  double animTime_ = 0.0, speed_ = 1.0;
  Clock::time_point lastTick_{};
};

}  // namespace rast
