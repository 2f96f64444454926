#include "app/distribute.h"

#include "app/guarded_main.h"
#include "host/distributed/ranks.h"
#include "scenes/procedural.h"
#include "scenes/stress_scenes.h"

#include <cstdio>
#include <cstdlib>

namespace rast {

std::string agreeAll(const std::string& error) { return Ranks::agree(error); }

void failTogether(const std::string& message) {
  if (Ranks::rank() == 0) throw Error(message);
  throw QuietFailure();
}

void abortRun(const std::string& message) {
  std::fprintf(stderr, "rast: error: rank %d: %s\n", Ranks::rank(), printable(message, 900).c_str());
  Ranks::abortAll(1);
}

void startDistributed() {
  char b[200];
  std::snprintf(b, sizeof b, "rast %s (Kokkos %d.%d.%d, %s backend)", RAST_VERSION, KOKKOS_VERSION / 10000,
                KOKKOS_VERSION / 100 % 100, KOKKOS_VERSION % 100, Exec::name());
  const std::string version = b;
  if (!Ranks::builtWithMpi())
    throw Error("--distribute: this rast was built without MPI (configure with RAST_MPI=ON and an MPI such as "
                "Debian's libopenmpi-dev; docs/distributed.md)");
  const std::vector<std::string> all = Ranks::gather(version);
  for (size_t r = 1; r < all.size(); ++r)
    if (all[r] != all[0])
      failTogether("--distribute: rank " + std::to_string(r) + " runs '" + printable(all[r]) + "', rank 0 '" +
                   printable(all[0]) + "': every rank must run the same build");
}

RunScene loadRunScene(const SceneOptions& so, bool share) {
  // Fault injection for tests/cli/cli_distributed.py: one rank fails to load.
  if (const char* f = std::getenv("RAST_TEST_FAIL_RANK"))
    if (Ranks::distributed() && std::atoi(f) == Ranks::rank()) throw Error("injected failure (RAST_TEST_FAIL_RANK)");
  RunScene out;
  // builtin:tiny?n= is generated in part: each rank makes only the rows of
  // the grid that hold its share, so a billion triangles never exist on one host.
  Scene part;
  uint64_t first = 0, total = 0;
  const std::string spec = so.scene.rfind("builtin:", 0) == 0 ? so.scene.substr(8) : std::string();
  if (share && !spec.empty() && makeStressScenePart(spec, 0, 0, part, first, total)) {
    const std::vector<ShareRange> shares = planShares(total, 0, 0, Ranks::size());
    const ShareRange& mine = shares[size_t(Ranks::rank())];
    makeStressScenePart(spec, mine.t0, mine.t1, part, first, total);
    out.camera = so.camera(part);  // the builtin scene's own camera (no bounds needed)
    ShareRange local;
    local.t0 = mine.t0 - first;
    local.t1 = mine.t1 - first;
    out.scene = takeShare(part, local);
    out.scene.validate();
    out.trianglesAll = total;
    if (Ranks::size() > 1) out.split = std::make_unique<SortLast>(shares, Ranks::rank());
    return out;
  }
  Scene full = loadSceneArg(so.scene, so.loadOptions());
  so.pose(full);  // --time/--animation: framed and drawn as posed
  out.camera = so.camera(full);
  out.trianglesAll = full.triangleCount();
  if (!share) {
    out.scene = std::move(full);
    return out;
  }
  const std::vector<ShareRange> shares =
      planShares(full.triangleCount(), full.lineCount(), full.pointCount(), Ranks::size());
  // BLEND draws are composited by rank 0, which holds them whole (docs/distributed.md).
  const bool blend = Ranks::size() > 1 && drawsBlend(full);
  std::vector<TriRun> blendWhole;
  out.scene = takeShare(full, shares[size_t(Ranks::rank())], blend && Ranks::rank() == 0 ? &blendWhole : nullptr);
  out.scene.validate();
  full = Scene();  // only the share stays
  // One rank holds the whole frame: nothing to exchange (no composite, no
  // merge; the H100 paid 3 + 1.5 ms a 1080p frame for them, staged through
  // the host).
  if (Ranks::size() > 1) out.split = std::make_unique<SortLast>(shares, Ranks::rank(), blendWhole, blend);
  return out;
}

}  // namespace rast
