// What `rast export` writes for a scene that moves (Scene::rig): the node
// hierarchy placing the draws, skins (joints, weights, inverse bind
// matrices), morph targets and animations, so that a skinned or animated
// scene, read from a file or built in (scenes/skinned_scenes.h), goes out as
// a glTF that rast and other renderers pose alike. Kept apart from
// gltf_export.cpp, which writes the meshes and materials and calls this.
#pragma once

#include "host/scene/scene.h"

namespace tinygltf {
class Model;
struct Scene;
}  // namespace tinygltf

namespace rast {

// For a scene with a rig, after exportGlb has written one mesh per
// Scene::prims entry (mesh index = prim index) into m.meshes and its data into
// m.buffers[0]: writes the rig's nodes (node i of the rig is node i of the
// file) with each draw's primitive on the node that places it, the roots into
// `scene`, the skins, the morph targets with their default weights, and the
// animations; deformed primitives get their bind pose back in place of the
// posed vertices. Throws Error for what it cannot write (instanced draws of
// a rig). A scene without a rig: nothing to do (false), the caller writes a
// node per draw.
bool writeMotion(const Scene& s, tinygltf::Model& m, tinygltf::Scene& scene);

}  // namespace rast
