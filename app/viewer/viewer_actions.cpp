// The rows of rast-viewer's action table (viewer_actions.h says why there is
// one table), and the few functions that read it: which row a key belongs to,
// which option a key chooses, the overlay's labels and the help table.
// The Viewer runs a chosen option (Viewer::runAction, viewer_input.cpp) and
// draws the widgets (Viewer::drawActionWidgets, viewer_overlay.cpp).
#include "app/viewer/viewer_actions.h"

#include "base/error.h"
#include "app/viewer/viewer_app.h"
#include "app/viewer/viewer_script.h"

#include <algorithm>
#include <initializer_list>
#include <sstream>

namespace rast {
namespace {

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
  return knownModes<ShadingMode>(parseShading, {"lambert", "blinn-phong", "normals", "depth", "uv", "miplevel", "pbr",
                                                "basecolor", "metalrough", "occlusion", "emissive", "shading-normals"});
}
// T: bilinear <-> nearest first, then the rest.
std::vector<TexFilter> filterModes() { return knownModes<TexFilter>(parseFilter, {"bilinear", "nearest", "trilinear", "auto"}); }
// M: auto first in the combo box; the keys skip it (stepSkip 1).
std::vector<RasterMethod> rasterMethods() {
  std::vector<RasterMethod> ms = allRasterMethods();
  ms.insert(ms.begin(), RasterMethod::Auto);
  return ms;
}

// B: how BLEND surfaces are composited (docs/transparency.md).
std::vector<Transparency> transparencyModes() {
  return knownModes<Transparency>(parseTransparency, {"auto", "exact", "kbuffer", "weighted", "sorted"});
}

template <class T>
std::vector<std::string> namesOf(const std::vector<T>& values) {
  std::vector<std::string> out;
  for (const T& x : values) out.push_back(toString(x));
  return out;
}
template <class T>
int indexOf(const std::vector<T>& values, T x) {
  const auto it = std::find(values.begin(), values.end(), x);
  return it == values.end() ? -1 : int(it - values.begin());
}

std::vector<std::string> splitKeys(const char* keys) {
  std::istringstream in(keys);
  std::vector<std::string> out;
  for (std::string k; in >> k;) out.push_back(k);
  return out;
}

// Mouse input, which is not an action: the first rows of the help table.
const char* const kMouseControls[][2] = {
    {"left drag", "orbit around the target"},
    {"right drag", "pan"},
    {"wheel / middle drag", "zoom"},
};

void checkTable(const std::vector<ViewerAction>& table) {
  std::vector<int> seen;
  for (const ViewerAction& a : table) {
    const std::vector<std::string> keys = splitKeys(a.keys);
    for (const std::string& k : keys) {
      const int code = keyFromName(k);
      if (code < 0) throw Error(std::string("viewer action '") + a.name + "': key '" + k + "' has no script name");
      if (std::find(seen.begin(), seen.end(), code) != seen.end())
        throw Error(std::string("viewer action '") + a.name + "': key '" + k + "' belongs to two actions");
      seen.push_back(code);
    }
    if (keys.empty() || (a.kind != ActionKind::Command && !a.options) || !a.apply || (a.options && !a.current))
      throw Error(std::string("viewer action '") + a.name + "': incomplete row");
  }
}

}  // namespace

