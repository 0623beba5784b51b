#pragma once
// Parallel loops for the O(n²) stages (distance matrices, neighbour searches, all-pairs shortest
// paths, dense products) with std::thread. Work is claimed in increasing order from an atomic
// counter, so uneven items (row i of a triangle) balance by themselves. The calling thread works
// too and is the only one that reports progress or polls for cancellation, so a GUI's callbacks
// are never called from a helper thread. Results must not depend on the thread count: give each
// item its own output and combine them in item order.
#include <functional>

namespace motionmap {

struct LoopControl {
  std::function<void(double)> progress;  ///< fraction of items done, 0…1; may be empty
  std::function<bool()> cancel;          ///< polled between items; true stops the loop
};

/// Threads the loops use: the hardware's thread count (at least 1).
int worker_count();

/// Threads parallel_chunks() uses for `num_chunks` chunks (the size of per-thread scratch).
int worker_count(int num_chunks, bool serial = false);

/// Runs body(c, w) for every chunk c in [0, num_chunks) on up to worker_count() threads, the
/// calling thread included (w = 0; helpers are w = 1, 2, …, so per-thread scratch space can be
/// indexed by w). Between two of its chunks, and once at the end, the calling thread runs
/// tick(chunks finished so far), which may throw (Cancelled): the other threads then stop
/// claiming chunks, and the exception is rethrown once every chunk they claimed is over. An
/// exception from body is rethrown the same way. Returns as soon as every chunk is done: a helper
/// thread the system has not started by then is left to exit by itself (it runs nothing). With
/// `serial`, everything runs on the caller.
void parallel_chunks(int num_chunks, const std::function<void(int chunk, int worker)>& body,
                     const std::function<void(int)>& tick = {}, bool serial = false);

/// Calls body(i) for i in [0, n) on up to worker_count() threads; body must be thread-safe for
/// distinct i. Progress is reported about a hundred times, and 1 at the end.
/// @throws Cancelled if control.cancel() returned true (items already started finish first);
///         rethrows the first exception a body threw.
void parallel_for(int n, const std::function<void(int)>& body, const LoopControl& control = {});

}  // namespace motionmap
