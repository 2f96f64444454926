// Launch shapes and tuning constants of the pipeline, per kind of machine.
//
// core/ takes every "how many threads / how big a team" decision from here.
// They depend only on rast::kOnDevice (backends/exec_space.h), not on a
// particular GPU vendor: the values below hold for NVIDIA (32-wide warps) and
// AMD (64-wide wavefronts) alike, which the static_asserts keep true.
#pragma once

#include "backends/exec_space.h"

#include <cstddef>
#include <cstdint>

namespace rast {

// Widest SIMD group of any supported GPU: AMD's 64-lane wavefront (NVIDIA's
// warp is 32). Team sizes are multiples of it so no wavefront runs half empty.
constexpr int kMaxSimdWidth = 64;

// Threads per team for the team kernels (setup count/write, binned fine
// raster): a full block on a GPU; on a CPU a team is one thread that loops over
// the team's range. The team kernels never assume a warp size: they use
// TeamThreadRange, team scans and team_barrier only.
constexpr int kTeamSize = kOnDevice ? 256 : 1;
static_assert(!kOnDevice || kTeamSize % kMaxSimdWidth == 0, "GPU teams must be whole 64-lane wavefronts");

// Team scratch (bytes) a kernel may keep at level 0 (on-chip: CUDA shared
// memory, AMD LDS). 32 KiB fits every supported GPU (48 KiB static shared
// memory on NVIDIA, 64 KiB LDS on AMD) with room for two teams per
// multiprocessor; larger buffers go to level 1.
constexpr size_t kFastScratchBytes = 32 * 1024;

// Binned raster: at most this many triangle batches. On a GPU a fixed count
// keeps a good part of the machine busy; on a CPU a few batches per core.
uint32_t binBatchLimit();

// Threads to launch for persistent (grid-stride) loops whose trip count is only
// known on the device: enough to fill every core or multiprocessor.
uint32_t persistentThreads();
// The threads a GPU multiprocessor (an AMD compute unit) holds at once, in
// whose units Kokkos counts a GPU's concurrency (persistentThreads): 2,048
// on every NVIDIA generation from Maxwell to Hopper and on AMD's CDNA.
constexpr uint32_t kThreadsPerMultiprocessor = 2048;

// RasterMethod::Auto: GPUs (measured on an H100, docs/raster-methods.md)
// favour the visibility buffer's bounded blocks, by 3-20x over binned whose
// per-tile lists serialise; CPUs favour binned. Naive wins when no raster
// triangle's box exceeds this many pixels (GPU: one 8x8 block; CPU: the
// triangle-size sweep crosses over between 5 and 16 pixel legs).
constexpr bool kPreferVisBuffer = kOnDevice;
constexpr uint64_t kNaiveMaxBoxArea = kOnDevice ? 8 * 8 : 10 * 10;
// How often `auto` refreshes its statistics (one frame in this many, and
// whenever it has none): the statistics pass and its read-back cost 0.01-0.02
// ms a frame on the H100 (0.085 ms over a million triangles), while the choice
// it feeds only changes when the view changes a lot. Images do not depend on
// it: every method gives the same ids, depth and colour.
constexpr uint32_t kAutoStatsEvery = 8;
// The visbuffer raster's occluder pass (raster_visbuffer.cpp), under `auto`:
// run when the occluder candidates' summed area within the view is at least
// this many frames. On the H100 (1080p, same-run A/B) it took engine_inside
// (candidates: 8.8 frames) from 0.272 to 0.210 ms and overdraw (9.9) from
// 0.192 to 0.144, and cost milktruck_cab (1.7) 4 us of raster; bigtri's
// single layer (1.0) and the outside views (0.1-0.5) gain nothing.
constexpr double kOccluderMinLayers = 3.0;

// GPU setup: scenes of at most this many chunks of 256 triangles set up in
// one pass, each chunk finding its place by looking back at the chunks before
// it, four at a time (kLookBackBatch); larger ones count first
// (primitive_setup.cpp). On the H100, one at a time saved 2-8 us up to 17
// chunks, was even at 23 (cow) and lost 30 us at 475 (engine) and 320 us at
// 3,900 (tiny); four at a time then took cow's frame 0.076 -> 0.067-0.070 ms
// and duck's 0.080 -> 0.074-0.075, one- and two-chunk scenes even, and
// engine's setup (475 chunks) from 39.9 us with the count pass to 32.7 in one
// pass (engine_inside 61.7 -> 55.6), so the limit rose from 24 to 512 (same-run
// A/Bs, 300 frames, docs/journal/performance-2026-11-*.md). Tiny's 3,900 chunks still count first:
// one pass was not measured there with four at a time.
constexpr uint32_t kSetupLookBackMaxChunks = 512;

// Host setup: a scene whose raster triangles may take more than this many
// bytes has them copied out with streaming stores (backends/stream_store.h),
// past the caches: the raster reads them back from memory anyway. Smaller
// ones stay in the caches for it (primitive_setup.cpp).
constexpr size_t kHostSetupStreamMinBytes = size_t(16) << 20;

// Scenes of at most this many draws have their model-view-projection
// matrices computed on the host and uploaded with the camera, in the same
// copy: a frame then has one launch fewer (the draw_matrices kernel), about
// 3 us on the H100, for at most 16 KiB more to copy (DeviceScene::hostMvps).
constexpr uint32_t kHostMatricesMaxDraws = 256;

// Shading: pixels per work item along a row. A CPU thread keeps the last
// triangle's lookups (draw, indices, vertex attributes, material) across its
// run, so neighbouring pixels of one triangle pay for them once. A GPU thread
// shades kShadeInterleave pixels one above the other instead (a warp, a tile 32 wide: coalesced),
// loading their keys together: on the H100, one pixel per thread left the
// empty 1080p frame's shading at 0.028 ms, one load latency per wave of
// resident threads; runs of 4 along a row were slower still (0.044 ms), their
// strided accesses uncoalesced.
// (A CPU takes that layout only when a run of 1 is asked for, as the tests do.)
constexpr int32_t kShadeRun = kOnDevice ? 1 : 64;
constexpr int32_t kShadeInterleave = 4;
// Raster: pixels of a row whose visibility keys one thread reads together
// before testing them (rasterRect): the 8 of a row of an 8x8 block on a GPU.
// CPUs group the same way (their usual method, binned, has its own loop).
constexpr int kRasterRowGroup = 8;
// The per-pixel shade kernel's launch bounds on GPUs: {threads per block, blocks
// per multiprocessor}; {256, 2} caps it at 128 registers a thread on NVIDIA's
// 64K-register multiprocessors. Ignored by host backends.
constexpr unsigned kShadeLaunchBounds[2] = {256, 2};
// The exact and sorted methods' resolve (pipeline/blend/blend_tiles.cpp,
// its lightweight instances) on GPUs, the same cap: unbounded, ptxas gives
// the lit instance 175 registers (one block of 256 a multiprocessor); capped
// at 128 it spills 176 bytes and still takes 25-30% less time on the H100
// (8 full-screen layers 1.29 -> 0.96 ms, 32 layers 6.51 -> 4.56 ms).
constexpr unsigned kBlendResolveLaunchBounds[2] = {256, 2};
// Its team form (PeelTeam, the specialised instances on GPUs): a team per
// 8x8 block, a thread a pixel; {64, 12}, a cap of 80 registers. The block's
// listed triangles are set up in team scratch: this many bytes a team (12
// teams, 192 KiB, fit a Hopper multiprocessor's 228 KiB: 24 warps), or, when
// the last frame's longest list needed more, up to the larger size (fewer
// teams a multiprocessor, under their own launch bounds: Kokkos refuses a
// scratch that does not let the bounds' teams fit; below the 48 KiB a CUDA
// block has without opting in). A longer list is walked from global memory,
// as by the plain resolve. H100, 1920x1080, 8 mixed layers, exact's
// resolve with the scratch read by shared loads (backends/team_scratch.h;
// docs/journal/transparency-2026-11.md): {64, 8} and 24 KiB 0.397 ms,
// {64, 10} and 20 KiB 0.425, {64, 12} and 16 KiB 0.367, {64, 14} and 14 KiB
// 0.367 (weighted and sorted 2-3% faster, but 18 glTF-shaded triangles fill
// it: shorter lists would take the larger scratch). Before, 44 KiB and
// {64, 5} for every frame made 64 layers 3x faster and 8 layers 1.4x slower.
// The larger scratch holds a block's list of 64 triangles (64 full-screen
// layers off their diagonals): under the lit shading 70 entries of 640
// bytes a GPU (PeelTeam::Entry and the list's two indices) in 44 KiB at five
// teams a multiprocessor; under the glTF shading 66 of 728 bytes in 47 KiB at
// four (five do not fit a Hopper multiprocessor's 228 KiB; Kokkos adds 528
// bytes a team, and 48 KiB is a CUDA block's most without opting in).
constexpr unsigned kBlendTeamLaunchBounds[2] = {64, 12};
constexpr size_t kBlendTeamScratchBytes = 16 * 1024;
constexpr unsigned kBlendTeamDeepLaunchBounds[2] = {64, 5};
constexpr size_t kBlendTeamScratchMaxBytes = 44 * 1024;
constexpr unsigned kBlendTeamDeepPbrLaunchBounds[2] = {64, 4};
constexpr size_t kBlendTeamScratchMaxPbrBytes = 47 * 1024;
// Whether every tile lists' resolve encodes the colour as it writes the film,
// where no post pass follows (BlendPlan::encode), instead of the post chain's
// own pass. On 2 CPU cores, 8 mixed layers at 1920x1080: the 6 ms pass
// gone, the resolve 3 ms longer. On a GPU the team resolve's three table
// reads a pixel cost more than the pass they replace under Lambert (H200,
// same scene: resolve 0.368 -> 0.383 ms, encode 0.015 -> 0, frame 0.524 ->
// 0.528; 64 layers 4.40 -> 4.45): there only the glTF shading's resolve
// encodes, whose uniform blocks' pixels a light kernel writes
// (blendResolveEncodes, Peel::kEncodes).
constexpr bool kBlendResolveEncodes = !kOnDevice;
// The tile lists' strided layout (pipeline/blend/blend_tiles.cpp): where the
// last frame's longest list was at most this long, each block's list has
// this many entries' room at block x stride, filled in one pass with no
// count pass and no scan. 32 entries: 4 MiB at 1920x1080 (2 bytes a pixel),
// 16 full-screen layers' quads on their diagonals. On a GPU those two
// passes were a third of the lists' stage (8 mixed layers, H200); a CPU's
// count pass owns its blocks (no atomics) and is cheap: counted there.
constexpr uint32_t kBlendListStride = kOnDevice ? 32 : 0;
// The visbuffer raster's blocks (raster_visbuffer.cpp) on GPUs: one SIMD group
// a block, {threads, blocks per multiprocessor}; on NVIDIA {32, 20}, a cap of
// 102 registers that the kernel's 96 stay under. Its items cost from a few
// instructions (a block outside its triangle) to a 64-pixel walk, and a block
// holds its multiprocessor's slots until its slowest thread ends: a block a
// warp frees them a warp at a time. On the H100 (1080p, three same-run A/Bs
// against Kokkos' own block size): box 0.0661 -> 0.0630 ms, bigtri -0.3 to
// -3.2 us, milktruck_cab -0.7 to -2.1 us, others -2.1 to +1.7 us with no sign
// common to the runs; blocks of 64, 128 and 256 gained nothing measurable
// (docs/journal/performance-2026-11-*.md). AMD's {64, 10} is one wavefront a block, unmeasured.
constexpr unsigned kRasterLaunchBounds[2] = {unsigned(kSimdWidth), 640u / unsigned(kSimdWidth)};

// The visbuffer raster with a block's row on consecutive lanes
// (RasterBlockRows, raster_visbuffer.cpp): its coalesced key reads and atomics
// pay where items are few and mostly covered, its item set-up on eight lanes
// costs where they are many, small or skipped. Under `auto` on GPUs it runs
// when the raster triangles' mean bounding box is at least this many pixels
// and the occluder pass does not (in frames of layered triangles most items
// are skipped). Same-run A/Bs on the H100, 1920x1080 (frame ms, mean box in
// pixels, docs/journal/performance-2026-11-*.md): milktruck_cab 0.1501 -> 0.1425 (34,000),
// bigtri 0.1152 -> 0.0968 (2.07 M), box 0.0608 -> 0.0508 (186,000),
// checkerboard 0.0451 -> 0.0409 (158,000); but milktruck 0.0730 -> 0.0777
// (1,228), duck +5 us (365), cow +5 us (204), engine +52 us (73), and with
// the occluder pass overdraw +41 us (81,600) and engine_inside +144 us (4,431).
constexpr uint64_t kRowLanesMinBoxArea = 4096;
// Team members (of eight lanes each) a team: a block of 128 threads.
constexpr uint32_t kRowTeam = kOnDevice ? 16 : 1;
// Scenes of more draws than this (and at most 65,536) get a table from each
// drawn triangle and drawn vertex to its draw (DeviceScene::triDraw,
// vertDraw): one load instead of a binary search over the draws' starts, a
// chain of dependent loads per vertex, triangle and shaded triangle (seven
// for engine's 115 draws). Fewer draws search a few entries; 2 bytes a
// triangle and a vertex are then not worth it. On the H100 (1080p, same-run
// A/B): engine 0.1158 -> 0.1114 ms (vertex, setup and shading each 1-2 us
// faster), engine_inside 0.1945 -> 0.1871; tables for every scene of two or
// more draws gave milktruck_cab 1 us of shading and nothing else measurable.
// tiny (one draw, no table) shaded 3 us slower in every build with them, which
// its code path does not explain (docs/journal/performance-2026-11-*.md).
constexpr uint32_t kDrawTableMinDraws = 16;

}  // namespace rast
