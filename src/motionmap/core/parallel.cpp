#include "motionmap/core/parallel.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "motionmap/core/error.h"

namespace motionmap {

void parallel_for(int n, const std::function<void(int)>& body, const LoopControl& control) {
  if (n <= 0) return;
  std::atomic<int> next{0};
  std::atomic<int> done{0};
  std::atomic<bool> stop{false};
  std::exception_ptr failure;
  std::mutex failure_mutex;

  auto work = [&](bool is_caller) {
    int last_reported = -1;
    while (!stop.load(std::memory_order_relaxed)) {
      if (is_caller) {
        if (control.cancel && control.cancel()) {
          stop = true;
          break;
        }
        // Report about a hundred times over the loop, not once per item.
        const int d = done.load(std::memory_order_relaxed);
        if (control.progress && d * 100 / n != last_reported) {
          last_reported = d * 100 / n;
          control.progress(static_cast<double>(d) / n);
        }
      }
      const int i = next.fetch_add(1, std::memory_order_relaxed);
      if (i >= n) break;
      try {
        body(i);
      } catch (...) {
        std::lock_guard<std::mutex> lock(failure_mutex);
        if (!failure) failure = std::current_exception();
        stop = true;
      }
      done.fetch_add(1, std::memory_order_relaxed);
    }
  };

  const int threads = std::max(1, std::min<int>(n, static_cast<int>(std::thread::hardware_concurrency())));
  std::vector<std::thread> helpers;
  helpers.reserve(static_cast<std::size_t>(threads - 1));
  for (int t = 1; t < threads; ++t) helpers.emplace_back(work, false);
  work(true);
  for (auto& h : helpers) h.join();

  if (failure) std::rethrow_exception(failure);
  if (stop) throw Cancelled();
  if (control.progress) control.progress(1.0);
}

}  // namespace motionmap
