#include "motionmap/core/parallel.h"

#include <algorithm>
#include <atomic>
#include <exception>
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
  std::atomic<int> next{0};
  std::atomic<int> done{0};
  std::atomic<bool> stop{false};
  std::exception_ptr error;
  std::mutex error_mutex;

  auto fail = [&](std::exception_ptr e) {
    std::lock_guard<std::mutex> lock(error_mutex);
    if (!error) error = e;
    stop = true;
  };
  auto work = [&](int worker) {
    const bool caller = worker == 0;
    while (!stop) {
      const int c = next.fetch_add(1);
      if (c >= num_chunks) break;
      try {
        body(c, worker);
      } catch (...) {
        fail(std::current_exception());
        break;
      }
      done.fetch_add(1);
      if (caller && tick) {
        try {
          tick(done.load());
        } catch (...) {
          fail(std::current_exception());
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
    fail(std::current_exception());  // could not start a thread: stop the ones running
  }
  work(0);
  for (auto& h : helpers) h.join();
  if (error) std::rethrow_exception(error);
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
