// FrameGraphs (backends/frame_graphs.h): a recorded frame replays its upload
// and its kernels (they run, on the values uploaded for this frame), replays
// the timer's marks, and is dropped when a buffer is allocated or the key
// changes. On backends that record nothing every call launches directly; the
// results are the same.
#include <catch2/catch.hpp>

#include "backends/frame_graphs.h"
#include "backends/stage_timer.h"
#include "pipeline/data/device.h"
#include "pipeline/data/test_hooks.h"
#include "host/settings/render_settings.h"

#include <set>

using namespace rast;

namespace {

// Adds the device value `step` to counter(0): a kernel whose effect shows
// whether it ran, and whose input changes between replays.
struct AddStep {
  DView<uint32_t> counter, step;
  KOKKOS_INLINE_FUNCTION void operator()(const int) const { counter(0) += step(0); }
};
void addStep(const DView<uint32_t>& counter, const DView<uint32_t>& step) {
  Kokkos::parallel_for("test::graphs::add", Range(0, 1), AddStep{counter, step});
}

uint32_t readBack(const DView<uint32_t>& v) {
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), v);
  return h(0);
}


}  // namespace

TEST_CASE("a recorded frame replays its kernels, marks and host state", "[graphs]") {
  DView<uint32_t> counter = allocZeroed<uint32_t>("test.counter", 1);
  DView<uint32_t> step = allocZeroed<uint32_t>("test.step", 1);
  FrameGraphs graphs;
  StageTimer timer;
  int direct = 0, replays = 0;
  uint32_t expected = 0;
  uint64_t state = 0;
  for (int i = 1; i <= 6; ++i) {
    const uint32_t value = uint32_t(i);  // uploaded, like the camera
    expected += value;
    timer.start();
    const bool replayed = graphs.run("key", &timer, state, {&value, step.data(), sizeof value, value}, [&] {
      ++direct;
      addStep(counter, step);
      timer.mark("add");
      state = 7;
    });
    replays += replayed;
    REQUIRE(state == 7);
    const auto stages = timer.finish();
    REQUIRE(stages.size() == 1);
    CHECK(stages[0].first == "add");
    CHECK(stages[0].second >= 0.0);
    REQUIRE(readBack(counter) == expected);
  }
  // Recording backends: direct, recorded (its launch runs it), then replays.
  CHECK(direct == (FrameGraphs::records() ? 2 : 6));
  CHECK(replays == (FrameGraphs::records() ? 4 : 0));

  SECTION("an allocation drops the recording") {
    DView<uint32_t> other = allocUninit<uint32_t>("test.other", 4);
    const int before = direct;
    const uint32_t value = 100;
    graphs.run("key", nullptr, state, {&value, step.data(), sizeof value, value}, [&] {
      ++direct;
      addStep(counter, step);
    });
    CHECK(direct == before + 1);
    CHECK(readBack(counter) == expected + 100);
  }
  SECTION("another key records anew") {
    const int before = direct;
    for (uint32_t value : {10u, 20u, 30u})
      graphs.run("other key", nullptr, state, {&value, step.data(), sizeof value, value}, [&] {
        ++direct;
        addStep(counter, step);
      });
    CHECK(direct == before + (FrameGraphs::records() ? 2 : 3));
    CHECK(readBack(counter) == expected + 60);
  }
}

TEST_CASE("settings keys differ exactly when settings do", "[graphs]") {
  RenderSettings a;
  std::set<std::string> keys{settingsKey(a)};
  CHECK(settingsKey(a) == settingsKey(RenderSettings(a)));
  auto differs = [&](const char* what, RenderSettings b) {
    INFO(what);
    CHECK(keys.insert(settingsKey(b)).second);
  };
  RenderSettings b = a;
  b.width = 1921; differs("width", b);
  b = a; b.shading = ShadingMode::Depth; differs("shading", b);
  b = a; b.ambient = std::nextafter(a.ambient, 1.0f); differs("ambient by one ulp", b);
  b = a; b.lights.push_back(DirectionalLight{}); differs("a light", b);
  b = a; b.post.ssao = true; differs("ssao", b);
  b = a; b.post.exposure = 0.5f; differs("exposure", b);
  b = a; b.background.w = 0.5f; differs("background alpha", b);
  b = a; b.wireframe = Wireframe::On; differs("wireframe", b);
}

TEST_CASE("the test hooks are part of a frame's key", "[graphs]") {
  // A recorded frame must not replay across a change of hook (frame_plan.cpp
  // appends TestHooks::key() to the plan's key).
  std::set<std::string> keys{TestHooks{}.key()};
  auto differs = [&](const char* what, const TestHooks& h) {
    INFO(what);
    CHECK(keys.insert(h.key()).second);
  };
  TestHooks h;
  h.shadeRun = 3; differs("shade run", h);
  h = TestHooks{}; h.rowLanes = 1; differs("row lanes", h);
  h = TestHooks{}; h.generalShade = true; differs("general shade", h);
  h = TestHooks{}; h.gpuSetupOnHostTeam = 4; differs("GPU setup on the host", h);
  h = TestHooks{}; h.hostSetupStaged = 3; differs("host setup staging", h);
  h = TestHooks{}; h.hostSetupStream = -1; differs("host setup stores", h);
}
