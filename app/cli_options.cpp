#include "app/cli_options.h"

#include "host/scene/memory_budget.h"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace rast {
namespace {

std::vector<double> parseNumbers(const std::string& s, const char* what, size_t minN, size_t maxN) {
  std::vector<double> v;
  if (!parseFiniteList(s, v))
    throw Error(std::string("--") + what + ": '" + s + "' is not a list of finite numbers");
  if (v.size() < minN || v.size() > maxN)
    throw Error(std::string("--") + what + ": expected " + std::to_string(minN) +
                (maxN > minN ? " to " + std::to_string(maxN) : std::string()) + " comma-separated numbers, got '" + s + "'");
  return v;
}

glm::dvec3 parseVec3(const std::string& s, const char* what) {
  const auto v = parseNumbers(s, what, 3, 3);
  return {v[0], v[1], v[2]};
}

}  // namespace

void SceneOptions::addTo(CLI::App& app) {
  app.add_option("scene", scene, "glTF 2.0 file (.gltf/.glb) or builtin:<name>; default: the embedded scene");
  app.add_option("--size", size, "image size WxH")->capture_default_str();
  app.add_option("--eye", eye, "camera position x,y,z (default: frame the scene)");
  app.add_option("--target", target, "point looked at x,y,z");
  app.add_option("--up", up, "up vector x,y,z");
  app.add_option("--fovy", fovy, "vertical field of view, degrees (default: the scene's camera's, else 45)");
  app.add_option("--near", znear, "near plane distance");
  app.add_option("--far", zfar, "far plane distance");
  app.add_option("--camera", fileCamera, "view through a camera of the glTF file: its index N (from 0) or its name "
                                         "(`rast info SCENE` lists them)");
  app.add_option("--ortho", ortho, "orthographic projection with this half height (world units) instead of --fovy");
  app.add_option("--cull", cull, "back-face culling: none|back")->capture_default_str();
  app.add_option("--shading", shading,
                 "pbr|lambert|blinn-phong|normals|depth|uv|miplevel, or one input of the glTF shading: "
                 "basecolor|metalrough|occlusion|emissive|shading-normals (default: pbr, the glTF "
                 "material model and the file's lights, for glTF files; lambert for builtin scenes)");
  app.add_option("--filter", filter, "texture filter: auto|nearest|bilinear|trilinear (auto: the glTF samplers' filters under pbr, bilinear otherwise)")->capture_default_str();
  app.add_option("--aa", aa, "anti-aliasing: none|ssaa2|ssaa4|msaa2|msaa4|msaa8 (default: none; msaa4 for the default scene's image)");
  app.add_option("--anisotropy", anisotropy,
                 "anisotropic filtering's most taps, 1..16, where a glTF sampler filters between mipmap levels "
                 "(--filter auto, the glTF shading; 1: the sampler's own filter, 16: as the Khronos Sample "
                 "Renderer asks WebGL for)")
      ->capture_default_str()
      ->check(CLI::Range(1, 16));
  app.add_option("--env", environment,
                 "image-based light of the glTF shading: a Radiance .hdr panorama, or none (default: the built-in "
                 "neutral environment)");
  app.add_option("--env-intensity", envIntensity, "environment intensity")->capture_default_str();
  app.add_option("--env-rotation", envRotation, "environment rotation about +Y, degrees")->capture_default_str();
  app.add_flag("--reference", reference, "ground truth: 16x16 stratified samples per pixel (slow on purpose)");
  app.add_option("--reference-grid", referenceGrid, "reference samples per pixel side")->capture_default_str();
  app.add_option("--interp", interp, "attribute interpolation: perspective|affine (affine only to compare)")
      ->capture_default_str();
  app.add_option("--raster", raster, "raster method: auto|naive|visbuffer|binned")->capture_default_str();
  app.add_option("--transparency", transparency,
                 "glTF BLEND surfaces: auto|exact|kbuffer|weighted|sorted (docs/transparency.md)")
      ->capture_default_str();
  app.add_option("--blend-k", blendK, "kbuffer: fragments kept exact per sample, 1..64")->capture_default_str();
  app.add_option("--light", lights, "directional light towards x,y,z[,intensity] (repeatable; default: a headlight)");
  app.add_option("--background", background, "background colour r,g,b[,a] in [0,1], linear, or `transparent`; alpha < 1 writes RGBA PNGs (default: black, or the builtin scene's)");
  app.add_option("--exposure", exposure, "exposure in EV (colour times 2^EV) before tone mapping")->capture_default_str();
  app.add_option("--tonemap", tonemap, "tone mapping: none|reinhard|aces|pbr-neutral")->capture_default_str();
  bloomOpt = app.add_option("--bloom", bloom,
                            "bloom, optionally --bloom=THRESHOLD[,STRENGTH[,RADIUS_PX]] (default 1,0.5,16)")
                 ->expected(0, 1);
  ssaoOpt = app.add_option("--ssao", ssao, "ambient occlusion, optionally --ssao=RADIUS[,SAMPLES] (default 0 = auto,8)")
                ->expected(0, 1);
  app.add_option("--polygon", polygon, "triangles drawn as: fill|line|point")->capture_default_str();
  app.add_flag("--wireframe", wireframe, "draw triangle edges over the shaded fill");
  app.add_flag("--hidden-line", hiddenLine, "wireframe whose edges are depth-tested against the fill (implies --wireframe)");
  app.add_option("--line-width", lineWidth, "line width in pixels, 1..64")->capture_default_str();
  app.add_option("--point-size", pointSize, "point size in pixels, 1..64")->capture_default_str();
  app.add_flag("--allow-external-files", allowExternalFiles,
               "let a glTF file read buffers and images outside its own folder (absolute paths, ..)");
  app.add_option("--time", time, "pose the scene's animations at this time in seconds (docs/animation.md)");
  app.add_option("--animation", animation, "which animation plays: its index N (from 0) or its name (default: all)");
  app.add_option("--max-memory", maxMemory,
                 "memory that loading and rendering may use, e.g. 512M or 4G (default: half of physical memory, " +
                     formatBytes(defaultMemoryBudget()) + " here)");
}

