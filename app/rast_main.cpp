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
#include "host/image/safe_output.h"
#include "pipeline/frame/renderer.h"
#include "scenes/gltf_export.h"
#include "scenes/procedural.h"
#include "app/bench.h"
#include "app/guarded_main.h"
#include "app/compare_cmd.h"
#include "app/ssao_error_cmd.h"
#include "app/cli_options.h"
#include "app/progress.h"
#include "app/scene_info.h"
#include "app/views.h"
#include "app/distribute.h"
#include "host/distributed/ranks.h"
#include "host/scene/camera_list.h"
#include "app/sequence_cmd.h"
#ifdef RAST_HAVE_OPENEXR
#include "app/exr_output.h"
#endif

#include <CLI/CLI.hpp>
#include <Kokkos_Core.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <memory>
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
        throw Error("--aov: expected name=file (depth=d.pfm, primid=ids.bin, normals=n.pfm), got '" + printable(kv) + "'");
      const std::string k = kv.substr(0, eq), v = kv.substr(eq + 1);
      if (k == "depth") r.depth = v;
      else if (k == "primid") r.primid = v;
      else if (k == "normals") r.normals = v;
      else if (k == "ao") r.ao = v;
      else throw Error("--aov: unknown output '" + printable(k) + "' (expected depth, primid, normals or ao)");
    }
  }
  return r;
}

// AOVs named *.npy are written as NumPy arrays, top row first (host/image/image_io.h).
bool isNpy(const std::string& f) { return f.size() > 4 && (f.compare(f.size() - 4, 4, ".npy") == 0 || f.compare(f.size() - 4, 4, ".NPY") == 0); }

std::string versionText() {
  char b[160];
  std::snprintf(b, sizeof b, "rast %s (Kokkos %d.%d.%d, %s backend)", RAST_VERSION, KOKKOS_VERSION / 10000,
                KOKKOS_VERSION / 100 % 100, KOKKOS_VERSION % 100, Exec::name());
  return b;
}

// Writes the last frame's outputs: every file goes to a temporary file beside
// its path first; only when all are complete are they renamed into place, so a
// failed write leaves every file that was there as it was
// (host/image/safe_output.h). Any AOV may be a .npy (numpy, top row first)
// instead of its PFM / ids file.
void writeOutputs(const Renderer& r, const RenderSettings& rs, const AovRequest& aov, const std::string& out) {
  std::vector<std::unique_ptr<AtomicFile>> files;
  const auto open = [&files](const std::string& path) -> AtomicFile& {
    files.push_back(std::make_unique<AtomicFile>(path));
    return *files.back();
  };
#ifdef RAST_HAVE_OPENEXR
  // Outputs named *.exr are channels of one file per name (-o and --aov may
  // share it): R G B A (linear, after the post chain), Z, id (UINT, triangle
  // index + 1, 0 where empty), N.X N.Y N.Z, AO.
  std::vector<std::pair<std::string, ExrImage>> exrs;
  const auto exr = [&](const std::string& path) -> ExrImage* {
    if (!isExrPath(path)) return nullptr;
    for (auto& e : exrs)
      if (e.first == path) return &e.second;
    exrs.emplace_back(path, ExrImage(rs.width, rs.height));
    return &exrs.back().second;
  };
#else
  struct NoExr {  // never returned: .exr names are refused before the render
    void addFloat(const std::string&, const float*, int = 1, int = 0) {}
    void addUint(const std::string&, const uint32_t*) {}
  };
  const auto exr = [](const std::string&) -> NoExr* { return nullptr; };
#endif
  if (rs.wantDepth) {
    const auto d = r.depthBottomUp();
    if (auto* e = exr(aov.depth)) e->addFloat("Z", d.data());
    else if (isNpy(aov.depth)) writeNpy(open(aov.depth), rs.width, rs.height, 1, "<f4", d.data());
    else writePfm(open(aov.depth), rs.width, rs.height, 1, d.data());
  }
  if (rs.wantPrimId) {
    const auto ids = r.primIdsBottomUp();
    if (auto* e = exr(aov.primid)) {
      e->addUint("id", ids.data());
    } else if (isNpy(aov.primid)) {
      writeNpy(open(aov.primid), rs.width, rs.height, 1, "<u4", ids.data());
    } else if (aov.primid.size() > 4 && aov.primid.substr(aov.primid.size() - 4) == ".pfm") {
      std::vector<float> f(ids.begin(), ids.end());
      writePfm(open(aov.primid), rs.width, rs.height, 1, f.data());
    } else {
      writeIdsBin(open(aov.primid), rs.width, rs.height, ids);
    }
  }
  if (rs.wantNormals) {
    const auto n = r.normalsBottomUp();
    if (auto* e = exr(aov.normals)) {
      e->addFloat("N.X", &n[0].x, 3, 0);
      e->addFloat("N.Y", &n[0].x, 3, 1);
      e->addFloat("N.Z", &n[0].x, 3, 2);
    } else if (isNpy(aov.normals)) {
      writeNpy(open(aov.normals), rs.width, rs.height, 3, "<f4", &n[0].x);
    } else {
      writePfm(open(aov.normals), rs.width, rs.height, 3, &n[0].x);
    }
  }
  if (!aov.ao.empty()) {
    const auto ao = r.aoBottomUp();
    if (auto* e = exr(aov.ao)) e->addFloat("AO", ao.data());
    else if (isNpy(aov.ao)) writeNpy(open(aov.ao), rs.width, rs.height, 1, "<f4", ao.data());
    else writePfm(open(aov.ao), rs.width, rs.height, 1, ao.data());
  }
  if (rs.post.floatOutput) {
    const std::vector<float4> film = r.filmBottomUp();
    if (auto* e = exr(out)) {
      for (int k = 0; k < 3; ++k) e->addFloat(std::string(1, "RGB"[k]), &film[0].x, 4, k);
      // Coverage accumulated in float can end a rounding step above 1;
      // compositors take alpha as a fraction.
      std::vector<float> alpha(film.size());
      for (size_t i = 0; i < film.size(); ++i) alpha[i] = std::min(1.0f, std::max(0.0f, film[i].w));
      e->addFloat("A", alpha.data());
    } else {
      // RGB of the RGBA film, a row at a time (no second copy of the frame).
      AtomicFile& f = open(out);
      f.write("PF\n" + std::to_string(rs.width) + " " + std::to_string(rs.height) + "\n-1.0\n");
      std::vector<float> row(size_t(rs.width) * 3);
      for (size_t y = 0; y < size_t(rs.height); ++y) {
        for (size_t x = 0; x < size_t(rs.width); ++x) {
          const float4& p = film[y * size_t(rs.width) + x];
          row[3 * x] = p.x;
          row[3 * x + 1] = p.y;
          row[3 * x + 2] = p.z;
        }
        f.write(row.data(), row.size() * sizeof(float));
      }
    }
  } else {
    writePng(open(out), rs.width, rs.height, r.colorTopDown(), rs.background.w < 1.0f);
  }
#ifdef RAST_HAVE_OPENEXR
  for (const auto& e : exrs) e.second.write(open(e.first));
#endif
  for (const auto& f : files) f->commit();
}

