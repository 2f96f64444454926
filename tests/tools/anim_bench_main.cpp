// rast-anim-bench: the wall time of evaluating the animations of a chain of
// N nodes (tests/support/animated_chain.h; the budget is 1 ms for
// 10,000 nodes on the CPU), as a median over many evaluations at times spread
// over the animation. Under callgrind (--toggle-collect='rast::evaluateNodes*')
// it gives the instructions of one evaluation times --runs.
//
//   rast-anim-bench [--nodes N] [--runs R] [--reference]     (threads: OMP_NUM_THREADS)
//
// --reference times the straightforward evaluation instead (one thread, every
// channel in file order; tests/support/animated_chain.h), the baseline.
#include "tests/support/animated_chain.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

using namespace rast;

int main(int argc, char** argv) {
  int nodes = 10000, runs = 200;
  bool reference = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--reference")) reference = true;
    else if (!std::strcmp(argv[i], "--nodes") && i + 1 < argc) nodes = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--runs") && i + 1 < argc) runs = std::atoi(argv[++i]);
    else {
      std::fprintf(stderr, "rast-anim-bench: unknown option %s\n", argv[i]);
      return 2;
    }
  }
  if (nodes < 1 || runs < 1) {
    std::fprintf(stderr, "rast-anim-bench: --nodes and --runs must be positive\n");
    return 2;
  }
  const SceneRig rig = test_support::animatedChain(nodes);
  std::vector<glm::dmat4> world = evaluateNodes(rig, PoseRequest{0.05, 0}, nullptr);  // warm
  std::vector<double> ms(static_cast<size_t>(runs));
  double check = 0.0;
  for (int r = 0; r < runs; ++r) {
    const double t = 0.05 + 9.8 * double(r) / double(runs);  // spread over the keys, increasing as playback does
    const auto t0 = std::chrono::steady_clock::now();
    if (reference) world = test_support::referenceEvaluate(rig, PoseRequest{t, 0}, nullptr);
    else evaluateNodes(rig, PoseRequest{t, 0}, world, nullptr);  // into the same buffer, as playback does
    ms[size_t(r)] = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    check += world.back()[3][0];
  }
  std::sort(ms.begin(), ms.end());
  std::printf("anim_bench %s nodes=%d runs=%d median_ms=%.4f min_ms=%.4f p90_ms=%.4f check=%.9g\n", reference ? "reference" : "evaluateNodes", nodes, runs, ms[ms.size() / 2],
              ms.front(), ms[ms.size() * 9 / 10], check);
  return 0;
}