uint64_t SceneOptions::memoryBudget() const {
  return maxMemory.empty() ? defaultMemoryBudget() : parseMemorySize(maxMemory);
}

LoadOptions SceneOptions::loadOptions() const {
  LoadOptions o;
  o.allowExternalFiles = allowExternalFiles;
  o.maxMemory = memoryBudget();
  return o;
}

std::optional<PoseRequest> SceneOptions::poseRequest(const Scene& scene) const {
  if (!time && animation.empty()) return std::nullopt;
  if (time && !std::isfinite(*time)) throw Error("--time must be a finite number of seconds");
  if (!scene.rig || scene.rig->animations.empty()) {
    if (!animation.empty()) throw Error("--animation: the scene has no animations");
    return std::nullopt;  // --time on a scene that does not move: its one pose
  }
  PoseRequest r;
  r.time = time.value_or(0.0);
  if (!animation.empty()) r.animation = findAnimation(*scene.rig, animation);
  return r;
}

void SceneOptions::pose(Scene& scene) const {
  if (const auto r = poseRequest(scene)) poseScene(scene, *r);
}

RenderSettings SceneOptions::settings() const {
  RenderSettings rs;
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(size.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X'))
    throw Error("--size: expected WxH, got '" + size + "'");
  rs.width = w;
  rs.height = h;
  if (w < 1 || h < 1 || w > 16384 || h > 16384)
    throw Error("--size: " + size + " is outside 1..16384 per side");
  rs.cull = parseCull(cull);
  rs.shading = shading.empty() ? ShadingMode::Lambert : parseShading(shading);
  rs.filter = parseFilter(filter);
  rs.anisotropy = anisotropy;
  if (!(std::isfinite(envIntensity) && envIntensity >= 0.0)) throw Error("--env-intensity must be a finite number >= 0");
  if (!std::isfinite(envRotation)) throw Error("--env-rotation must be finite");
  rs.environment = environment;
  rs.envIntensity = float(envIntensity);
  rs.envRotation = float(envRotation);
  rs.raster = parseRaster(raster);
  rs.transparency = parseTransparency(transparency);
  if (blendK < 1 || blendK > 64) throw Error("--blend-k must be 1..64");
  rs.blendK = blendK;
  parseAA(aa.empty() ? "none" : aa, rs);
  rs.reference = reference;
  rs.referenceGrid = referenceGrid;
  if (referenceGrid < 1 || referenceGrid > 64) throw Error("--reference-grid must be 1..64");
  if (interp != "perspective" && interp != "affine") throw Error("--interp: expected perspective or affine, got '" + interp + "'");
  rs.perspectiveCorrect = interp == "perspective";
  for (const std::string& l : lights) {
    const auto v = parseNumbers(l, "light", 3, 4);
    DirectionalLight d;
    d.direction = float3{float(v[0]), float(v[1]), float(v[2])};
    if (!(dot(d.direction, d.direction) > 0.0f)) throw Error("--light: direction must not be zero");
    d.intensity = v.size() == 4 ? float(v[3]) : 0.85f;
    rs.lights.push_back(d);
  }
  rs.polygon = parsePolygon(polygon);
  rs.wireframe = hiddenLine ? Wireframe::Hidden : wireframe ? Wireframe::On : Wireframe::Off;
  if (!(lineWidth >= 1.0 && lineWidth <= 64.0)) throw Error("--line-width must be 1..64 pixels");
  if (!(pointSize >= 1.0 && pointSize <= 64.0)) throw Error("--point-size must be 1..64 pixels");
  rs.lineWidth = float(lineWidth);
  rs.pointSize = float(pointSize);
  if (background == "transparent") {
    rs.background = float4{0.0f, 0.0f, 0.0f, 0.0f};  // RGBA PNGs (docs/transparency.md)
  } else if (!background.empty()) {
    const auto bg = parseNumbers(background, "background", 3, 4);
    if (bg.size() == 4 && !(bg[3] >= 0.0 && bg[3] <= 1.0)) throw Error("--background: alpha must be in [0,1]");
    rs.background = float4{float(bg[0]), float(bg[1]), float(bg[2]), bg.size() == 4 ? float(bg[3]) : 1.0f};
  }
  rs.post.exposure = float(exposure);
  rs.post.tonemap = parseToneMap(tonemap);
  if (bloomOpt && bloomOpt->count()) parseBloom(bloom.empty() ? std::string() : bloom[0], rs.post);
  if (ssaoOpt && ssaoOpt->count()) parseSsao(ssao.empty() ? std::string() : ssao[0], rs.post);
  validate(rs.post);
  return rs;
}

void SceneOptions::applySceneLook(const Scene& scene, RenderSettings& rs, bool still) const {
  const SceneLook& look = scene.look;
  // A glTF file is shown as its author made it: the glTF material model and
  // its lights; the built-in scenes keep their Lambert look (but the probes).
  if (shading.empty() && (!scene.sourceFiles.empty() || look.gltfMaterials)) rs.shading = ShadingMode::Pbr;
  // --filter auto means the file's samplers to the glTF shading; the others filter bilinearly.
  if (rs.filter == TexFilter::Auto && !readsGltfMaterial(rs.shading)) rs.filter = TexFilter::Bilinear;
  if (background.empty() && look.background) rs.background = *look.background;
  if (lights.empty() && !look.lights.empty()) {
    rs.lights.clear();
    for (const float4& l : look.lights) rs.lights.push_back(DirectionalLight{float3{l.x, l.y, l.z}, l.w});
  }
  if (still && aa.empty() && !reference && look.msaa > 1) rs.msaa = look.msaa;
}

Camera SceneOptions::camera(const Scene& s) const {
  // A builtin scene's own camera keeps its field of view unless --fovy is given.
  if (fovy && !(*fovy > 0.0 && *fovy < 180.0)) throw Error("--fovy must be in (0, 180) degrees");
  if (ortho && !(*ortho > 0.0 && std::isfinite(*ortho))) throw Error("--ortho must be a positive half height");
  Camera c;
  if (!fileCamera.empty()) {
    // The file's camera sets the whole view; only its planes may be overridden.
    if (cameraGiven() || fovy || ortho)
      throw Error("--camera sets the view: give it or --eye/--target/--up/--fovy/--ortho, not both");
    c = rast::fileCamera(s, fileCamera);
  } else try {
    const Camera framed = defaultCamera(s, fovy.value_or(45.0));
    c = framed;
  } catch (const Error&) {
    // A scene auto-framing cannot place may still be viewed from a camera the
    // user gives in full.
    if (eye.empty() || target.empty() || !znear || !zfar) throw;
  }
  if (fovy) c.fovyDeg = *fovy;
  if (ortho) c.orthoHalfHeight = *ortho;
  if (!eye.empty()) c.eye = parseVec3(eye, "eye");
  if (!target.empty()) c.target = parseVec3(target, "target");
  if (!up.empty()) c.up = parseVec3(up, "up");
  if (znear) c.znear = *znear;
  if (zfar) c.zfar = *zfar;
  if (!(c.fovyDeg > 0.0 && c.fovyDeg < 180.0)) throw Error("--fovy must be in (0, 180) degrees");
  // An orthographic view may start at the eye (glTF allows znear 0 there).
  if (!(c.orthoHalfHeight > 0.0 ? c.znear >= 0.0 : c.znear > 0.0) || !(c.zfar > c.znear) || !std::isfinite(c.zfar))
    throw Error(c.orthoHalfHeight > 0.0 ? "--near/--far: need 0 <= near < far" : "--near/--far: need 0 < near < far");
  // SSAO reconstructs view-space positions through a perspective projection.
  if (c.orthoHalfHeight > 0.0 && ssaoOpt && ssaoOpt->count() > 0)
    throw Error("--ssao needs a perspective camera (this one is orthographic)");
  if (glm::length(c.eye - c.target) == 0.0) throw Error("--eye and --target must differ");
  if (glm::length(glm::cross(c.target - c.eye, c.up)) == 0.0) throw Error("--up must not be parallel to the view direction");
  return c;
}

std::optional<int> parseCommandLine(CLI::App& app, const char* program, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);
    std::string m = e.what();
    for (char& c : m)
      if (c == '\n') c = ' ';
    std::fprintf(stderr, "%s: error: %s\n", program, m.c_str());
    return 2;
  }
  return std::nullopt;
}

}  // namespace rast
