// Every switch that tests use to force one of the pipeline's internal paths,
// in one place. Each forces a path the renderer would otherwise choose by
// itself (by backend, scene or frame statistics), so that tests can compare
// two paths that must give the same bytes on one backend; none of them may
// change an image. Production code never sets them. Values are read on the
// host when a frame is planned or launched; the frame plan's key
// (pipeline/frame/frame_plan.h) includes them, so recorded frames never
// replay across a change.
#pragma once

#include <cstdint>
#include <string>

namespace rast {

struct TestHooks {
  // > 0: a host backend sets up primitives as a GPU does (primitive_setup.cpp's
  // WriteChunks: a team per chunk of this many threads; the look-back for few
  // chunks, a count pass for more), so that the GPU's setup runs, and can hang
  // or fail, on the CPU too. 0: the host's own. GPUs ignore it.
  int gpuSetupOnHostTeam = 0;
  // The host's setup (SetupChunksHost) stages at most this many raster
  // triangles a chunk before it writes the rest directly (0: as many as fit),
  // and copies them with streaming stores (> 0), plain ones (< 0) or as the
  // scene's size decides (0). GPUs ignore them.
  int hostSetupStaged = 0;
  int hostSetupStream = 0;
  // true: the per-pixel shade kernel takes its general form for every frame,
  // including lit frames that normally take the kernel compiled for lit
  // shading alone (shade_fragment.h, Shade::litOnly).
  bool generalShade = false;
  // The visbuffer raster's layout: 1 a block's rows on lanes (RasterBlockRows)
  // on any backend, -1 never, 0 as the frame plan decides.
  int rowLanes = 0;
  // Pixels per shading work item along a row; 0: the backend's kShadeRun
  // (backends/tuning.h). 1 on a CPU forces the per-pixel kernel (the span
  // kernel needs runs).
  int shadeRun = 0;
  // true: the exact and sorted BLEND resolve takes a GPU's team form on a
  // host backend too (pipeline/blend/peel_team.h, PeelTeam: a block's list set up once
  // in team scratch), so that its bits are checked against the host's own.
  bool teamResolve = false;
  // > 0: under teamResolve, the larger team scratch's entries on a host
  // backend (PeelTeam::deepEntries; above the smaller scratch's), so that
  // small frames' lists outgrow it and the long lists' kernel resolves them.
  uint32_t teamDeepEntries = 0;
  // true: a CPU's exact, sorted and weighted resolve peels every block's rows
  // (pipeline/blend/peel.h), never walking a block's triangles in order
  // (peel_block.h), so that the two are checked against each other. GPUs
  // ignore it (their team form walks in order itself).
  bool peelRows = false;
  // true: the post chain encodes every frame's film, never the tile lists'
  // resolve as it writes the film (BlendPlan::encode), so that the two are
  // checked against each other.
  bool chainEncode = false;
  // > 0: the tile lists take the strided layout with this stride wherever
  // the last frame's lists fit it (a GPU's, kBlendListStride) on any
  // backend; 0: as the backend decides.
  uint32_t listStride = 0;
  // true: every frame writes the whole float film, also where its colour's
  // bytes are written without it (BlendPlan::filmless), for tests that
  // compare films (tests/support/test_main.cpp sets it; the tests of the
  // filmless frames clear it).
  bool keepFilm = false;

  // The values as bytes, for the frame plan's key.
  std::string key() const;
};

// The process's hooks (tests set fields and restore them; see
// tests/support/hooks_guard.h).
TestHooks& testHooks();

}  // namespace rast
