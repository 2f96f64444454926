// Compositing on GPUs with NCCL (docs/distributed.md): the key exchange as
// ncclAllReduce of ncclUint64 with ncclMin, and the merge of outputs as
// ncclReduce of ncclUint32 with ncclSum onto rank 0 (each word is non-zero on
// at most one rank, so the sum is the or), both in place in device memory on
// the execution space's stream: no host staging, no wait on the host. NCCL is
// not a Debian package: it is loaded at run time (dlopen of libnccl.so.2, or
// the file RAST_NCCL_LIB names), so one CUDA build runs with or without it.
// Used only by CUDA builds; every other build, or a machine without NCCL,
// composites through MPI on the host (sort_last.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

namespace rast {

class NcclComposite {
 public:
  // Loads NCCL for this process: null, with the reason in *why, when this
  // build does not run on a CUDA device or the library cannot be loaded.
  static std::unique_ptr<NcclComposite> load(std::string* why);
  ~NcclComposite();
  // Makes the communicator of every rank (collective: every rank that loaded
  // NCCL calls it; rank 0's unique id travels over MPI). Throws Error.
  void join();
  void allMinU64(uint64_t* deviceData, size_t n);
  void sumToRoot(uint32_t* deviceData, size_t n);
  std::string version() const;

 private:
  struct Api;
  NcclComposite();
  std::unique_ptr<Api> api_;
};

}  // namespace rast
