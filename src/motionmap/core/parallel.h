#pragma once
// Parallel loops for the O(n²) stages (distance matrices, neighbour searches, all-pairs shortest
// paths, dense products) on one process-wide pool of persistent worker threads. Work is claimed
// in increasing order from an atomic counter, so uneven items (row i of a triangle) balance by
// themselves. The calling thread works too and is the only one that reports progress or polls
// for cancellation, so a GUI's callbacks are never called from a pool thread. Results must not
// depend on the thread count: give each item its own output and combine them in item order.
//
// The pool runs one loop at a time. A loop started while it is busy (a second application
// thread, or a loop inside a loop's body) runs on its calling thread alone: same results, no
// deadlock. The pool has worker_count() − 1 threads, started on first use and joined at exit.
#include <functional>

#include "motionmap/core/control.h"

namespace motionmap {

/// Threads the loops use, the caller included: the environment variable MOTIONMAP_THREADS when
/// it holds a number ≥ 1 (read once), else the hardware's thread count (at least 1).
int worker_count();

/// Threads parallel_chunks() uses for `num_chunks` chunks (the size of per-thread scratch).
int worker_count(int num_chunks, bool serial = false);

/// Runs body(c, w) for every chunk c in [0, num_chunks) on up to worker_count(num_chunks)
/// threads, the calling thread included (w = 0; pool threads are w = 1, 2, …, so per-thread
/// scratch space can be indexed by w < worker_count(num_chunks)). Between two of its chunks, and
/// once at the end, the calling thread runs tick(chunks finished so far), which may throw
/// (Cancelled): the other threads then stop claiming chunks, and the exception is rethrown once
/// every chunk they claimed is over. An exception from body is rethrown the same way. Of several,
/// the lowest chunk's is rethrown (a tick's counts as the chunk before it): the one a serial loop
/// meets first, whichever thread met it. Returns when no pool thread is inside body or tick any
/// more. With `serial`, everything runs on the caller.
void parallel_chunks(int num_chunks, const std::function<void(int chunk, int worker)>& body,
                     const std::function<void(int)>& tick = {}, bool serial = false);

/// Calls body(i) for i in [0, n) on up to worker_count() threads; body must be thread-safe for
/// distinct i. Reports the fraction of items done through `control` (throttled) and 1 at the end.
/// @throws Cancelled if control is cancelled (items already started finish first); rethrows the
///         exception of the lowest item that threw (as parallel_chunks()).
void parallel_for(int n, const std::function<void(int)>& body, const Control& control = {});

}  // namespace motionmap
