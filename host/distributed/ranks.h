// The processes of a distributed run (`mpirun -np N rast ... --distribute`,
// docs/distributed.md): who this process is, and the few collective steps that
// sort-last compositing and many-view batches need, on host memory. Built once
// (not per execution space) over MPI when the build found it (RAST_MPI,
// ranks_mpi.cpp), else over a single process (ranks_single.cpp), so that
// callers are the same either way. No MPI header leaks out of here.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace rast {

class Ranks {
 public:
  // Starts MPI (once, before Kokkos, so that the device can follow the rank's
  // place on its node); without MPI in the build, or with start == false, the
  // run is one process. finish() ends MPI after Kokkos.
  static void start(int* argc, char*** argv, bool start);
  static void finish();
  static bool builtWithMpi();

  static int rank();
  static int size();
  // The rank's index among the ranks of its node (MPI_Comm_split_type), which
  // picks its GPU.
  static int localRank();
  static bool distributed() { return size() > 1; }

  // Agreement after a step that may fail: every rank passes "" or its error;
  // each returns "" when all succeeded, else the lowest failing rank's error as
  // "rank R: <error>" (the same text on every rank).
  static std::string agree(const std::string& error);
  // Element-wise minimum over the ranks, in place on every rank.
  static void allMinU64(uint64_t* data, size_t n);
  // Element-wise bitwise or over the ranks into rank 0's buffer (the others'
  // are left as they were): merges buffers in which each element is non-zero
  // on at most one rank.
  static void orToRoot(uint32_t* data, size_t n);
  static void orToRoot(uint8_t* data, size_t n);
  // Rank `root`'s bytes to every rank (NCCL's unique id).
  static void broadcast(void* data, size_t bytes, int root);
  // Every rank's string, on every rank (the build check at start).
  static std::vector<std::string> gather(const std::string& mine);
  // Ends every rank now (the last resort when a rank fails where the others
  // may be waiting in a collective step).
  [[noreturn]] static void abortAll(int code);
  static double seconds();  // wall clock, for the composite's timing
};

}  // namespace rast
