// Helpers of the BLEND tests (test_transparency.cpp, test_tile_lists.cpp):
// one frame's float film, two films compared bit for bit (the listed methods
// promise the same bits across forms, layouts and thread schedules), and the
// resolve's team form on a CPU for a scope.
#pragma once

#include <cstring>
#include <vector>

#include "host/scene/camera.h"
#include "pipeline/data/test_hooks.h"
#include "pipeline/frame/renderer.h"

namespace rast::test {

// The linear film (bottom row first) of one frame from the default camera,
// its statistics into *st; budget as Renderer's (0: the default).
inline std::vector<rast::float4> film(const Scene& s, const RenderSettings& rs, FrameStats* st = nullptr,
                                      uint64_t budget = 0) {
  Renderer r(s, budget);
  const FrameStats f = r.render(defaultCamera(s), rs);
  if (st) *st = f;
  return r.filmBottomUp();
}

inline bool sameBits(const std::vector<rast::float4>& a, const std::vector<rast::float4>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(rast::float4)) == 0;
}

// The resolve's team form on a CPU (TestHooks::teamResolve) for a scope.
struct TeamForm {
  explicit TeamForm(bool on = true) { testHooks().teamResolve = on; }
  ~TeamForm() { testHooks().teamResolve = false; }
};

}  // namespace rast::test
