// backends/: whether an execution space is a GPU comes from Kokkos' space
// traits, and the launch shapes follow from it.
#include <catch2/catch.hpp>

#include "pipeline/data/device.h"
#include "scenes/procedural.h"
#include "tests/support/test_support.h"

TEST_CASE("backends: host spaces are not devices, GPU spaces are", "[backends]") {
  STATIC_REQUIRE_FALSE(rast::runsOnDevice<Kokkos::Serial>());
  STATIC_REQUIRE_FALSE(rast::runsOnDevice<Kokkos::DefaultHostExecutionSpace>());
#if defined(KOKKOS_ENABLE_OPENMP)
  STATIC_REQUIRE_FALSE(rast::runsOnDevice<Kokkos::OpenMP>());
#endif
#if defined(KOKKOS_ENABLE_CUDA)
  STATIC_REQUIRE(rast::runsOnDevice<Kokkos::Cuda>());
#endif
#if defined(KOKKOS_ENABLE_HIP)
  STATIC_REQUIRE(rast::runsOnDevice<Kokkos::Experimental::HIP>());
#endif
  STATIC_REQUIRE(rast::kOnDevice == rast::runsOnDevice<rast::Exec>());
}

TEST_CASE("backends: team size and thread counts follow the kind of machine", "[backends]") {
  const uint32_t c = uint32_t(rast::Exec().concurrency());
  if (rast::kOnDevice) {
    // whole 64-lane wavefronts (and 32-lane warps)
    CHECK(rast::kTeamSize % 64 == 0);
    CHECK(rast::persistentThreads() == c);
  } else {
    // a host team is one thread looping over the team's range (FineRaster's
    // incremental path relies on it)
    CHECK(rast::kTeamSize == 1);
    CHECK(rast::persistentThreads() == 16 * c);
    CHECK(rast::binBatchLimit() == 8 * c);
  }
  CHECK(rast::TeamPolicy(1, rast::kTeamSize).team_size() == rast::kTeamSize);
}

TEST_CASE("backends: auto refreshes its statistics every kAutoStatsEvery frames, and follows the view", "[backends][auto]") {
  // A 128x128 grid: from far away every triangle is a pixel or less (naive's
  // domain), from close up they are tens of pixels wide (the bounded-work
  // method's). Auto decides from statistics of an earlier frame, refreshed one
  // frame in kAutoStatsEvery, so it may lag a view change by that many frames
  // and never more; the image never depends on it.
  using namespace rast;
  using namespace rast::test;
  RenderSettings rs;
  rs.width = 128;
  rs.height = 128;
  rs.raster = RasterMethod::Auto;
  const Scene s = builtinScene("builtin:grid?n=128");
  Renderer r(s);
  Camera far = defaultCamera(s), near = far;
  far.eye = {0.0, 0.0, 60.0};
  far.target = {0.0, 0.0, 0.0};
  near.eye = {0.0, 0.0, 0.05};  // a few quads across the image: boxes of tens of pixels
  near.target = {0.0, 0.0, 0.0};
  far.znear = near.znear = 0.01;
  far.zfar = near.zfar = 100.0;
  const RasterMethod bounded = kPreferVisBuffer ? RasterMethod::VisBuffer : RasterMethod::Binned;

  // No statistics yet: the bounded-work method; from the next frame, naive.
  CHECK(r.resolveMethod(rs) == bounded);
  r.render(far, rs);
  CHECK(r.resolveMethod(rs) == RasterMethod::Naive);
  // kAutoStatsEvery + 1 frames in all: the next refresh is kAutoStatsEvery - 1
  // frames away.
  for (uint32_t k = 0; k < kAutoStatsEvery; ++k) r.render(far, rs);
  CHECK(r.resolveMethod(rs) == RasterMethod::Naive);

  // The view changes; auto switches at the next refresh, not before and not
  // after: the kAutoStatsEvery-th frame from here renders the statistics.
  int switchedAfter = -1;
  for (uint32_t k = 0; k <= kAutoStatsEvery && switchedAfter < 0; ++k) {
    r.render(near, rs);
    if (r.resolveMethod(rs) == bounded) switchedAfter = int(k) + 1;
  }
  INFO("auto switched after " << switchedAfter << " frames");
  CHECK(switchedAfter == int(kAutoStatsEvery));

  // Whatever auto picked, the frame equals every fixed method's.
  RenderSettings fixed = rs;
  fixed.raster = RasterMethod::Naive;
  const Frame a = renderFrame(s, near, rs), b = renderFrame(s, near, fixed);
  CHECK(a.ids == b.ids);
  CHECK(a.depth == b.depth);
}
