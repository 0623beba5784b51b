#pragma once
// A minimal parallel loop over numbered chunks with std::thread, for the O(F²) loops of the
// embedding routines. Results must not depend on the thread count: callers give each chunk its
// own output and combine them in chunk order.
#include <functional>

namespace motionmap::embed {

/// Worker threads used by the embedding loops: the hardware's thread count (at least 1).
int worker_count();

/// Threads parallel_chunks will use for `num_chunks` chunks (the size of per-thread scratch).
int worker_count(int num_chunks, bool serial = false);

/// Runs body(c, w) for every chunk c in [0, num_chunks) on up to worker_count() threads, the
/// calling thread included (w = 0; helpers are w = 1, 2, …, so per-thread scratch space can be
/// indexed by w); chunks are claimed in increasing order. Between two of its chunks
/// the calling thread runs tick(chunks finished so far), which may throw (Cancelled): the other
/// threads then stop claiming chunks, and the exception is rethrown after all have joined. An
/// exception from body is rethrown the same way. With `serial`, everything runs on the caller.
void parallel_chunks(int num_chunks, const std::function<void(int chunk, int worker)>& body,
                     const std::function<void(int)>& tick = {}, bool serial = false);

}  // namespace motionmap::embed
