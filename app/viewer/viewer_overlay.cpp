// What rast-viewer shows and prints about itself: the Dear ImGui panel
// (timings, stage times, triangle counts, method, backend, display path, the
// action table's widgets and the post-processing controls), the help window,
// notices, and the statistics behind them: per-frame times, the script's
// print-state and print-memory lines and the summary line at exit. These
// texts are what users and tests/cli/cli_viewer.py read, so they live together
// here, away from the window and input code.
#include "app/viewer/viewer_app.h"

#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include <algorithm>
#include <cstdio>
#include <fstream>

#include <unistd.h>  // sysconf, for the resident set size

namespace rast {
namespace {

// Resident set size of this process in bytes (Linux /proc; 0 elsewhere).
size_t residentBytes() {
  std::ifstream f("/proc/self/statm");
  size_t pages = 0, rss = 0;
  if (!(f >> pages >> rss)) return 0;
  return rss * size_t(sysconf(_SC_PAGESIZE));
}

}  // namespace

double FrameSeries::median() const {
  if (v.empty()) return 0.0;
  std::vector<double> s = v;  // sorts a copy
  std::sort(s.begin(), s.end());
  const size_t n = s.size();
  return n % 2 ? s[n / 2] : 0.5 * (s[n / 2 - 1] + s[n / 2]);
}

void Viewer::notice(const std::string& text) {
  notice_ = text;
  noticeAt_ = Clock::now();
  std::printf("rast-viewer: %s\n", text.c_str());
  std::fflush(stdout);
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

    // The action table's widgets (viewer_actions.h), kind by kind.
    drawActionWidgets(Widget::Radio);
    drawActionWidgets(Widget::Checkbox);
    ImGui::PushItemWidth(140);
    drawActionWidgets(Widget::Combo);
    drawPostControls();
    ImGui::PopItemWidth();
    drawActionWidgets(Widget::Button);
    if (animated_) {  // the timeline scrubber: dragging it pauses the animation there
      float t = float(animTime_);
      ImGui::PushItemWidth(220);
      if (ImGui::SliderFloat("time (s)", &t, float(animStart()), float(animEnd()), "%.3f")) {
        playing_ = false;
        setAnimationTime(t);
      }
      ImGui::PopItemWidth();
    }
    if (!notice_.empty() && msSince(noticeAt_) < 4000.0) {
      ImGui::Separator();
      ImGui::TextWrapped("%s", notice_.c_str());
    }
    ImGui::End();
  }
  if (help_) drawHelpWindow();
  ImGui::Render();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

void Viewer::drawActionWidgets(Widget w) {
  bool first = true;
  for (const ViewerAction& a : viewerActions()) {
    if (a.widget != w) continue;
    const std::vector<std::string> names = a.options ? a.options(*this) : std::vector<std::string>();
    const int cur = a.options ? a.current(*this) : -1;
    switch (w) {
      case Widget::None: break;
      case Widget::Radio: {
        int sel = cur;
        bool changed = false;
        for (size_t i = 0; i < names.size(); ++i) {
          if (i > 0) ImGui::SameLine();
          changed |= ImGui::RadioButton(actionLabel(a, names[i], int(i)).c_str(), &sel, int(i));
        }
        if (changed) runAction(a, sel);
        break;
      }
      case Widget::Checkbox:
      case Widget::PostCheckbox: {
        bool on = cur == 1;
        if (ImGui::Checkbox(actionLabel(a, a.label).c_str(), &on)) runAction(a, on ? 1 : 0);
        break;
      }
      case Widget::Combo: {
        if (names.empty()) break;
        const int shown = cur < 0 ? 0 : cur;
        int sel = shown;
        if (ImGui::BeginCombo(actionLabel(a, a.label).c_str(), names[size_t(shown)].c_str())) {
          for (size_t i = 0; i < names.size(); ++i)
            if (ImGui::Selectable(names[i].c_str(), int(i) == shown)) sel = int(i);
          ImGui::EndCombo();
        }
        if (sel != shown) runAction(a, sel);
        break;
      }
      case Widget::Button:
        if (!first) ImGui::SameLine();
        if (ImGui::Button(actionLabel(a, a.label).c_str())) runAction(a, 0);
        break;
    }
    first = false;
  }
}

void Viewer::drawPostControls() {
  PostSettings p = rs_.post;
  ImGui::Separator();
  ImGui::TextUnformatted("post-processing");
  ImGui::SliderFloat("exposure (EV)", &p.exposure, -6.0f, 6.0f, "%.2f");
  int tm = int(p.tonemap);
  const char* names[] = {"none", "reinhard", "aces", "neutral"};  // ToneMap's order; neutral: Khronos PBR Neutral
  ImGui::Combo("tone map", &tm, names, 4);
  p.tonemap = ToneMap(tm);
  drawActionWidgets(Widget::PostCheckbox);  // bloom (P): the table's row, as its key does
  p.bloom = rs_.post.bloom;
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

void Viewer::drawHelpWindow() {
  // Bottom right, clear of the statistics window at the top left.
  const ImVec2 size = ImGui::GetIO().DisplaySize;
  ImGui::SetNextWindowPos(ImVec2(size.x - 10.0f, size.y - 10.0f), ImGuiCond_Always, ImVec2(1.0f, 1.0f));
  ImGui::Begin("controls", &help_, ImGuiWindowFlags_AlwaysAutoResize);
  if (ImGui::BeginTable("keys", 2, ImGuiTableFlags_SizingFixedFit | ImGuiTableFlags_RowBg)) {
    for (const auto& c : controlsTable()) {
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(c.first.c_str());
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(c.second.c_str());
    }
    ImGui::EndTable();
  }
  ImGui::End();
}

void Viewer::printHelp() const {
  std::printf("rast-viewer controls:\n");
  for (const auto& c : controlsTable()) std::printf("  %-20s %s\n", c.first.c_str(), c.second.c_str());
  std::fflush(stdout);
}

void Viewer::recordFrameTimes() {
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

std::string Viewer::stateLine() const {
  char b[256];
  std::snprintf(b, sizeof b, "--size %dx%d --cull %s --shading %s --filter %s --raster %s --polygon %s method=%s mode=%s bloom=%s",
                rs_.width, rs_.height, toString(rs_.cull), toString(rs_.shading), toString(rs_.filter),
                toString(rs_.raster), toString(rs_.polygon), toString(renderer_.resolveMethod(rs_)), toString(prim_),
                rs_.post.bloom ? "on" : "off");
  std::string s = b;
  s += " camera=" + (camera_ < 0 ? std::string("orbit") : std::to_string(camera_));
  s += " env=" + (rs_.environment.empty() ? std::string("built-in") : rs_.environment);
  if (animated_) s += " time=" + std::to_string(animTime_) + (playing_ ? " playing" : " paused");
  return s;
}

void Viewer::printState() {
  ensureRendered();
  std::printf("state: %s triangles=%u visible=%u\n", stateLine().c_str(), stats_.trianglesIn, stats_.rasterTris);
  std::fflush(stdout);
}

void Viewer::printMemory() const {
  const DeviceMemory dm = deviceMemory();
  std::printf("memory: frame %d rss %.1f MiB renderer %.1f MiB", framesShown_, residentBytes() / 1048576.0,
              renderer_.deviceBytes() / 1048576.0);
  if (dm.known)
    std::printf(" device-used %.1f MiB of %.1f MiB", (dm.totalBytes - dm.freeBytes) / 1048576.0,
                dm.totalBytes / 1048576.0);
  std::printf("\n");
  std::fflush(stdout);
}

void Viewer::printSummary() const {
  // Medians of the last FrameSeries::kKeep frames. "without the swap" is what
  // the viewer itself costs per frame, whatever the window system adds.
  const double fm = frameMs_.median(), sw = swapMsAll_.median();
  const double own = renderMsAll_.median() + uploadMsAll_.median() + drawMsAll_.median() + overlayMsAll_.median();
  std::printf("rast-viewer: %d frames at %dx%d, median frame %.3f ms (%.1f fps): render %.3f ms, upload %.3f ms "
              "(copy-out %.3f ms), draw %.3f ms, overlay %.3f ms, swap %.3f ms; without the swap %.3f ms (%.0f fps); "
              "display %s; method %s, backend %s\n",
              framesShown_, rs_.width, rs_.height, fm, fm > 0 ? 1000.0 / fm : 0.0, renderMsAll_.median(),
              uploadMsAll_.median(), copyOutMsAll_.median(), drawMsAll_.median(), overlayMsAll_.median(), sw, own,
              own > 0 ? 1000.0 / own : 0.0, display_->pathDescription().c_str(), toString(renderer_.resolveMethod(rs_)),
              backend_.c_str());
}

}  // namespace rast
