// rast: render a glTF scene (or a built-in one) with the Kokkos pipeline.
//
//   rast render [SCENE] -o out.png [camera, settings, --aov ...]
//   rast bench  [SCENE] [--frames N] [--json F] [--csv F]
//   rast compare REF.png TEST.png [--ids ref_ids.bin] [--json F]
//   rast info
//
// Every error ends in one line on stderr and exit status 1.
#include "backends/stage_timer.h"
#include "host/image/image_io.h"
#include "pipeline/frame/renderer.h"
#include "scenes/gltf_export.h"
#include "scenes/procedural.h"
#include "app/bench.h"
#include "app/guarded_main.h"
#include "app/compare_cmd.h"
#include "app/ssao_error_cmd.h"
#include "app/cli_options.h"
#include "app/progress.h"

#include <CLI/CLI.hpp>
#include <Kokkos_Core.hpp>

#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>

namespace rast {
namespace {

struct AovRequest {
  std::string depth, primid, normals, ao;
};

AovRequest parseAovs(const std::vector<std::string>& items) {
  AovRequest r;
  for (const std::string& it : items) {
    std::stringstream ss(it);
    std::string kv;
    while (std::getline(ss, kv, ',')) {
      const auto eq = kv.find('=');
      if (eq == std::string::npos || eq + 1 == kv.size())
        throw Error("--aov: expected name=file (depth=d.pfm, primid=ids.bin, normals=n.pfm), got '" + kv + "'");
      const std::string k = kv.substr(0, eq), v = kv.substr(eq + 1);
      if (k == "depth") r.depth = v;
      else if (k == "primid") r.primid = v;
      else if (k == "normals") r.normals = v;
      else if (k == "ao") r.ao = v;
      else throw Error("--aov: unknown output '" + k + "' (expected depth, primid, normals or ao)");
    }
  }
  return r;
}

// AOVs named *.npy are written as NumPy arrays, top row first (host/image/image_io.h).
bool isNpy(const std::string& f) { return f.size() > 4 && (f.compare(f.size() - 4, 4, ".npy") == 0 || f.compare(f.size() - 4, 4, ".NPY") == 0); }

int cmdRender(const SceneOptions& so, const std::string& out, const std::vector<std::string>& aovItems) {
  RenderSettings rs = so.settings();
  const AovRequest aov = parseAovs(aovItems);
  rs.wantDepth = !aov.depth.empty();
  rs.wantPrimId = !aov.primid.empty();
  rs.wantNormals = !aov.normals.empty();
  const auto endsWith = [&out](const char* ext) {
    const std::string e(ext);
    return out.size() >= e.size() && out.compare(out.size() - e.size(), e.size(), e) == 0;
  };
  if (endsWith(".exr") || endsWith(".EXR")) throw Error("-o: OpenEXR output is not built in; write a .pfm for a float image");
  rs.post.floatOutput = endsWith(".pfm") || endsWith(".PFM");  // linear float RGB after the post chain
  if (!aov.ao.empty() && !rs.post.ssao) throw Error("--aov ao=F.pfm needs --ssao");
  // Every output is checked before the (possibly long) render, not after it.
  checkOutputPath(out, "-o");
  for (const std::string* a : {&aov.depth, &aov.primid, &aov.normals, &aov.ao})
    if (!a->empty()) checkOutputPath(*a, "--aov");
  const Scene scene = loadSceneArg(so.scene, so.loadOptions());
  const Camera cam = so.camera(scene);
  so.applySceneLook(scene, rs, /*still=*/true);
  if (!so.cameraGiven()) std::printf("rast: camera (%s) %s\n", cameraOrigin(scene), cam.flags().c_str());
  Renderer r(scene, so.memoryBudget());
  Progress progress(rs.reference ? "rast: reference passes" : "rast: supersampling passes");
  if (progress.active()) r.onPass = [&progress](int done, int total) { progress.update(done, total); };
  const FrameStats st = r.render(cam, rs);
  // AOVs first, the colour image last: a failed write leaves no partial set of
  // outputs behind (the files already written are removed).
  std::vector<std::string> written;
  try {
    if (rs.wantDepth) {
      if (isNpy(aov.depth)) writeNpy(aov.depth, rs.width, rs.height, 1, "<f4", r.depthBottomUp().data());
      else writePfm(aov.depth, rs.width, rs.height, 1, r.depthBottomUp().data());
      written.push_back(aov.depth);
    }
    if (rs.wantPrimId) {
      const auto ids = r.primIdsBottomUp();
      if (isNpy(aov.primid)) {
        writeNpy(aov.primid, rs.width, rs.height, 1, "<u4", ids.data());
      } else if (aov.primid.size() > 4 && aov.primid.substr(aov.primid.size() - 4) == ".pfm") {
        std::vector<float> f(ids.begin(), ids.end());
        writePfm(aov.primid, rs.width, rs.height, 1, f.data());
      } else {
        writeIdsBin(aov.primid, rs.width, rs.height, ids);
      }
      written.push_back(aov.primid);
    }
    if (rs.wantNormals) {
      const auto n = r.normalsBottomUp();
      if (isNpy(aov.normals)) writeNpy(aov.normals, rs.width, rs.height, 3, "<f4", &n[0].x);
      else writePfm(aov.normals, rs.width, rs.height, 3, &n[0].x);
      written.push_back(aov.normals);
    }
    if (!aov.ao.empty()) {
      if (isNpy(aov.ao)) writeNpy(aov.ao, rs.width, rs.height, 1, "<f4", r.aoBottomUp().data());
      else writePfm(aov.ao, rs.width, rs.height, 1, r.aoBottomUp().data());
      written.push_back(aov.ao);
    }
    if (rs.post.floatOutput) {
      const std::vector<float4> film = r.filmBottomUp();
      std::vector<float> rgb(film.size() * 3);
      for (size_t i = 0; i < film.size(); ++i) {
        rgb[3 * i] = film[i].x;
        rgb[3 * i + 1] = film[i].y;
        rgb[3 * i + 2] = film[i].z;
      }
      writePfm(out, rs.width, rs.height, 3, rgb.data());
    } else {
      writePng(out, rs.width, rs.height, r.colorTopDown());
    }
  } catch (...) {
    for (const std::string& f : written) std::remove(f.c_str());
    throw;
  }
  std::printf("rast: wrote %s (%dx%d, %u triangles, %u rasterised, method %s, aa %s)\n", out.c_str(), rs.width,
              rs.height, st.trianglesIn, st.rasterTris, toString(st.method), aaName(rs).c_str());
  return 0;
}

int cmdInfo() {
  std::cout << deviceDescription();
  const char* bind = std::getenv("OMP_PROC_BIND");
  std::printf("OMP_PROC_BIND: %s (%s)\n", bind ? bind : "unset", openMPBindingIsDefault() ? "default" : "yours");
  std::cout << "raster methods:";
  for (RasterMethod m : allRasterMethods()) std::cout << " " << toString(m);
  std::cout << "\nbuiltin scenes:\n";
  for (const BuiltinSceneInfo& b : builtinScenes()) {
    const std::string name = "builtin:" + b.name;
    std::printf("  %-20s %s\n", name.c_str(), b.description.c_str());
  }
  return 0;
}

std::string versionText() {
  char b[160];
  std::snprintf(b, sizeof b, "rast %s (Kokkos %d.%d.%d, %s backend)", RAST_VERSION, KOKKOS_VERSION / 10000,
                KOKKOS_VERSION / 100 % 100, KOKKOS_VERSION % 100, Exec::name());
  return b;
}

int run(int argc, char** argv) {
  CLI::App app{"rast: a portable Kokkos rasterizer for glTF 2.0 scenes", "rast"};
  app.require_subcommand(0, 1);
  app.set_version_flag("--version", versionText());
  // Kokkos' own flags reach Kokkos (app/guarded_main); here they get one line.
  app.footer("Kokkos options (--kokkos-threads=N, --kokkos-device-id=N, ...): rast --kokkos-help\n"
             "Help on a command: rast help COMMAND, or rast COMMAND --help");

  SceneOptions renderOpts;
  std::string out = "out.png";
  std::vector<std::string> aovs;
  CLI::App* render = app.add_subcommand("render", "render one frame to a PNG");
  renderOpts.addTo(*render);
  render->add_option("-o,--output", out, "colour image: .png (sRGB8) or .pfm (linear float RGB, after the post chain)")
      ->capture_default_str();
  render->add_option("--aov", aovs, "extra outputs: depth=F.pfm,primid=F.bin|F.pfm,normals=F.pfm,ao=F.pfm (with --ssao); any as F.npy (numpy, top row first)");

  SceneOptions benchOpts;
  BenchOptions bo;
  CLI::App* bench = app.add_subcommand("bench", "time frames: median per stage over many frames");
  benchOpts.addTo(*bench);
  bo.addTo(*bench);

  std::string exportScene, exportOut;
  CLI::App* exportCmd = app.add_subcommand("export", "write a scene (e.g. a builtin: stress scene) as .glb");
  exportCmd->add_option("scene", exportScene, "scene to export (builtin:<name> or a glTF file)")->required();
  exportCmd->add_option("-o,--output", exportOut, "output .glb")->required();

  // Image quality of TEST against REF (app/compare_cmd.h).
  CompareOptions compareOpts;
  CLI::App* compare = app.add_subcommand("compare", "image error metrics of TEST against the reference REF");
  compareOpts.addTo(*compare);

  // SSAO against a ray-traced reference, per sample count (app/ssao_error_cmd.h).
  SceneOptions ssaoOpts;
  SsaoErrorOptions seo;
  CLI::App* ssaoErr = app.add_subcommand("ssao-error", "SSAO error against ray-traced AO and its cost, per sample count");
  ssaoOpts.addTo(*ssaoErr);
  seo.addTo(*ssaoErr);

  CLI::App* info = app.add_subcommand("info", "backend, Kokkos version, threads / device, builtin scenes");

  std::string helpTopic;
  CLI::App* help = app.add_subcommand("help", "show this help, or a command's: rast help render");
  help->add_option("command", helpTopic, "render, bench, compare, export, ssao-error or info");

  if (const std::optional<int> status = parseCommandLine(app, "rast", argc, argv)) return *status;
  if (help->parsed() || app.get_subcommands().empty()) {
    if (helpTopic.empty()) {
      std::cout << app.help();
      return 0;
    }
    for (CLI::App* sub : {render, bench, exportCmd, compare, ssaoErr, info})
      if (sub->get_name() == helpTopic) {
        std::cout << sub->help();
        return 0;
      }
    throw Error("help: no command '" + helpTopic + "' (commands: render, bench, compare, export, ssao-error, info)");
  }
  if (render->parsed()) return cmdRender(renderOpts, out, aovs);
  if (bench->parsed()) return runBench(benchOpts, bo);
  if (compare->parsed()) return runCompare(compareOpts);
  if (ssaoErr->parsed()) return runSsaoError(ssaoOpts, seo);
  if (exportCmd->parsed()) {
    checkOutputPath(exportOut, "-o");
    const Scene s = loadSceneArg(exportScene);
    exportGlb(s, exportOut);
    std::printf("rast: wrote %s (%u triangles); view it with %s\n", exportOut.c_str(), s.triangleCount(),
                defaultCamera(s).flags().c_str());
    return 0;
  }
  return cmdInfo();
}

}  // namespace
}  // namespace rast

int main(int argc, char** argv) { return rast::guardedMain("rast", argc, argv, rast::run); }
