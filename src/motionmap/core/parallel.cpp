#include "motionmap/core/parallel.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "motionmap/core/error.h"

namespace motionmap {

int worker_count() { return static_cast<int>(std::max(1u, std::thread::hardware_concurrency())); }

int worker_count(int num_chunks, bool serial) {
  return serial ? 1 : std::max(1, std::min(worker_count(), num_chunks));
}

void parallel_chunks(int num_chunks, const std::function<void(int, int)>& body,
                     const std::function<void(int)>& tick, bool serial) {
  if (num_chunks <= 0) return;
  const int threads = worker_count(num_chunks, serial);
  // Shared with the helper threads, which may outlive this call: on a busy machine a new thread
  // can wait milliseconds for a core, and the caller does not wait for one that has not claimed
  // a chunk by the time every chunk is claimed. Such a late helper finds nothing left and exits
  // without touching body or tick; only the chunks it did claim are waited for.
  struct State {
    std::atomic<int> next{0};      // next chunk to claim
    std::atomic<int> done{0};      // chunks run to completion
    std::atomic<int> finished{0};  // claimed chunks that are over (run, failed or skipped)
    std::atomic<bool> stop{false};
    std::mutex error_mutex;
    std::exception_ptr error;
    void fail(std::exception_ptr e) {
      std::lock_guard<std::mutex> lock(error_mutex);
      if (!error) error = e;
      stop = true;
    }
  };
  const auto state = std::make_shared<State>();
  auto work = [state, num_chunks, &body, &tick](int worker) {
    State& st = *state;
    const bool caller = worker == 0;
    while (!st.stop) {
      const int c = st.next.fetch_add(1);
      if (c >= num_chunks) break;
      bool ok = false;
      if (!st.stop) {
        try {
          body(c, worker);
          ok = true;
        } catch (...) {
          st.fail(std::current_exception());
        }
      }
      if (ok) st.done.fetch_add(1);
      st.finished.fetch_add(1);
      st.finished.notify_all();
      if (!ok) break;
      if (caller && tick) {
        try {
          tick(st.done.load());
        } catch (...) {
          st.fail(std::current_exception());
          break;
        }
      }
    }
  };

  std::vector<std::thread> helpers;
  helpers.reserve(static_cast<std::size_t>(threads - 1));
  try {
    for (int t = 1; t < threads; ++t) helpers.emplace_back(work, t);
  } catch (...) {
    state->fail(std::current_exception());  // could not start a thread: stop the ones running
  }
  work(0);
  // Close the queue (later claims get numbers ≥ num_chunks), then wait for the claimed chunks.
  const int claimed = std::min(state->next.exchange(num_chunks), num_chunks);
  for (int f = state->finished.load(); f < claimed; f = state->finished.load()) {
    state->finished.wait(f);
  }
  for (auto& h : helpers) h.detach();
  if (state->error) std::rethrow_exception(state->error);
  // Once more at the end, so that a loop whose chunks all ran on helpers (short chunks, a caller
  // slow to get a core) still reports and polls for cancellation.
  if (tick) tick(state->done.load());
}

void parallel_for(int n, const std::function<void(int)>& body, const LoopControl& control) {
  if (n <= 0) return;
  if (control.cancel && control.cancel()) throw Cancelled();
  int last_reported = -1;
  auto tick = [&](int done) {
    if (control.cancel && control.cancel()) throw Cancelled();
    // About a hundred reports over the loop, not one per item.
    const int percent = static_cast<int>(static_cast<long long>(done) * 100 / n);
    if (control.progress && percent != last_reported) {
      last_reported = percent;
      control.progress(static_cast<double>(done) / n);
    }
  };
  parallel_chunks(n, [&](int i, int) { body(i); }, tick);
  if (control.progress) control.progress(1.0);
}

}  // namespace motionmap
