// The command line's side of distributed runs (docs/distributed.md): the
// build check at start, steps that every rank takes together (a failure on
// any rank ends all of them with one line from rank 0 naming the failing
// rank), and the scene each rank draws: under sort-last its share of the
// whole scene, seen through the camera the whole scene gives.
#pragma once

#include "app/cli_options.h"
#include "pipeline/distributed/sort_last.h"

#include <memory>
#include <string>

namespace rast {

// Checks that MPI is built in and that every rank runs the same build
// (rast's version, Kokkos and backend); throws on every rank.
void startDistributed();

// Ends the run on this rank for an error every rank knows: rank 0 throws it
// (one line), the others exit quietly.
[[noreturn]] void failTogether(const std::string& message);

// Every rank's error or "" -> the lowest failing rank's, named (Ranks::agree).
std::string agreeAll(const std::string& error);
// Prints the error with the rank and ends every rank (MPI_Abort).
[[noreturn]] void abortRun(const std::string& message);

// Runs a step that may fail on some ranks; then all ranks agree on whether
// it failed anywhere (failTogether names the lowest failing rank).
template <class F>
void together(bool distributed, F&& step) {
  if (!distributed) {
    step();
    return;
  }
  std::string error;
  try {
    step();
  } catch (const std::exception& e) {
    error = e.what();
    if (error.empty()) error = "failed";
  }
  const std::string all = agreeAll(error);
  if (!all.empty()) failTogether(all);
}

// Runs frames whose collective steps agree on failure themselves (a Renderer
// with a SortLast split): an agreed failure ends every rank as failTogether
// does; any other (a device error between collective steps, where the others
// may wait) is printed with the rank and ends every rank (MPI_Abort).
template <class F>
void frames(bool distributed, F&& step) {
  if (!distributed) {
    step();
    return;
  }
  try {
    step();
  } catch (const AgreedFailure& e) {
    failTogether(e.what());
  } catch (const std::exception& e) {
    abortRun(e.what());
  }
}

struct RunScene {
  Scene scene;  // the whole scene, or this rank's share under sort-last
  Camera camera;  // from the whole scene
  std::unique_ptr<SortLast> split;  // sort-last: attach to the renderer
  uint64_t trianglesAll = 0;
};

// Loads SCENE as the command line says; with `share`, keeps this rank's share
// of it (sort-last) and makes the split that composites the frames.
RunScene loadRunScene(const SceneOptions& so, bool share);

}  // namespace rast
