// The shade stage's front: the parameters a frame's shading reads (ShadeParams,
// filled once per frame by the frame plan) and the per-pixel shading kernel
// (rast::shade, rast::shade::lit) that every backend runs. The CPU's span and
// fused tile shading build on the same fragment maths in pipeline/cpu/.
#pragma once

#include "pipeline/data/frame_buffers.h"
#include "pipeline/shade/environment.h"
#include "host/settings/render_settings.h"

namespace rast {

struct LightGPU {
  float3 direction;  // normalised, towards the light
  float intensity;
};

struct ShadeParams {
  ShadingMode mode;
  TexFilter filter;
  DView<FrameUniforms> frame;  // the camera's eye, view, near and far: FrameBuffers::uniforms
  float ambient, specular, shininess;
  float4 background;
  uint32_t backgroundPacked;  // sRGB RGBA8, encoded once on the host
  int32_t headlight;  // 1: one light at the eye, per fragment
  int32_t wantDepth, wantPrimId, wantNormals;
  int32_t perspective;  // 0: affine interpolation (for comparison only)
  // The float film (pipeline/post/): shading writes linear colour to f.post.hdr
  // instead of packing RGBA8, and with wantGeom view-space normal and depth
  // to f.post.geom for every pixel.
  int32_t floatOut, wantGeom;
  float4 backgroundFilm;  // the background as the film holds it
  int32_t shadeRun;       // pixels per shading work item along a row; 0: the backend's kShadeRun
  // Only the visbuffer or naive raster wrote keys this frame, one sample per pixel:
  // an 8x8 block whose FrameBuffers::blockFrame is not this frame's holds
  // only clear keys, and the GPU's shading skips reading them.
  int32_t blockFrames;
  int32_t anisotropy;  // most taps of anisotropic filtering (--filter auto, the glTF shading)
  // Image-based light of the glTF shading (the renderer's environment), when useEnv.
  int32_t useEnv;
  EnvironmentGPU env;
};

// What the shade stage writes for the transparency methods that walk tile
// lists (pipeline/blend/, BlendPlan), where the frame plan asks it to; only
// the kernel of shadeWritesOpaqueDepth does.
struct ShadeBlend {
  // Each sample's depth bits, written as its key is read and cleared
  // (BlendPlan::shadeDepth).
  DView<uint32_t> opaqueDepth;
  // Per 8x8 block, where every pixel's BLEND layers composite alike
  // (BlendBuffers::blockFrags not kUniformWalk), what lies in front of the
  // opaque surface (BlendBuffers::blockComposite): such a pixel's film value
  // is that over the colour shaded (overOpaque), with its bytes where encode
  // (encodeFilm; BlendPlan::shadeComposite, encode, raw, straight).
  DView<float4> composite;
  DView<uint32_t> frags;
  bool encode = false, raw = false, straight = false;
  // With encode: such a pixel's film value is not written (BlendPlan::filmless).
  bool filmless = false;
};
void shadeStage(const DeviceScene& s, FrameBuffers& f, const ShadeParams& p, const DView<LightGPU>& lights,
                const ShadeBlend& blend = ShadeBlend());
// Whether shadeStage's kernel for p can write the opaque depth (the glTF
// shading's kernel, one sample), which the listed transparency methods
// then need not copy out of the keys before shading clears them.
bool shadeWritesOpaqueDepth(const ShadeParams& p, int samples);

// Whether a frame of p with `samples` coverage samples a pixel is shaded by a
// kernel launched lightweight: the lit kernel (Lambert or Blinn-Phong straight
// to 8-bit colour, one sample), or the glTF shading's (rast::shade::pbr, one
// sample); the general kernel launches heavyweight (device.h).
bool shadeLaunchesLightweight(const ShadeParams& p, int samples);

}  // namespace rast
