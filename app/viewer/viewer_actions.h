// The table of rast-viewer's actions: one row per thing a user can do with a
// key (cycle the raster method, culling on/off, frame the scene, ...). Each row
// names the action, its keys, its help text, its overlay widget and label, and
// how it reads and changes the viewer. Why one table: the keyboard, scripted
// `key K` events (viewer_script.h), the overlay's radio buttons, checkboxes,
// combo boxes and buttons, and the help window are all served from it, so they
// cannot drift apart, and adding an action means adding one row
// (viewer_actions.cpp).
//
// Scripts press keys by name ("key M", "key shift+M", "key F12"); a row's keys
// are written in that same spelling, so a row's key column is also its
// script-event name, and the overlay's labels ("raster method (M)") and the
// help table's key column ("M / Shift+M") are made from it too.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace rast {

class Viewer;

// What a key of the action does.
enum class ActionKind {
  Command,  // runs it (F: frame the scene)
  Toggle,   // two options, off and on: flips it (C: back-face culling)
  Cycle,    // the next option, with Shift the previous (M / Shift+M: raster method)
  Select,   // one key per option (1 / 2 / 3: triangles / wireframe / points)
};

// How the overlay shows the action. The overlay draws the kinds in this order,
// the rows of each kind in table order.
enum class Widget {
  None,          // keys only
  Radio,         // one radio button per option, on one line: "triangles (1)"
  Checkbox,      // ticked when on: "back-face culling (C)"
  Combo,         // a combo box of the options: "raster method (M)"
  PostCheckbox,  // a checkbox in the post-processing section: "bloom (P)"
  Button,        // a button, on one line with the other buttons: "frame scene (F)"
};

struct ViewerAction {
  const char* name;   // the word its notices start with: "raster" -> "rast-viewer: raster binned"
  const char* keys;   // its keys, space-separated, as scripts name them: "M", "1 2 3", "Esc Q"
  const char* help;   // the help table's text
  ActionKind kind;
  Widget widget;
  const char* label;  // the overlay's label, before " (KEY)"; Radio labels are the options' names
  // The options' names (nullptr for a command), which one is current (-1: none
  // of them), and choosing one (for a command: running it). Choosing an option
  // is followed by the notice "NAME OPTION" and a new pipeline frame.
  std::vector<std::string> (*options)(const Viewer&);
  int (*current)(const Viewer&);
  void (*apply)(Viewer&, int option);
  // Cycle only: where the keys step from when not current() (-1: the first
  // they reach), and how many leading options they skip (the raster method
  // steps from the method auto chose, and never to auto itself).
  int (*stepFrom)(const Viewer&) = nullptr;
  int stepSkip = 0;
};

// The table, in the help window's order; checked on first use (every key
// known to keyFromName, no key in two rows).
const std::vector<ViewerAction>& viewerActions();

// The row a key (GLFW key code) belongs to and which of its keys it is;
// nullptr when no action has that key.
const ViewerAction* actionForKey(int key, int* keyIndex);

// The option a key press chooses, given the current state (-1: none).
int optionForKey(const ViewerAction& a, const Viewer& v, int keyIndex, bool shift);

// An overlay label: TEXT and the row's keyIndex-th key, "raster method (M)",
// "wireframe (2)" (Radio rows label each option with its own key).
std::string actionLabel(const ViewerAction& a, const std::string& text, int keyIndex = 0);

// The help table: the mouse, then every action; {"M / Shift+M", "next / previous raster method"}.
std::vector<std::pair<std::string, std::string>> controlsTable();

}  // namespace rast
