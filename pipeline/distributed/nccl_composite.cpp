#include "pipeline/distributed/nccl_composite.h"

#include "base/error.h"
#include "host/distributed/ranks.h"
#include "pipeline/data/device.h"

#include <dlfcn.h>

#include <cstdlib>
#include <type_traits>

namespace rast {
namespace {

// NCCL 2.x's stable C ABI (nccl.h), declared here so that no NCCL header is
// needed to build: an opaque communicator, a 128-byte unique id, the enums'
// values, and cudaStream_t as the pointer it is.
struct NcclId {
  char internal[128];
};
using NcclComm = void*;
constexpr int kNcclSuccess = 0;
constexpr int kNcclUint32 = 3, kNcclUint64 = 5;  // ncclDataType_t
constexpr int kNcclSum = 0, kNcclMin = 3;        // ncclRedOp_t

// The execution space's stream (null: not a CUDA space).
template <class E>
void* streamOf(const E&) {
  return nullptr;
}
#if defined(KOKKOS_ENABLE_CUDA)
inline void* streamOf(const Kokkos::Cuda& e) { return static_cast<void*>(e.cuda_stream()); }
#endif

}  // namespace

struct NcclComposite::Api {
  void* lib = nullptr;
  void* stream = nullptr;
  NcclComm comm = nullptr;
  int (*getVersion)(int*) = nullptr;
  int (*getUniqueId)(NcclId*) = nullptr;
  int (*commInitRank)(NcclComm*, int, NcclId, int) = nullptr;
  int (*commDestroy)(NcclComm) = nullptr;
  int (*allReduce)(const void*, void*, size_t, int, int, NcclComm, void*) = nullptr;
  int (*reduce)(const void*, void*, size_t, int, int, int, NcclComm, void*) = nullptr;
  const char* (*errorString)(int) = nullptr;

  void check(int r, const char* what) const {
    if (r != kNcclSuccess)
      throw Error(std::string("NCCL ") + what + " failed: " + (errorString ? errorString(r) : std::to_string(r)));
  }
};

NcclComposite::NcclComposite() : api_(new Api) {}

NcclComposite::~NcclComposite() {
  if (api_->comm && api_->commDestroy) api_->commDestroy(api_->comm);
  // The library stays loaded: NCCL's threads may outlive the communicator.
}

std::unique_ptr<NcclComposite> NcclComposite::load(std::string* why) {
  void* stream = streamOf(Exec());
  if (!stream) {
    *why = std::string("the build's execution space (") + Exec::name() + ") is not CUDA";
    return nullptr;
  }
  const char* path = std::getenv("RAST_NCCL_LIB");
  void* lib = dlopen(path && *path ? path : "libnccl.so.2", RTLD_NOW | RTLD_LOCAL);
  if (!lib) {
    const char* e = dlerror();
    *why = std::string("cannot load NCCL (") + (e ? e : "libnccl.so.2") + "; set RAST_NCCL_LIB or LD_LIBRARY_PATH)";
    return nullptr;
  }
  std::unique_ptr<NcclComposite> n(new NcclComposite);
  Api& a = *n->api_;
  a.lib = lib;
  a.stream = stream;
  bool ok = true;
  const auto sym = [&](auto& fn, const char* name) {
    fn = reinterpret_cast<std::remove_reference_t<decltype(fn)>>(dlsym(lib, name));
    ok = ok && fn != nullptr;
  };
  sym(a.getVersion, "ncclGetVersion");
  sym(a.getUniqueId, "ncclGetUniqueId");
  sym(a.commInitRank, "ncclCommInitRank");
  sym(a.commDestroy, "ncclCommDestroy");
  sym(a.allReduce, "ncclAllReduce");
  sym(a.reduce, "ncclReduce");
  sym(a.errorString, "ncclGetErrorString");
  if (!ok) {
    *why = "the NCCL library lacks a function rast needs (ncclAllReduce, ncclReduce, ...)";
    return nullptr;
  }
  return n;
}

void NcclComposite::join() {
  Api& a = *api_;
  NcclId id{};
  if (Ranks::rank() == 0) a.check(a.getUniqueId(&id), "ncclGetUniqueId");
  Ranks::broadcast(&id, sizeof id, 0);
  a.check(a.commInitRank(&a.comm, Ranks::size(), id, Ranks::rank()), "ncclCommInitRank");
}

void NcclComposite::allMinU64(uint64_t* d, size_t n) {
  api_->check(api_->allReduce(d, d, n, kNcclUint64, kNcclMin, api_->comm, api_->stream), "ncclAllReduce");
}

void NcclComposite::sumToRoot(uint32_t* d, size_t n) {
  api_->check(api_->reduce(d, d, n, kNcclUint32, kNcclSum, 0, api_->comm, api_->stream), "ncclReduce");
}

std::string NcclComposite::version() const {
  int v = 0;
  if (api_->getVersion) api_->getVersion(&v);
  // NCCL >= 2.9 codes versions as major * 10000 + minor * 100 + patch.
  return std::to_string(v / 10000) + "." + std::to_string(v / 100 % 100) + "." + std::to_string(v % 100);
}

}  // namespace rast
