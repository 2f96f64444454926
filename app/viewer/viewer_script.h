// Input scripts of rast-viewer (--script FILE): one event per line, replayed
// through the same handlers as the real mouse and keyboard.
//
//   # comment                     blank lines and comments are skipped
//   frame [N]                     render and show N frames (default 1)
//   key K                         press key K: a letter or digit, or F1..F12,
//                                 escape, space, tab; "shift+K" adds Shift
//   drag left|right|middle DX DY  drag with a mouse button by (DX, DY) window
//                                 pixels (y down)
//   scroll DY                     mouse wheel by DY steps (up = positive)
//   resize W H                    resize the window (and so the framebuffers)
//   screenshot FILE.png           the pipeline's colour buffer (rast's image)
//   window-screenshot FILE.png    the window as shown, overlay included
//   print-camera                  "camera: --eye ... --far ..." on stdout
//   print-state                   "state: --size WxH --cull ... method=..." on stdout
//   print-memory                  "memory: frame N rss X MiB renderer Y MiB [device-used ...]"
//   quit                          stop here
#pragma once

#include <string>
#include <vector>

namespace rast {

struct ScriptEvent {
  enum class Kind { Frame, Key, Drag, Scroll, Resize, Screenshot, WindowScreenshot, PrintCamera, PrintState, PrintMemory, Quit };
  Kind kind = Kind::Frame;
  int count = 1;              // frame
  int key = 0;                // key: a GLFW key code
  bool shift = false;         // key
  int button = 0;             // drag: 0 left, 1 right, 2 middle (GLFW's numbering)
  double dx = 0.0, dy = 0.0;  // drag; scroll uses dy
  int width = 0, height = 0;  // resize
  std::string path;           // screenshots
  int line = 0;               // where it came from, for messages
};

// Parses a whole script; throws Error("FILE:LINE: ...") on the first bad line.
std::vector<ScriptEvent> parseScript(const std::string& text, const std::string& fileName);
std::vector<ScriptEvent> loadScript(const std::string& path);

// GLFW key code of a key name ("C", "7", "F1", "escape", ...); -1 when unknown.
int keyFromName(const std::string& name);

}  // namespace rast
