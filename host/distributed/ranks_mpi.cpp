// Ranks over MPI (host/distributed/ranks.h): MPI_COMM_WORLD, its node-local
// split for the device, and the collective steps on host memory. Debian's
// OpenMPI is not CUDA-aware, so device buffers are staged through the host by
// the callers (pipeline/distributed/); NCCL, where built, composites on the
// device instead (nccl_composite.cpp).
#include "host/distributed/ranks.h"

#include <mpi.h>

#include <algorithm>
#include <climits>
#include <cstdio>

namespace rast {
namespace {

bool g_started = false;  // MPI_Init ran here (finish() ends it)
int g_rank = 0, g_size = 1, g_local = 0;

constexpr size_t kChunk = size_t(1) << 30;  // MPI counts are ints

}  // namespace

void Ranks::start(int* argc, char*** argv, bool start) {
  if (!start || g_started) return;
  int inited = 0;
  MPI_Initialized(&inited);
  if (!inited) MPI_Init(argc, argv);
  g_started = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &g_size);
  MPI_Comm node;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, g_rank, MPI_INFO_NULL, &node);
  MPI_Comm_rank(node, &g_local);
  MPI_Comm_free(&node);
}

void Ranks::finish() {
  if (!g_started) return;
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (!finalized) MPI_Finalize();
  g_started = false;
}

bool Ranks::builtWithMpi() { return true; }
int Ranks::rank() { return g_rank; }
int Ranks::size() { return g_size; }
int Ranks::localRank() { return g_local; }

std::string Ranks::agree(const std::string& error) {
  if (!g_started) return error.empty() ? error : "rank 0: " + error;
  const int mine = error.empty() ? INT_MAX : g_rank;
  int first = INT_MAX;
  MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  if (first == INT_MAX) return "";
  int len = g_rank == first ? int(std::min<size_t>(error.size(), 2000)) : 0;
  MPI_Bcast(&len, 1, MPI_INT, first, MPI_COMM_WORLD);
  std::string text(size_t(len), '\0');
  if (g_rank == first) std::copy(error.begin(), error.begin() + len, text.begin());
  if (len > 0) MPI_Bcast(&text[0], len, MPI_CHAR, first, MPI_COMM_WORLD);
  return "rank " + std::to_string(first) + ": " + text;
}

void Ranks::allMinU64(uint64_t* data, size_t n) {
  if (!g_started || g_size == 1) return;
  for (size_t at = 0; at < n; at += kChunk)
    MPI_Allreduce(MPI_IN_PLACE, data + at, int(std::min(kChunk, n - at)), MPI_UINT64_T, MPI_MIN, MPI_COMM_WORLD);
}

void Ranks::orToRoot(uint32_t* data, size_t n) {
  if (!g_started || g_size == 1) return;
  for (size_t at = 0; at < n; at += kChunk)
    MPI_Reduce(g_rank == 0 ? MPI_IN_PLACE : data + at, data + at, int(std::min(kChunk, n - at)), MPI_UINT32_T, MPI_BOR,
               0, MPI_COMM_WORLD);
}

void Ranks::orToRoot(uint8_t* data, size_t n) {
  if (!g_started || g_size == 1) return;
  for (size_t at = 0; at < n; at += kChunk)
    MPI_Reduce(g_rank == 0 ? MPI_IN_PLACE : data + at, data + at, int(std::min(kChunk, n - at)), MPI_UINT8_T, MPI_BOR,
               0, MPI_COMM_WORLD);
}

void Ranks::broadcast(void* data, size_t bytes, int root) {
  if (!g_started || g_size == 1) return;
  for (size_t at = 0; at < bytes; at += kChunk)
    MPI_Bcast(static_cast<char*>(data) + at, int(std::min(kChunk, bytes - at)), MPI_BYTE, root, MPI_COMM_WORLD);
}

std::vector<std::string> Ranks::gather(const std::string& mine) {
  if (!g_started) return {mine};
  const int len = int(std::min<size_t>(mine.size(), 4096));
  std::vector<int> lens(static_cast<size_t>(g_size)), offs(static_cast<size_t>(g_size));
  MPI_Allgather(&len, 1, MPI_INT, lens.data(), 1, MPI_INT, MPI_COMM_WORLD);
  int total = 0;
  for (int r = 0; r < g_size; ++r) {
    offs[size_t(r)] = total;
    total += lens[size_t(r)];
  }
  std::string all(size_t(total), '\0');
  MPI_Allgatherv(mine.data(), len, MPI_CHAR, &all[0], lens.data(), offs.data(), MPI_CHAR, MPI_COMM_WORLD);
  std::vector<std::string> out;
  for (int r = 0; r < g_size; ++r) out.push_back(all.substr(size_t(offs[size_t(r)]), size_t(lens[size_t(r)])));
  return out;
}

void Ranks::abortAll(int code) {
  std::fflush(stdout);
  std::fflush(stderr);
  if (g_started) MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}

double Ranks::seconds() { return MPI_Wtime(); }

}  // namespace rast
