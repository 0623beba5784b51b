#pragma once
// A minimal parallel loop for the O(n²) stages (distance matrices, all-pairs shortest paths):
// items are handed out one at a time from an atomic counter, so uneven items (row i of a
// triangle) balance by themselves. Progress and cancellation are handled on the calling thread,
// which works too, so a GUI's callbacks are never called from a helper thread.
#include <functional>

namespace motionmap {

struct LoopControl {
  std::function<void(double)> progress;  ///< fraction of items done, 0…1; may be empty
  std::function<bool()> cancel;          ///< polled between items; true stops the loop
};

/// Calls body(i) for i in [0, n) on up to std::thread::hardware_concurrency() threads.
/// body must be thread-safe for distinct i. @throws Cancelled if control.cancel() returned
/// true (items already started finish first); rethrows the first exception a body threw.
void parallel_for(int n, const std::function<void(int)>& body, const LoopControl& control = {});

}  // namespace motionmap
