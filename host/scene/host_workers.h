// Work shared with helper threads that may never show up. On a machine whose
// cores are busy with other programs, a fork-join region (OpenMP's parallel
// for) waits at its end for every thread it woke, and a woken thread may wait
// a scheduler tick (milliseconds) for a core: a 0.3 ms job then takes 4 ms or
// more (docs/animation.md, "Cost"). Here the calling thread claims chunks of
// the work itself, in order, and only waits for a chunk that a helper has
// claimed and is running: a helper that comes late finds nothing left, and
// one that never comes costs nothing. Each chunk is run by exactly one
// thread, so work whose chunks write disjoint data gives the same bits
// whatever the number of threads.
#pragma once

#include <cstdint>

namespace rast {

// Runs run(ctx, c) for every chunk c in [0, chunks), on the calling thread
// and up to threads - 1 persistent helper threads (started on first use,
// asleep when idle), and returns once every chunk has run. threads <= 1 or
// chunks <= 1: everything on the calling thread, no helper woken.
// Not reentrant: run must not call shareChunks itself; calls from several
// threads at once are serialised.
void shareChunks(uint32_t chunks, int threads, void (*run)(void* ctx, uint32_t chunk), void* ctx);

}  // namespace rast
