// Image-based light (docs/lighting.md): an environment panorama filtered once,
// on the device, into what the fragment shader reads, as the Khronos glTF
// Sample Renderer filters it: a cube map of GGX-prefiltered radiance (one
// level per roughness step), a Lambertian irradiance cube map, and the
// split-sum BRDF table. Built per environment and kept across frames; the
// fragment maths that read it are in ibl_shading.h.
#pragma once

#include "host/image/hdr_image.h"
#include "pipeline/data/device.h"
#include "base/vec.h"

namespace rast {

constexpr int kMaxEnvLevels = 16;

// How an environment is filtered and lit. The defaults are the Sample
// Renderer's (its iblSampler), except where docs/lighting.md says otherwise:
// the irradiance map's side (64, not 256) and the table's (256, not 1024).
struct EnvOptions {
  float intensity = 1.0f;         // multiplies every environment sample (--env-intensity)
  float rotationDegrees = 90.0f;  // about +Y, as the Sample Renderer's environmentRotation (default 90)
  float backgroundBlur = 0.6f;    // the background's level of detail / (mipCount - 1) (its blurEnvironmentMap)
  int faceSize = 256;             // side of the panorama's cube map and of the sharpest specular level
  int lowestMipLevel = 4;         // the smallest specular level has side 2^lowestMipLevel (16)
  int ggxSamples = 1024;          // per texel of a specular level
  int lambertSamples = 2048;      // per texel of the irradiance map
  int diffuseSize = 64;           // side of the irradiance map's faces
  int lutSize = 256;              // side of the split-sum table
  int lutSamples = 512;           // per entry of the table
};

// Settings for the built-in neutral environment (hdr_image.h), which has no
// detail finer than its soft key light: a 64-texel cube (5 specular levels,
// 64 down to 4, so lod = roughness * 4 as with the reference's settings), a
// 16-texel irradiance map and a 128x128 table: 2e7 samples, a tenth of the
// reference settings' (docs/lighting.md).
EnvOptions neutralOptions();

// The filtered environment on the device. Cube levels are stored face after
// face with a one-texel border (pipeline/shade/cube_map.h).
struct EnvironmentGPU {
  DView<float4> specular;  // mipCount levels, level l of side faceSize >> l, roughness l / (mipCount - 1)
  DView<float4> diffuse;   // one level of side diffuseSize: mean radiance over the cosine lobe (E / pi)
  DView<float2> lut;       // lutSize^2, row = roughness, column = NdotV: (scale, bias) of F0
  int32_t faceSize = 0, mipCount = 0, diffuseSize = 0, lutSize = 0;
  uint32_t levelOffset[kMaxEnvLevels] = {};
  float cosRot = 1.0f, sinRot = 0.0f;  // the rotation about +Y applied to every lookup direction
  float intensity = 1.0f;
  float backgroundLod = 0.0f;
  bool valid() const { return faceSize > 0; }
  // Device bytes held (the three views).
  uint64_t bytes() const;
};

// Checks `o` (throws rast::Error naming the bad option) and returns the
// device bytes an environment built with it holds, and those it needs while
// building besides (the panorama's copy and its cube map with all levels).
uint64_t environmentBytes(const EnvOptions& o);
uint64_t environmentBuildBytes(const EnvOptions& o, int panoramaWidth, int panoramaHeight);

// Filters `img` on the device (kernels rast::shade::ibl::*). The held bytes
// are charged to `ledger`, the temporary ones checked against it first.
// Deterministic: the same bits on every run and backend (fixed sample
// sequences, each texel summed in a fixed order by one thread, no atomics).
EnvironmentGPU buildEnvironment(const HdrImage& img, const EnvOptions& o, MemoryLedger& ledger);

// The environment of `--env FILE` (readHdr, then buildEnvironment with `o`),
// or with an empty path the built-in neutral one (neutralEnvironment(),
// filtered with neutralOptions() and o's intensity, rotation and blur).
// The host panorama is charged while it lives and released after.
EnvironmentGPU loadEnvironment(const std::string& path, const EnvOptions& o, MemoryLedger& ledger);

// Changes what needs no filtering again: intensity, rotation, background blur.
void setEnvironmentLook(EnvironmentGPU& env, const EnvOptions& o);

// The view ray of every pixel for the background (envBackground), as an
// affine function of the pixel: dir(px, py) = d00 + dx px + dy py (not unit),
// px from the left, py from the top row, for a width x height image seen
// through `viewProj` (world to clip, column-major, perspective or
// orthographic). Computed on the host once per camera; each ray is the
// difference of the pixel centre's points at NDC depth +0.5 and -0.5, so it
// needs no eye position and holds for an orthographic camera too.
struct EnvViewRays {
  float3 d00, dx, dy;
};
EnvViewRays envViewRays(const mat4d& viewProj, int width, int height);

}  // namespace rast
