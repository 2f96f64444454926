// Ray-traced ambient occlusion on the CPU, the reference SSAO is measured
// against (docs/post.md): for every pixel the rasterizer covered, rays from the
// visible surface point over the cosine-weighted hemisphere around its normal,
// tested against every triangle of the scene through a bounding-volume
// hierarchy; AO = the fraction of rays that hit nothing within the radius.
// Slow on purpose (many rays per pixel); host code only.
#pragma once

#include "host/scene/camera.h"
#include "host/scene/scene.h"

#include <vector>

namespace rast {

// geom: the frame's view-space normal and depth per pixel, bottom row first
// (Renderer::geometryBottomUp after a frame with SSAO on); background pixels
// (depth 0) get AO 1. Returns AO per pixel, bottom row first.
std::vector<float> rayTracedAo(const Scene& scene, const Camera& cam, int width, int height,
                               const std::vector<float4>& geom, float radius, int raysPerPixel, uint32_t seed = 1);

}  // namespace rast
