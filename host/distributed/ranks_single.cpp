// Ranks for a build without MPI: one process, every collective step the
// identity (host/distributed/ranks.h).
#include "host/distributed/ranks.h"

#include <chrono>
#include <cstdlib>

namespace rast {

void Ranks::start(int*, char***, bool) {}
void Ranks::finish() {}
bool Ranks::builtWithMpi() { return false; }
int Ranks::rank() { return 0; }
int Ranks::size() { return 1; }
int Ranks::localRank() { return 0; }
std::string Ranks::agree(const std::string& error) { return error.empty() ? error : "rank 0: " + error; }
void Ranks::allMinU64(uint64_t*, size_t) {}
void Ranks::orToRoot(uint32_t*, size_t) {}
void Ranks::orToRoot(uint8_t*, size_t) {}
void Ranks::broadcast(void*, size_t, int) {}
std::vector<std::string> Ranks::gather(const std::string& mine) { return {mine}; }
void Ranks::abortAll(int code) { std::exit(code); }
double Ranks::seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace rast
