// rast-viewer's input: GLFW's keyboard and mouse callbacks and the events of
// --script files go through the same handlers here, so that a script (and so
// tests/cli/cli_viewer.py under Xvfb) exercises exactly what a user's hands do.
// Keys are looked up in the action table (viewer_actions.h); the overlay's
// widgets end in runAction() too. Mouse drags and the wheel move the orbit
// camera (orbit_camera.h).
#include "app/viewer/viewer_app.h"

#include <GLFW/glfw3.h>
#include <imgui.h>

#include <cstdio>

namespace rast {
namespace {

Viewer* self(GLFWwindow* w) { return static_cast<Viewer*>(glfwGetWindowUserPointer(w)); }

}  // namespace

void Viewer::installInputCallbacks() {
  // Before ImGui's backend is initialised: it chains to these. The window's
  // user pointer is this Viewer (openWindow).
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
}

void Viewer::onKey(int key, int mods) {
  int keyIndex = 0;
  const ViewerAction* a = actionForKey(key, &keyIndex);
  if (!a) return;
  const int option = optionForKey(*a, *this, keyIndex, (mods & GLFW_MOD_SHIFT) != 0);
  if (option >= 0) runAction(*a, option);
}

void Viewer::runAction(const ViewerAction& a, int option) {
  if (a.kind == ActionKind::Command) {
    a.apply(*this, option);
    return;
  }
  const std::vector<std::string> names = a.options(*this);
  if (option < 0 || option >= int(names.size())) return;
  a.apply(*this, option);
  notice(std::string(a.name) + " " + names[size_t(option)]);
  dirty_ = true;
}

void Viewer::onDrag(int button, double dx, double dy) {
  leaveFileCamera();
  if (button == 0) orbit_.orbit(dx, dy);
  else if (button == 1) orbit_.pan(dx, dy, rs_.height);
  else orbit_.zoomDrag(dy);
  dirty_ = true;
}

void Viewer::onScroll(double dy) {
  leaveFileCamera();
  orbit_.zoomSteps(dy);
  dirty_ = true;
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
      std::printf("camera: %s\n", currentCamera().flags().c_str());
      std::fflush(stdout);
      break;
    case K::PrintState: printState(); break;
    case K::PrintMemory: printMemory(); break;
    case K::Quit: quit_ = true; break;
  }
}

}  // namespace rast
