// Command-line options shared by the rast subcommands (render, bench, and the
// viewer): scene, image size, camera and render settings.
#pragma once

#include "../core/camera.h"
#include "../core/gltf_loader.h"
#include "../core/render_settings.h"

#include <CLI/CLI.hpp>

#include <optional>
#include <string>

namespace rast {

struct SceneOptions {
  std::string scene;  // empty: the embedded default scene
  std::string size = "1920x1080";
  std::string eye, target, up;  // empty: auto-framing
  double fovy = 45.0;
  std::optional<double> znear, zfar;
  std::string cull = "none", shading = "lambert", filter = "bilinear", raster = "auto";
  std::vector<std::string> lights;
  std::string background = "0,0,0";
  std::string aa = "none", interp = "perspective";
  bool reference = false;
  int referenceGrid = 16;
  // Security and resource limits (docs/security.md).
  bool allowExternalFiles = false;
  std::string maxMemory;  // empty: defaultMemoryBudget()

  void addTo(CLI::App& app);
  // How the scene file may be read, and the bytes loading and rendering may use.
  LoadOptions loadOptions() const;
  uint64_t memoryBudget() const;
  // Builds settings and camera; throws Error for malformed values.
  RenderSettings settings() const;
  Camera camera(const Scene& scene) const;
  bool cameraGiven() const { return !eye.empty() || !target.empty() || !up.empty(); }
};

// Parses the command line into `app`. Returns the exit status when the program
// is to stop here: 0 after --help, 2 after a malformed command line, reported
// as one line "<program>: error: ..." on stderr (CLI11's messages can span
// lines); nothing when it is to go on.
std::optional<int> parseCommandLine(CLI::App& app, const char* program, int argc, char** argv);

}  // namespace rast
