#include "app/scene_info.h"

#include "host/scene/animation.h"

#include <glm/glm.hpp>

#include <cstdio>

namespace rast {

bool extensionHonoured(const std::string& name) {
  // The loader reads quantized attributes (host/gltf/accessors.cpp), bakes
  // the textures' transform into the UVs (model_walk.cpp) and reads lights and
  // the material extensions (materials.cpp), which `--shading pbr` shades; every
  // other extension is ignored (and refused when a file requires it).
  return name == "KHR_mesh_quantization" || name == "KHR_texture_transform" || name == "KHR_lights_punctual" ||
         name == "KHR_materials_unlit" || name == "KHR_materials_emissive_strength" || name == "EXT_mesh_gpu_instancing" ||
         name == "KHR_materials_clearcoat" || name == "KHR_draco_mesh_compression" || name == "EXT_meshopt_compression";
}

void printSceneInfo(const Scene& s, const std::string& source) {
  const FileFacts& f = s.facts;
  std::printf("scene: %s\n", source.c_str());
  std::printf("geometry: %u triangles, %llu line segments, %llu points in %zu draws of %zu primitives; %zu vertices\n",
              s.triangleCount(), (unsigned long long)s.lineCount(), (unsigned long long)s.pointCount(), s.draws.size(),
              s.prims.size(), s.positions.size());
  std::printf("textures: %zu\n", s.textures.size());

  std::printf("cameras: %zu%s\n", s.cameras.size(), s.cameras.empty() ? " (rast frames the scene)" : " (--camera N|NAME)");
  for (size_t i = 0; i < s.cameras.size(); ++i) {
    const FileCamera& c = s.cameras[i];
    const glm::dvec3 eye(c.world[3]);
    char proj[160];
    if (c.orthographic)
      std::snprintf(proj, sizeof proj, "orthographic xmag %.6g ymag %.6g", c.xmag, c.ymag);
    else
      std::snprintf(proj, sizeof proj, "perspective yfov %.6g deg%s", glm::degrees(c.yfovRad),
                    c.aspectRatio > 0.0 ? " (file aspect ignored: the image's is used)" : "");
    char planes[96];
    if (c.zfar > 0.0)
      std::snprintf(planes, sizeof planes, "near %.6g far %.6g", c.znear, c.zfar);
    else
      std::snprintf(planes, sizeof planes, "near %.6g far infinite", c.znear);
    std::printf("  %zu '%s': %s, %s, at %.6g,%.6g,%.6g\n", i, c.name.c_str(), proj, planes, eye.x, eye.y, eye.z);
  }

  // What moves (docs/animation.md).
  if (s.rig) {
    size_t skinned = 0, morphed = 0;
    for (const DeformedDraw& d : s.rig->deformed) {
      skinned += d.skin >= 0;
      morphed += d.targets > 0;
    }
    std::printf("animation: %zu animations, %zu skins; %zu skinned and %zu morphed draws (--time T, --animation N|NAME)\n",
                s.rig->animations.size(), s.rig->skins.size(), skinned, morphed);
    for (size_t i = 0; i < s.rig->animations.size(); ++i) {
      const Animation& a = s.rig->animations[i];
      std::printf("  %zu '%s': %zu channels, %.6g to %.6g s\n", i, a.name.c_str(), a.channels.size(), a.start, a.end);
    }
  }

  const uint32_t lights = f.lightsDeclared[0] + f.lightsDeclared[1] + f.lightsDeclared[2];
  std::printf("lights (KHR_lights_punctual): %u declared (%u directional, %u point, %u spot), placed by %u nodes: %s\n",
              lights, f.lightsDeclared[0], f.lightsDeclared[1], f.lightsDeclared[2], f.lightNodes,
              lights ? "honoured by --shading pbr (the default for glTF files)" : "none (rast lights with its headlight)");

  std::printf("materials: %u\n", f.materials);
  static const char* kFeature[11] = {"baseColorTexture",  "metallicRoughnessTexture", "normalTexture",
                                     "occlusionTexture",  "emissive",                 "alphaMode MASK",
                                     "alphaMode BLEND",   "doubleSided",              "KHR_materials_unlit",
                                     "KHR_texture_transform", "KHR_materials_clearcoat"};
  // What `--shading pbr` uses (pipeline/shade/pbr_shading.h); MASK and BLEND
  // are drawn by the alpha passes (pipeline/blend/, docs/transparency.md).
  static const bool kHonoured[11] = {true, true, true, true, true, true, true, true, true, true, true};
  for (int k = 0; k < 11; ++k)
    if (f.materialUses[k])
      std::printf("  %-26s %u material%s: %s\n", kFeature[k], f.materialUses[k], f.materialUses[k] == 1 ? "" : "s",
                  kHonoured[k] ? "honoured" : "ignored");
  if (f.tangentPrims || f.generatedTangentPrims)
    std::printf("  %-26s %u normal-mapped primitive%s with TANGENT: honoured; %u without: tangents generated per vertex\n",
                "TANGENT", f.tangentPrims, f.tangentPrims == 1 ? "" : "s", f.generatedTangentPrims);
  if (f.twoUvMaterials)
    std::printf("  %-26s %u material%s: honoured (a second set of coordinates)\n", "two texCoord sets/transforms", f.twoUvMaterials,
                f.twoUvMaterials == 1 ? "" : "s");

  auto list = [](const char* what, const std::vector<std::string>& names) {
    std::printf("%s: %zu\n", what, names.size());
    for (const std::string& n : names) std::printf("  %-34s %s\n", n.c_str(), extensionHonoured(n) ? "honoured" : "ignored");
  };
  list("extensions used", f.extensionsUsed);
  list("extensions required", f.extensionsRequired);
}

}  // namespace rast
