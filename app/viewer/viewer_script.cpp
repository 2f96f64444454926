#include "app/viewer/viewer_script.h"

#include "base/error.h"

#include <GLFW/glfw3.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace rast {

namespace {

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

bool toDouble(const std::string& s, double& out) {
  char* end = nullptr;
  out = std::strtod(s.c_str(), &end);
  return !s.empty() && *end == '\0' && std::isfinite(out);
}

bool toInt(const std::string& s, int& out) {
  char* end = nullptr;
  const long v = std::strtol(s.c_str(), &end, 10);
  if (s.empty() || *end != '\0' || v < -1000000000L || v > 1000000000L) return false;
  out = int(v);
  return true;
}

}  // namespace

int keyFromName(const std::string& name) {
  if (name.size() == 1) {
    const char c = char(std::toupper(static_cast<unsigned char>(name[0])));
    if (c >= 'A' && c <= 'Z') return GLFW_KEY_A + (c - 'A');
    if (c >= '0' && c <= '9') return GLFW_KEY_0 + (c - '0');
    return -1;
  }
  const std::string n = lower(name);
  if (n == "escape" || n == "esc") return GLFW_KEY_ESCAPE;
  if (n == "space") return GLFW_KEY_SPACE;
  if (n == "tab") return GLFW_KEY_TAB;
  if (n.size() >= 2 && n[0] == 'f') {
    int k = 0;
    if (toInt(n.substr(1), k) && k >= 1 && k <= 12) return GLFW_KEY_F1 + (k - 1);
  }
  return -1;
}

std::vector<ScriptEvent> parseScript(const std::string& text, const std::string& fileName) {
  std::vector<ScriptEvent> events;
  std::istringstream in(text);
  std::string line;
  int lineNo = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    std::istringstream ls(line);
    std::vector<std::string> w;
    for (std::string t; ls >> t;) w.push_back(t);
    if (w.empty()) continue;
    const std::string where = fileName + ":" + std::to_string(lineNo) + ": ";
    auto fail = [&](const std::string& msg) { throw Error(where + msg + " (in '" + line + "')"); };
    auto argc = [&](size_t lo, size_t hi) {
      if (w.size() - 1 < lo || w.size() - 1 > hi)
        fail("'" + w[0] + "' takes " + (lo == hi ? std::to_string(lo) : std::to_string(lo) + " to " + std::to_string(hi)) +
             " argument(s)");
    };
    ScriptEvent e;
    e.line = lineNo;
    const std::string cmd = lower(w[0]);
    if (cmd == "frame" || cmd == "frames") {
      argc(0, 1);
      e.kind = ScriptEvent::Kind::Frame;
      if (w.size() == 2 && (!toInt(w[1], e.count) || e.count < 1)) fail("frame count must be a positive integer");
    } else if (cmd == "key") {
      argc(1, 1);
      e.kind = ScriptEvent::Kind::Key;
      std::string k = w[1];
      if (lower(k).rfind("shift+", 0) == 0 && k.size() > 6) {
        e.shift = true;
        k = k.substr(6);
      }
      e.key = keyFromName(k);
      if (e.key < 0) fail("unknown key '" + w[1] + "' (letters, digits, F1..F12, escape, space, tab)");
    } else if (cmd == "drag") {
      argc(3, 3);
      e.kind = ScriptEvent::Kind::Drag;
      const std::string b = lower(w[1]);
      if (b == "left") e.button = 0;
      else if (b == "right") e.button = 1;
      else if (b == "middle") e.button = 2;
      else fail("drag button must be left, right or middle");
      if (!toDouble(w[2], e.dx) || !toDouble(w[3], e.dy)) fail("drag needs two numbers DX DY");
    } else if (cmd == "scroll") {
      argc(1, 1);
      e.kind = ScriptEvent::Kind::Scroll;
      if (!toDouble(w[1], e.dy)) fail("scroll needs a number");
    } else if (cmd == "resize") {
      argc(2, 2);
      e.kind = ScriptEvent::Kind::Resize;
      if (!toInt(w[1], e.width) || !toInt(w[2], e.height) || e.width < 1 || e.height < 1 || e.width > 16384 ||
          e.height > 16384)
        fail("resize needs W H in 1..16384");
    } else if (cmd == "screenshot" || cmd == "window-screenshot") {
      argc(1, 1);
      e.kind = cmd == "screenshot" ? ScriptEvent::Kind::Screenshot : ScriptEvent::Kind::WindowScreenshot;
      e.path = w[1];
    } else if (cmd == "print-camera") {
      argc(0, 0);
      e.kind = ScriptEvent::Kind::PrintCamera;
    } else if (cmd == "print-state") {
      argc(0, 0);
      e.kind = ScriptEvent::Kind::PrintState;
    } else if (cmd == "print-memory") {
      argc(0, 0);
      e.kind = ScriptEvent::Kind::PrintMemory;
    } else if (cmd == "quit") {
      argc(0, 0);
      e.kind = ScriptEvent::Kind::Quit;
    } else {
      fail("unknown event '" + w[0] +
           "' (frame, key, drag, scroll, resize, screenshot, window-screenshot, print-camera, print-state, print-memory, quit)");
    }
    events.push_back(e);
  }
  return events;
}

std::vector<ScriptEvent> loadScript(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw Error("cannot read script '" + path + "'");
  std::ostringstream ss;
  ss << f.rdbuf();
  return parseScript(ss.str(), path);
}

}  // namespace rast