// The outputs of view `v` (many views: each name's %d replaced by v).
AovRequest viewAovs(const AovRequest& a, bool many, size_t v) {
  if (!many) return a;
  AovRequest r;
  for (auto [src, dst] : {std::pair{&a.depth, &r.depth}, std::pair{&a.primid, &r.primid},
                          std::pair{&a.normals, &r.normals}, std::pair{&a.ao, &r.ao}})
    if (!src->empty()) *dst = viewPath(*src, v, "--aov");
  return r;
}

int cmdRender(const SceneOptions& so, const std::string& out, const std::vector<std::string>& aovItems,
              const std::string& cameraFile, bool distribute) {
  // Under --distribute (docs/distributed.md) a list of views is spread over
  // the ranks, each rendering and writing its own; one view is cut by
  // geometry (sort-last): each rank draws its share, rank 0 writes the frame.
  // Every step that may fail is taken together: one rank's failure ends all.
  if (distribute) startDistributed();
  const bool many = !cameraFile.empty(), sortLast = distribute && !many;
  RenderSettings rs;
  AovRequest aov;
  together(distribute, [&] {
    rs = so.settings();
    aov = parseAovs(aovItems);
    rs.wantDepth = !aov.depth.empty();
    rs.wantPrimId = !aov.primid.empty();
    rs.wantNormals = !aov.normals.empty();
    const auto endsWith = [&out](const char* ext) {
      const std::string e(ext);
      return out.size() >= e.size() && out.compare(out.size() - e.size(), e.size(), e) == 0;
    };
#ifdef RAST_HAVE_OPENEXR
    rs.post.floatOutput = endsWith(".pfm") || endsWith(".PFM") || isExrPath(out);  // linear float RGB after the post chain
#else
    for (const std::string* f : {&out, &aov.depth, &aov.primid, &aov.normals, &aov.ao})
      if (f->size() > 4 && (f->compare(f->size() - 4, 4, ".exr") == 0 || f->compare(f->size() - 4, 4, ".EXR") == 0))
        throw Error("'" + printable(*f) + "': OpenEXR output is not built in (libopenexr-dev, RAST_OPENEXR); "
                    "write a .pfm or .npy instead");
    rs.post.floatOutput = endsWith(".pfm") || endsWith(".PFM");  // linear float RGB after the post chain
#endif
    if (!aov.ao.empty() && !rs.post.ssao) throw Error("--aov ao=F.pfm needs --ssao");
    if (sortLast && rs.shading == ShadingMode::Depth)
      throw Error("--distribute: --shading depth scales by the depth range of the whole frame, which no rank sees; "
                  "use --aov depth=F instead");
  });
  // Every output is checked before the (possibly long) render, not after it:
  // writable, and neither an input of the run nor another of its outputs. With
  // many views every name is checked once the views are known.
  const auto checkOutputs = [&](size_t views, const Scene* scene) {
    OutputSet outputs;
    for (size_t v = 0; v < views; ++v) {
      const std::string o = many ? viewPath(out, v, "-o") : out;
      const AovRequest a = viewAovs(aov, many, v);
      checkOutputPath(o, "-o");
      outputs.addOutput(o, "-o");
      // Outputs named *.exr may share a file (its channels); each is checked once.
      std::vector<std::string> exrNames;
#ifdef RAST_HAVE_OPENEXR
      if (isExrPath(o)) exrNames.push_back(o);
#endif
      for (const auto& [file, what] : {std::pair{&a.depth, "--aov depth"}, std::pair{&a.primid, "--aov primid"},
                                       std::pair{&a.normals, "--aov normals"}, std::pair{&a.ao, "--aov ao"}})
        if (!file->empty()) {
#ifdef RAST_HAVE_OPENEXR
          if (isExrPath(*file)) {
            if (std::find(exrNames.begin(), exrNames.end(), *file) != exrNames.end()) continue;
            exrNames.push_back(*file);
          }
#endif
          checkOutputPath(*file, "--aov");
          outputs.addOutput(*file, what);
        }
    }
    if (!so.scene.empty() && so.scene.rfind("builtin:", 0) != 0) outputs.addInput(so.scene, "the scene file");
    if (many) outputs.addInput(cameraFile, "the --cameras file");
    if (scene)
      for (const std::string& f : scene->sourceFiles) outputs.addInput(f, "a file the scene reads");
    outputs.check();
  };
  const bool writer = !sortLast || Ranks::rank() == 0;
  together(distribute, [&] { checkOutputs(1, nullptr); });
  RunScene loaded;
  std::vector<Camera> cams;
  together(distribute, [&] {
    loaded = loadRunScene(so, sortLast);
    cams = many ? loadCameraList(cameraFile, loaded.camera, rs.width, rs.height) : std::vector<Camera>{loaded.camera};
    if (writer) checkOutputs(cams.size(), &loaded.scene);
  });
  const Scene& scene = loaded.scene;
  const Camera& cam = loaded.camera;
  so.applySceneLook(scene, rs, /*still=*/true);
  if (!so.cameraGiven() && !many)
    std::printf("rast: camera (%s) %s\n", so.fileCamera.empty() ? cameraOrigin(scene) : ("file camera " + so.fileCamera).c_str(),
                cam.flags().c_str());
  std::unique_ptr<Renderer> r;
  together(distribute, [&] { r = std::make_unique<Renderer>(scene, so.memoryBudget()); });
  if (loaded.split) r->setSplit(loaded.split.get());
  Progress progress(rs.reference ? "rast: reference passes" : "rast: supersampling passes");
  if (progress.active()) r->onPass = [&progress](int done, int total) { progress.update(done, total); };
  // One renderer for every view: its buffers are reused from view to view.
  // Spread over ranks, view v is rank v mod N's.
  const size_t step = distribute && many ? size_t(Ranks::size()) : 1, first = distribute && many ? size_t(Ranks::rank()) : 0;
  for (size_t v = first; v < cams.size(); v += step) {
    FrameStats st;
    const std::string o = many ? viewPath(out, v, "-o") : out;
    if (many && distribute) {
      st = r->render(cams[v], rs);  // this rank's alone: its failure is its own
      writeOutputs(*r, rs, viewAovs(aov, many, v), o);
    } else {
      frames(sortLast, [&] { st = r->render(cams[v], rs); });
      together(sortLast, [&] {
        if (writer) writeOutputs(*r, rs, viewAovs(aov, many, v), o);
      });
    }
    if (sortLast) st.trianglesIn = uint32_t(loaded.trianglesAll);
    if (st.blendFallback)
      std::fprintf(stderr, "rast: note: the tile lists of exact transparency would exceed the memory budget: drawn "
                           "with --transparency kbuffer (k %d) instead\n", rs.blendK);
    std::printf("rast: wrote %s (%dx%d, %u triangles, %u rasterised%s, method %s, aa %s)\n", printable(o).c_str(), rs.width,
                rs.height, st.trianglesIn, st.rasterTris, sortLast ? " on rank 0" : "", toString(st.method),
                aaName(rs).c_str());
  }
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
  render->add_option("-o,--output", out, "colour image: .png (sRGB8), .pfm (linear float RGB, after the post chain) or .exr (linear float RGBA, and the AOVs named with the same file)")
      ->capture_default_str();
  std::string cameraFile;
  render->add_option("--cameras", cameraFile, "many views: a JSON list of cameras ({\"eye\": [x,y,z], \"target\", \"up\", "
                     "\"fovy\", \"near\", \"far\"}) or a NeRF transforms.json; outputs named with a view field, "
                     "-o out_%04d.png (docs/distributed.md)");
  bool distribute = false;
  render->add_flag("--distribute", distribute, "under mpirun/srun: one view cut by geometry over the ranks (sort-last), "
                   "or the --cameras views spread over them (docs/distributed.md)");
  SequenceOptions seq;
  render->add_option("--frames", seq.frames, "render the animation from START to END seconds at FPS frames a second, "
                                              "START:END:FPS, to -o out_%04d.png or a video (.mp4, .webm, .gif through ffmpeg)");
  render->add_option("--turntable", seq.turntable, "orbit the camera around its target in N frames (with --frames: N frames an orbit)");
  render->add_option("--aov", aovs, "extra outputs: depth=F.pfm,primid=F.bin|F.pfm,normals=F.pfm,ao=F.pfm (with --ssao); any as F.npy (numpy, top row first) or F.exr (channels Z, id, N.X/N.Y/N.Z, AO; several may share one file, -o's too)");

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

  CLI::App* info = app.add_subcommand("info", "backend, Kokkos version, threads / device, builtin scenes; "
                                              "with SCENE: its cameras, lights, materials and extensions");
  SceneOptions infoOpts;
  info->add_option("scene", infoOpts.scene, "glTF 2.0 file (.gltf/.glb) or builtin:<name> to describe");
  info->add_flag("--allow-external-files", infoOpts.allowExternalFiles,
                 "let the file read buffers and images outside its folder");
  info->add_option("--max-memory", infoOpts.maxMemory, "memory budget for loading (e.g. 4G)");

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
  if (render->parsed() && seq.wanted()) {
    if (!aovs.empty()) throw Error("--aov is for single images, not with --frames or --turntable");
    if (!cameraFile.empty() || distribute) throw Error("--frames/--turntable cannot be combined with --cameras or --distribute");
    return runSequence(renderOpts, seq, out);
  }
  if (render->parsed()) return cmdRender(renderOpts, out, aovs, cameraFile, distribute);
  if (bench->parsed()) return runBench(benchOpts, bo);
  if (compare->parsed()) return runCompare(compareOpts);
  if (ssaoErr->parsed()) return runSsaoError(ssaoOpts, seo);
  if (exportCmd->parsed()) {
    checkOutputPath(exportOut, "-o");
    OutputSet outputs;
    outputs.addOutput(exportOut, "-o");
    if (exportScene.rfind("builtin:", 0) != 0) outputs.addInput(exportScene, "the scene file");
    outputs.check();
    const Scene s = loadSceneArg(exportScene);
    for (const std::string& f : s.sourceFiles) outputs.addInput(f, "a file the scene reads");
    outputs.check();
    exportGlb(s, exportOut);
    std::printf("rast: wrote %s (%u triangles); view it with %s\n", printable(exportOut).c_str(), s.triangleCount(),
                defaultCamera(s).flags().c_str());
    return 0;
  }
  if (!infoOpts.scene.empty()) {
    printSceneInfo(loadSceneArg(infoOpts.scene, infoOpts.loadOptions()), infoOpts.scene);
    return 0;
  }
  return cmdInfo();
}

}  // namespace
}  // namespace rast

// MPI starts before Kokkos when --distribute is given, so that each rank's
// device follows its place on the node (one rank per GPU); the other ranks'
// standard output is silent (rank 0 speaks for the run).
int main(int argc, char** argv) {
  bool distribute = false, deviceGiven = false;
  for (int i = 1; i < argc; ++i) {
    distribute |= std::strcmp(argv[i], "--distribute") == 0;
    deviceGiven |= std::strncmp(argv[i], "--kokkos-device", 15) == 0 || std::strncmp(argv[i], "--kokkos-num-devices", 20) == 0 ||
                   std::strncmp(argv[i], "--kokkos-ndevices", 17) == 0;
  }
  rast::Ranks::start(&argc, &argv, distribute);
  std::vector<char*> args(argv, argv + argc);
  std::string device = "--kokkos-device-id=" + std::to_string(rast::Ranks::localRank());
  if (distribute && rast::kOnDevice && !deviceGiven) args.push_back(&device[0]);
  if (distribute && rast::Ranks::rank() != 0 && !std::freopen("/dev/null", "w", stdout)) return 1;
  const int rc = rast::guardedMain("rast", int(args.size()), args.data(), rast::run);
  rast::Ranks::finish();
  return rc;
}
