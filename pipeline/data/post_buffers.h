// The float film and the buffers of the post passes. Each is allocated the
// first time a pass needs it (grow-only, like every frame buffer) and released
// when the frame size changes, so a frame that asks for no float path holds
// none of them.
#pragma once

#include "pipeline/data/device.h"
#include "base/vec.h"

namespace rast {

struct PostBuffers {
  DView<float4> hdr;    // per pixel: linear colour (the float film)
  DView<float4> geom;   // per pixel: view-space normal (xyz) and view depth (w > 0; 0 = background), for SSAO
  DView<float> depth;   // per pixel: the view depth alone (geom.w), what SSAO's many taps read
  DView<float> ao, aoBlur;       // per pixel: ambient occlusion (1 = open); the march writes aoBlur, the blur's
                                 // horizontal half ao, its vertical half aoBlur (the final AO)
  DView<float4> half0, half1;    // bloom: bright pass at half resolution and the blur's ping-pong partner
  DView<float> kernel;           // bloom: Gaussian weights; SSAO: unused
  DView<float4> samples;         // SSAO: hemisphere sample kernel (xyz, scale in w)
  int kernelRadius = -1, sampleCount = -1;

  void release() { *this = PostBuffers(); }
  // Frees what the next frame will not use (a pass switched off, or no float
  // path at all), so the memory report follows the settings.
  void trim(bool film, bool ssao, bool bloom) {
    if (!film) return release();
    if (!ssao) {
      geom = DView<float4>();
      depth = DView<float>();
      ao = aoBlur = DView<float>();
      samples = DView<float4>();
      sampleCount = -1;
    }
    if (!bloom) {
      half0 = half1 = DView<float4>();
      kernel = DView<float>();
      kernelRadius = -1;
    }
  }
  size_t bytes() const {
    return viewBytes(hdr) + viewBytes(geom) + viewBytes(depth) + viewBytes(ao) + viewBytes(aoBlur) + viewBytes(half0) +
           viewBytes(half1) + viewBytes(kernel) + viewBytes(samples);
  }
};

}  // namespace rast
