// What makes a glTF scene move, kept beside its Scene: the node hierarchy with
// each node's rest transform, the animations (samplers and channels), the
// skins (joints and inverse bind matrices) and, per deformed draw, its bind
// pose, joint influences and morph-target deltas. A static scene has none
// (Scene::rig is null) and pays nothing.
//
// Posing (poseScene) evaluates the animations at a time into node transforms,
// then writes every draw's model matrix and every deformed draw's vertices
// (morph targets, then skinning) into the Scene, in place: the pose a
// renderer uploads and auto-framing bounds. It runs on the host in double
// precision, so the same time gives the same bits on every backend (and with
// any number of threads).
#pragma once

#include "host/scene/scene.h"

#include <glm/gtc/quaternion.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace rast {

struct RigNode {
  int32_t parent = -1;
  bool hasMatrix = false;  // a node given as a matrix (never animated)
  glm::dmat4 matrix = glm::dmat4(1.0);
  glm::dvec3 translation{0.0};
  glm::dquat rotation{1.0, 0.0, 0.0, 0.0};  // w, x, y, z
  glm::dvec3 scale{1.0};
  std::vector<double> weights;  // morph weights (the node's, else its mesh's); empty: no targets
};

enum class Interpolation { Linear, Step, CubicSpline };
enum class AnimPath { Translation, Rotation, Scale, Weights };

struct AnimSampler {
  Interpolation interp = Interpolation::Linear;
  std::vector<float> times;   // strictly increasing, finite
  std::vector<float> values;  // per key: comps (x3 for CUBICSPLINE: in-tangent, value, out-tangent)
  uint32_t comps = 0;         // 3 (T, S), 4 (R), or the target count (weights)
};

struct AnimChannel {
  int32_t node = 0;
  AnimPath path = AnimPath::Translation;
  int32_t sampler = 0;
};

struct Animation {
  std::string name;
  std::vector<AnimSampler> samplers;
  std::vector<AnimChannel> channels;
  double start = 0.0, end = 0.0;  // first and last key time over its samplers
};

struct Skin {
  std::vector<int32_t> joints;           // node indices
  std::vector<glm::dmat4> inverseBind;   // one per joint (identity when the file gives none)
};

// A draw whose vertices move: it owns its primitive (the loader copies a
// primitive drawn by several deformed nodes), whose bind-pose streams are kept
// here, so that each pose is written from them.
struct DeformedDraw {
  uint32_t draw = 0;
  int32_t skin = -1;                   // -1: morph targets only
  std::vector<float3> basePositions, baseNormals;
  bool flatNormals = false;            // normals were generated per face: recomputed after posing
  // Skinning: 4 joints and 4 weights per influence set (1 or 2 sets) per vertex;
  // weights normalised to sum 1 at load.
  uint32_t sets = 0;
  std::vector<uint16_t> joints;
  std::vector<float> weights;
  // Morph targets: targets x vertexCount deltas (normals empty when no target
  // has NORMAL; tangents empty when none has TANGENT or the primitive keeps no
  // tangents, Scene::tangents). Tangent deltas move xyz; w, the handedness,
  // stays the base's (glTF 2.0, 3.7.2.2).
  uint32_t targets = 0;
  std::vector<float3> targetPositions, targetNormals, targetTangents;
  std::vector<float4> baseTangents;  // the bind pose's, when targetTangents is not empty
};

// A sampler as evaluation reads it: its keys where the rig holds them, and
// the first and last key times at hand (no trip to the keys to find the
// interval when they are evenly spaced).
struct SamplerView {
  const float* times = nullptr;
  const float* values = nullptr;
  uint32_t n = 0, comps = 0;
  Interpolation interp = Interpolation::Linear;
  float first = 0.0f, last = 0.0f;
  double keysPerSecond = 0.0;  // (n - 1) / (last - first): where a time's interval would be were the keys evenly spaced
};
SamplerView viewOf(const AnimSampler& s);

// Which channel sets each driven node's translation, rotation, scale and
// morph weights (indexed by AnimPath): the last one in file order where
// several do, as playing the channels one after another would leave it.
// timeline[p]: the selection's timeline (PlanSelection::timelines) that
// sampler[p]'s key times are.
struct NodeDrivers {
  int32_t node = 0;
  uint32_t driven = 0;  // bit p: path p is driven by sampler[p], else the node's rest value
  SamplerView sampler[4];
  uint32_t timeline[4] = {0, 0, 0, 0};
};

// One entry of the pass down the hierarchy: a node that is driven or under a
// driven one, in SceneRig::order.
struct MovedNode {
  int32_t node = 0, parent = -1;
  bool driven = false;  // its local matrix is sampled; else its rest local matrix
};

// What one selection (every animation, or one) drives, resolved once.
struct PlanSelection {
  std::vector<NodeDrivers> drivers;
  // The distinct arrays of key times (equal by content) of the drivers'
  // samplers: exporters give the channels of an animation one input
  // accessor, so a pose searches each timeline's key interval once, not each
  // channel's.
  std::vector<SamplerView> timelines;
  std::vector<MovedNode> moved;    // composed per pose, parents first
  std::vector<int32_t> resting;    // nodes of the scene that keep their rest world matrix
};