const std::vector<ViewerAction>& viewerActions() {
  using K = ActionKind;
  using W = Widget;
  static const std::vector<ViewerAction> table = [] {
    std::vector<ViewerAction> t = {
        // name, keys, help; kind, widget, overlay label; options, current, apply (, stepFrom, stepSkip)
        {"frame", "F", "frame the scene", K::Command, W::Button, "frame scene", nullptr, nullptr,
         [](Viewer& v, int) {
           v.leaveFileCamera();
           v.orbit_.frame(v.boundsLo_, v.boundsHi_);
           v.notice("framed the scene");
           v.dirty_ = true;
         }},
        // Triangles filled, as their edges (polygon mode line) or as their corners.
        {"mode", "1 2 3", "triangles / wireframe / points", K::Select, W::Radio, "",
         [](const Viewer&) { return namesOf(std::vector<PrimMode>{PrimMode::Triangles, PrimMode::Wireframe, PrimMode::Points}); },
         [](const Viewer& v) { return int(v.prim_); },
         [](Viewer& v, int i) {
           v.prim_ = PrimMode(i);
           v.rs_.polygon = i == 0 ? PolygonMode::Fill : i == 1 ? PolygonMode::Line : PolygonMode::Point;
         }},
        {"cull", "C", "back-face culling on/off", K::Toggle, W::Checkbox, "back-face culling",
         [](const Viewer&) { return namesOf(std::vector<CullMode>{CullMode::None, CullMode::Back}); },
         [](const Viewer& v) { return v.rs_.cull == CullMode::Back ? 1 : 0; },
         [](Viewer& v, int i) { v.rs_.cull = i == 1 ? CullMode::Back : CullMode::None; }},
        {"raster", "M", "next / previous raster method", K::Cycle, W::Combo, "raster method",
         [](const Viewer&) { return namesOf(rasterMethods()); },
         [](const Viewer& v) { return indexOf(rasterMethods(), v.rs_.raster); },
         [](Viewer& v, int i) { v.rs_.raster = rasterMethods()[size_t(i)]; },
         [](const Viewer& v) { return indexOf(rasterMethods(), v.renderer_.resolveMethod(v.rs_)); }, 1},
        {"shading", "L", "next / previous shading: lambert, blinn-phong, then debug views", K::Cycle, W::Combo,
         "lighting", [](const Viewer&) { return namesOf(shadingModes()); },
         [](const Viewer& v) { return indexOf(shadingModes(), v.rs_.shading); },
         [](Viewer& v, int i) { v.rs_.shading = shadingModes()[size_t(i)]; }},
        {"filter", "T", "texture filter: bilinear, nearest (, trilinear)", K::Cycle, W::Combo, "texture filter",
         [](const Viewer&) { return namesOf(filterModes()); },
         [](const Viewer& v) { return indexOf(filterModes(), v.rs_.filter); },
         [](Viewer& v, int i) { v.rs_.filter = filterModes()[size_t(i)]; }},
        {"transparency", "B", "next / previous transparency method (glTF BLEND surfaces)", K::Cycle, W::Combo,
         "transparency", [](const Viewer&) { return namesOf(transparencyModes()); },
         [](const Viewer& v) { return indexOf(transparencyModes(), v.rs_.transparency); },
         [](Viewer& v, int i) { v.rs_.transparency = transparencyModes()[size_t(i)]; }},
        // The glTF file's cameras (#37): V steps through them after the orbit camera.
        {"camera", "V", "next / previous camera: the orbit camera, then the file's", K::Cycle, W::Combo, "camera",
         [](const Viewer& v) {
           std::vector<std::string> names = {"orbit"};
           names.insert(names.end(), v.fileCameraNames_.begin(), v.fileCameraNames_.end());
           return names;
         },
         [](const Viewer& v) { return v.camera_ + 1; },
         [](Viewer& v, int i) {
           if (i == 0) v.leaveFileCamera();
           else v.camera_ = i - 1;
         }},
        // Image-based light of the glTF shading (docs/gltf-support.md).
        {"environment", "E", "environment light (glTF shading): built-in, none, the --env file", K::Cycle, W::Combo,
         "environment",
         [](const Viewer& v) {
           std::vector<std::string> names;
           for (const std::string& e : v.environments_)
             names.push_back(e.empty() ? "built-in" : e == "none" ? "none" : e.substr(e.find_last_of('/') + 1));
           return names;
         },
         [](const Viewer& v) { return indexOf(v.environments_, v.rs_.environment); },
         [](Viewer& v, int i) { v.rs_.environment = v.environments_[size_t(i)]; }},
        {"bloom", "P", "bloom on/off (post-processing: overlay)", K::Toggle, W::PostCheckbox, "bloom",
         [](const Viewer&) { return std::vector<std::string>{"off", "on"}; },
         [](const Viewer& v) { return v.rs_.post.bloom ? 1 : 0; },
         [](Viewer& v, int i) { v.rs_.post.bloom = i == 1; }},
        // Animation playback (docs/animation.md): rows for every scene, inert without animations.
        {"play", "Space", "play / pause the animation", K::Toggle, W::Checkbox, "play animation",
         [](const Viewer&) { return std::vector<std::string>{"paused", "playing"}; },
         [](const Viewer& v) { return v.playing_ ? 1 : 0; },
         [](Viewer& v, int i) {
           v.playing_ = i == 1 && v.animated_;
           v.lastTick_ = Clock::now();
         }},
        {"loop", "R", "loop the animation on/off", K::Toggle, W::Checkbox, "loop animation",
         [](const Viewer&) { return std::vector<std::string>{"off", "on"}; },
         [](const Viewer& v) { return v.loop_ ? 1 : 0; }, [](Viewer& v, int i) { v.loop_ = i == 1; }},
        {"animation", "A", "next / previous animation (all of them at once first)", K::Cycle, W::Combo, "animation",
         [](const Viewer& v) {
           std::vector<std::string> names = {v.animated_ ? "all" : "none"};
           if (v.animated_)
             for (size_t k = 0; k < v.posed_.rig->animations.size(); ++k)
               names.push_back(std::to_string(k) + (v.posed_.rig->animations[k].name.empty() ? "" : " " + v.posed_.rig->animations[k].name));
           return names;
         },
         [](const Viewer& v) { return v.animation_ + 1; },
         [](Viewer& v, int i) {
           v.animation_ = i - 1;
           v.setAnimationTime(std::clamp(v.animTime_, v.animStart(), v.animEnd()));
         }},
        {"speed", "S", "animation speed: 1x, 2x, 4x, 0.25x, 0.5x", K::Cycle, W::Combo, "speed",
         [](const Viewer&) { return std::vector<std::string>{"1x", "2x", "4x", "0.25x", "0.5x"}; },
         [](const Viewer& v) { return v.speed_ == 1.0 ? 0 : v.speed_ == 2.0 ? 1 : v.speed_ == 4.0 ? 2 : v.speed_ == 0.25 ? 3 : 4; },
         [](Viewer& v, int i) { v.speed_ = std::vector<double>{1.0, 2.0, 4.0, 0.25, 0.5}[size_t(i)]; }},
        // Taken between frames (takeRequestedShots), never inside the overlay's frame.
        {"screenshot", "F12", "screenshot (rast-viewer-NNN.png + -window.png)", K::Command, W::Button, "screenshot",
         nullptr, nullptr, [](Viewer& v, int) { v.shotRequested_ = true; }},
        {"overlay", "O", "overlay on/off", K::Command, W::None, "", nullptr, nullptr,
         [](Viewer& v, int) { v.overlay_ = !v.overlay_; }},
        {"help", "H", "help", K::Command, W::Button, "help", nullptr, nullptr,
         [](Viewer& v, int) {
           v.help_ = !v.help_;
           if (v.help_) v.printHelp();
         }},
        {"quit", "Esc Q", "quit", K::Command, W::None, "", nullptr, nullptr, [](Viewer& v, int) { v.quit_ = true; }},
    };
    checkTable(t);
    return t;
  }();
  return table;
}

