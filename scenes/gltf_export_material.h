// The glTF material and light model in `rast export` (issue #37): what a
// Scene says of its materials (metallic-roughness factors and textures,
// normal / occlusion / emissive textures, alpha mode, double-sidedness,
// unlit), its samplers' filters, its tangents and second coordinates, its
// KHR_lights_punctual lights and its cameras, written into the glTF model
// that scenes/gltf_export.cpp builds for the meshes. Kept apart from that file
// so that the exporter's parts (meshes, materials, animation) grow separately.
#pragma once

#include "host/scene/scene.h"

#include <tiny_gltf.h>

namespace rast {

// Completes `m`, which gltf_export.cpp filled with one image, sampler and
// texture per Scene texture (in order), one material per Scene material, one
// mesh of one primitive per Scene primitive and one node per draw (scene 0):
//  - a scene that carries glTF materials (read from a file, or a built-in
//    scene made for the glTF shading: SceneLook::gltfMaterials) gets its
//    materials as they are and its samplers' filters; the others keep the
//    neutral matte, double-sided materials gltf_export.cpp writes (rast draws
//    them Lambert, unculled), and samplers without filters, as before;
//  - primitives get TANGENT (where every vertex has one) and TEXCOORD_1
//    (where their material samples the second coordinates);
//  - lights and cameras become nodes of scene 0.
// KHR_texture_transform is not written: rast bakes it into the coordinates at
// load, so the coordinates written are already transformed.
void exportMaterialModel(const Scene& s, tinygltf::Model& m);

}  // namespace rast
