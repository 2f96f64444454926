// Command-line options shared by the rast subcommands (render, bench, and the
// viewer): scene, image size, camera and render settings.
#pragma once

#include "host/scene/camera.h"
#include "host/gltf/gltf_loader.h"
#include "host/scene/animation.h"
#include "host/settings/render_settings.h"

#include <CLI/CLI.hpp>

#include <optional>
#include <string>

namespace rast {

struct SceneOptions {
  std::string scene;  // empty: the embedded default scene
  std::string size = "1920x1080";
  std::string eye, target, up;  // empty: auto-framing
  std::optional<double> fovy;  // empty: the scene's camera's, or 45 degrees for auto-framing
  std::optional<double> znear, zfar;
  std::string fileCamera;           // --camera N|NAME: a camera of the glTF file
  std::optional<double> ortho;      // --ortho H: orthographic, half height H
  // shading empty: pbr for glTF files, lambert for the built-in scenes (applySceneLook)
  std::string cull = "none", shading, filter = "auto", raster = "auto", transparency = "auto";
  int blendK = 8;
  std::vector<std::string> lights;
  std::string background;  // empty: the scene's look, else black
  std::string aa, interp = "perspective";  // aa empty: the scene's look for stills, else none
  bool reference = false;
  int referenceGrid = 16;
  // Post-processing (core/post/): --bloom and --ssao take optional values.
  double exposure = 0.0;
  std::string tonemap = "none";
  std::vector<std::string> bloom, ssao;
  CLI::Option* bloomOpt = nullptr;
  CLI::Option* ssaoOpt = nullptr;
  std::string polygon = "fill";  // points and lines (docs/points-lines.md)
  bool wireframe = false, hiddenLine = false;
  double lineWidth = 1.0, pointSize = 1.0;
  int anisotropy = 1;
  std::string environment;  // --env: "" the built-in neutral one, none, or a .hdr file
  double envIntensity = 1.0, envRotation = 90.0;  // anisotropic filtering's most taps (--filter auto, the glTF shading)
  // Security and resource limits (docs/security.md).
  bool allowExternalFiles = false;
  std::string maxMemory;  // empty: defaultMemoryBudget()
  // Animation (docs/animation.md): the time to pose the scene at, and which
  // animation plays (index or name; empty: all of them).
  std::optional<double> time;
  std::string animation;

  void addTo(CLI::App& app);
  // How the scene file may be read, and the bytes loading and rendering may use.
  LoadOptions loadOptions() const;
  uint64_t memoryBudget() const;
  // Builds settings and camera; throws Error for malformed values.
  RenderSettings settings() const;
  Camera camera(const Scene& scene) const;
  // Fills what the command line left open from the scene's own look
  // (background, key and fill lights; anti-aliasing only for `still` images,
  // where its cost is a fraction of a second, not for interactive or timed frames).
  void applySceneLook(const Scene& scene, RenderSettings& rs, bool still) const;
  bool cameraGiven() const { return !eye.empty() || !target.empty() || !up.empty(); }
  // The pose --time/--animation ask for (at time 0 when only --animation is given);
  // nullopt when neither is given. Throws Error for an unknown animation or a
  // scene without any.
  std::optional<PoseRequest> poseRequest(const Scene& scene) const;
  // Poses the scene as poseRequest() says (nothing when it says nothing).
  void pose(Scene& scene) const;
};

// "scene" when the scene carries its own camera, "auto" when it is framed.
inline const char* cameraOrigin(const Scene& s) { return s.camera ? "scene" : "auto"; }

// Parses the command line into `app`. Returns the exit status when the program
// is to stop here: 0 after --help, 2 after a malformed command line, reported
// as one line "<program>: error: ..." on stderr (CLI11's messages can span
// lines); nothing when it is to go on.
std::optional<int> parseCommandLine(CLI::App& app, const char* program, int argc, char** argv);

}  // namespace rast