const ViewerAction* actionForKey(int key, int* keyIndex) {
  for (const ViewerAction& a : viewerActions()) {
    const std::vector<std::string> keys = splitKeys(a.keys);
    for (size_t i = 0; i < keys.size(); ++i)
      if (keyFromName(keys[i]) == key) {
        if (keyIndex) *keyIndex = int(i);
        return &a;
      }
  }
  return nullptr;
}

int optionForKey(const ViewerAction& a, const Viewer& v, int keyIndex, bool shift) {
  if (a.kind == ActionKind::Command) return 0;
  const int n = int(a.options(v).size());
  switch (a.kind) {
    case ActionKind::Toggle: return a.current(v) == 1 ? 0 : 1;
    case ActionKind::Select: return keyIndex < n ? keyIndex : -1;
    case ActionKind::Cycle: {
      const int skip = std::min(a.stepSkip, n), m = n - skip;
      if (m <= 0) return -1;
      int i = a.stepFrom ? a.stepFrom(v) : a.current(v);
      if (i < skip || i >= n) i = skip;  // not one of the options: step from the first
      const int j = i - skip;
      return skip + (shift ? (j + m - 1) % m : (j + 1) % m);
    }
    case ActionKind::Command: break;
  }
  return 0;
}

std::string actionLabel(const ViewerAction& a, const std::string& text, int keyIndex) {
  const std::vector<std::string> keys = splitKeys(a.keys);
  return text + " (" + (keyIndex < int(keys.size()) ? keys[size_t(keyIndex)] : std::string()) + ")";
}

std::vector<std::pair<std::string, std::string>> controlsTable() {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& c : kMouseControls) out.emplace_back(c[0], c[1]);
  for (const ViewerAction& a : viewerActions()) {
    const std::vector<std::string> keys = splitKeys(a.keys);
    std::string k;
    for (const std::string& name : keys) k += (k.empty() ? "" : " / ") + name;
    if (a.kind == ActionKind::Cycle) k += " / Shift+" + keys[0];
    out.emplace_back(k, a.help);
  }
  return out;
}

}  // namespace rast