// The rig's channels resolved once (planAnimations), so that evaluating a
// pose walks flat arrays: per selection, the nodes it drives, each sampled by
// one thread, and the nodes to compose; and every node's world and local
// matrices at rest, which nodes outside the driven subtrees keep.
// A copied or moved plan comes out empty: its views would point into the
// keys of the rig it was made for, so only that rig uses it (a copy of a rig
// plans again on every evaluation until planAnimations is called on it).
struct AnimPlan {
  AnimPlan() = default;
  AnimPlan(const AnimPlan&) {}
  AnimPlan(AnimPlan&&) noexcept {}
  AnimPlan& operator=(const AnimPlan&) { return *this = AnimPlan(); }
  AnimPlan& operator=(AnimPlan&&) noexcept;
  const struct SceneRig* owner = nullptr;  // the rig planned: evaluating another plans afresh
  std::vector<PlanSelection> selections;   // [0]: every animation at once; [1 + a]: animation a alone
  std::vector<glm::dmat4> restWorld;       // per node (kNoAnimation's world matrices)
  std::vector<glm::dmat4> restLocal;       // per node, its local matrix at rest
};

struct SceneRig {
  std::vector<RigNode> nodes;      // every node of the file
  std::vector<int32_t> order;      // nodes with each parent before its children
  std::vector<int32_t> drawNode;   // per Scene::draws: the node that places it
  std::vector<glm::dmat4> drawInstance;  // per draw, its instance under the node (EXT_mesh_gpu_instancing); empty: none
  std::vector<Animation> animations;
  std::vector<Skin> skins;
  std::vector<DeformedDraw> deformed;
  AnimPlan plan;                   // planAnimations(), once the above is complete
};

// Fills rig.plan from its nodes, order and animations (the loader calls it;
// a rig built by hand should too: without a plan each evaluation makes one).
void planAnimations(SceneRig& rig);

// Which animations play, and when.
constexpr int kAllAnimations = -1;  // every animation at once (as the Khronos Sample Renderer plays them)
constexpr int kNoAnimation = -2;    // the nodes' own transforms and weights (the rest pose)
struct PoseRequest {
  double time = 0.0;
  int animation = kAllAnimations;  // or an index into SceneRig::animations
};

// The animation named `which` (an index from 0, or a name) of the rig; throws
// an Error listing the animations when there is none such.
int findAnimation(const SceneRig& rig, const std::string& which);

// One sampler at time t: comps values into out. Times before the first key give
// the first value, after the last the last (glTF 2.0, 3.11). Rotations are
// slerped (LINEAR) or normalised (CUBICSPLINE); cubic-spline tangents are
// scaled by the key interval.
void sampleAt(const AnimSampler& s, double t, bool rotation, double* out);
void sampleView(const SamplerView& s, double t, bool rotation, double* out);

// Every node's world matrix at the request's time (rest transforms where no
// channel drives a node), and every node's morph weights (out). The driven
// nodes are sampled in parallel, each by one thread, then the world
// matrices are composed down the hierarchy in one pass, only under driven
// nodes: the same bits whatever the thread count. Threads: OpenMP's count
// (OMP_NUM_THREADS), through shareChunks (host_workers.h), from 2,048
// driven nodes. The second form reuses the
// caller's buffer (no allocation once it has the size).
std::vector<glm::dmat4> evaluateNodes(const SceneRig& rig, const PoseRequest& r, std::vector<std::vector<double>>* weights);
void evaluateNodes(const SceneRig& rig, const PoseRequest& r, std::vector<glm::dmat4>& world,
                   std::vector<std::vector<double>>* weights);

// Writes the pose into the scene: draws' model matrices, deformed draws'
// vertices (morphed; skinned too with skinOnHost, else left in the morphed
// bind pose for the device's vertex stage to skin), and the request itself
// (Scene::poseTime, poseAnimation, skinnedOnHost).
void poseScene(Scene& s, const PoseRequest& r, bool skinOnHost = true);

// What the device's vertex stage skins with at the scene's pose
// (pipeline/data/device_scene.cpp): every skinned draw's joint matrices
// (world * inverse bind) and their normal matrices (inverse transpose), the
// draws' palettes one after another.
struct SkinPalette {
  std::vector<glm::dmat4> joints;
  std::vector<glm::dmat3> normals;
  std::vector<int32_t> start;  // per Scene::draws: its first joint, -1: not skinned on the device
};
// The palette; and, when the scene's skinned draws were skinned on the host,
// their morphed bind pose written over `positions`/`normals` (copies of the
// scene's streams), which is what the device takes.
SkinPalette skinPalette(const Scene& s, std::vector<float3>* positions = nullptr, std::vector<float3>* normals = nullptr);
// Whether any draw of the scene is skinned.
bool hasSkins(const Scene& s);

}  // namespace rast
