// The fixture of the glTF shading's closed-form tests (test_pbr_shading.cpp,
// test_clearcoat.cpp): a 2x2 square facing +z, seen along its axis by a
// camera of kSize x kSize pixels (odd: a pixel centre lies on the axis) and
// lit by one KHR_lights_punctual light, so that at the centre pixel
// N = V = L = H and the BRDF's terms have closed forms; and the tolerance
// that 8-bit sRGB allows there. Shared so that both files build, render and
// read the same square (the duplicates tool had found it copied).
#pragma once

#include "base/color.h"
#include "host/scene/camera.h"
#include "tests/support/test_support.h"
#include "tests/unit/loader_test_helpers.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace rast::pbr_axis {

using loader_test::Doc;
using loader_test::json;
using loader_test::kU16;

constexpr double kPi = 3.14159265358979323846;
constexpr int kSize = 33;  // odd: a pixel centre lies on the axis

// A 2x2 square in the z = 0 plane facing +z, with material 0, and a light
// (KHR_lights_punctual) when `light` is not null, placed by a node with
// `lightNode`'s values. TEXCOORD_0 when `withUv`; a TANGENT attribute
// (4 floats a vertex) when `tangent` is not empty.
inline Doc square(const json& material, const json* light = nullptr, const json& lightNode = json::object(),
                  bool withUv = false, const std::vector<float>& tangent = {}) {
  Doc doc;
  const std::vector<float> pos = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
  const std::vector<float> nrm = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
  const std::vector<uint16_t> idx = {0, 1, 2, 0, 2, 3};
  json attrs = {{"POSITION", doc.vec3(pos)}, {"NORMAL", doc.vec3(nrm)}};
  if (withUv) attrs["TEXCOORD_0"] = doc.floats({0, 1, 1, 1, 1, 0, 0, 0}, "VEC2", 2);
  if (!tangent.empty()) attrs["TANGENT"] = doc.floats(tangent, "VEC4", 4);
  const int ia = doc.accessor(doc.view(idx), kU16, idx.size(), "SCALAR");
  doc.prim({{"attributes", attrs}, {"indices", ia}, {"material", 0}});
  doc.j["materials"] = json::array({material});
  if (light) {
    json node = lightNode;
    node["extensions"] = {{"KHR_lights_punctual", {{"light", 0}}}};
    doc.j["nodes"].push_back(node);
    doc.j["scenes"][0]["nodes"].push_back(1);
    doc.j["extensions"] = {{"KHR_lights_punctual", {{"lights", json::array({*light})}}}};
    doc.j["extensionsUsed"] = {"KHR_lights_punctual"};
  }
  return doc;
}

// The square seen from `eye` towards the origin under `--shading pbr`, the
// file's lights alone (no environment: the closed forms), nearest texels
// (or `filter`).
inline test::Frame axisFrame(const Scene& s, const glm::dvec3& eye = {0, 0, 3}, TexFilter filter = TexFilter::Nearest) {
  Camera cam;
  cam.eye = eye;
  cam.target = {0, 0, 0};
  RenderSettings rs;
  rs.width = rs.height = kSize;
  rs.shading = ShadingMode::Pbr;
  rs.environment = "none";
  rs.filter = filter;
  return test::renderFrame(s, cam, rs);
}

// The centre pixel's colour, linear (decoded from the 8-bit sRGB image).
inline rast::float3 centreLinear(const test::Frame& f) {
  const uint32_t c = f.color[size_t(kSize / 2) * kSize + kSize / 2];
  return rast::float3{float(srgbDecode((c & 0xff) / 255.0)), float(srgbDecode(((c >> 8) & 0xff) / 255.0)),
                      float(srgbDecode(((c >> 16) & 0xff) / 255.0))};
}

// What 8-bit sRGB can tell apart: one step at the value's level, plus rounding.
inline void near(double got, double want) {
  const double tol = std::max(1.5 / 255.0, 2.0 * (srgbDecode(std::min(1.0, srgbEncode(want) + 1.0 / 255.0)) - want));
  INFO("got " << got << ", want " << want);
  CHECK(std::abs(got - want) <= tol);
}

}  // namespace rast::pbr_axis
