#include "motionmap/core/parallel.h"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "motionmap/core/error.h"

namespace motionmap {

namespace {

int configured_workers() {
  if (const char* env = std::getenv("MOTIONMAP_THREADS")) {
    try {
      const int n = std::stoi(env);
      if (n >= 1) return std::min(n, 1024);
    } catch (const std::exception&) {
      // not a number: fall back to the hardware's count
    }
  }
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

// One loop in flight: its chunks, who claims the next one, and the failure of the lowest chunk
// that failed. Chunks are claimed in increasing order and a claimed chunk runs to its end, so
// every chunk below a failed one has run when the loop returns: the failure kept is the one a
// serial loop would have met first, whichever thread met it.
struct Job {
  int num_chunks = 0;
  int threads = 1;  // workers 0 … threads − 1 take part
  const std::function<void(int, int)>* body = nullptr;
  std::atomic<int> next{0};
  std::atomic<int> done{0};
  std::atomic<bool> stop{false};
  std::mutex error_mutex;
  std::exception_ptr error;
  int error_chunk = 0;

  void fail(int chunk, std::exception_ptr e) {
    std::lock_guard<std::mutex> lock(error_mutex);
    if (!error || chunk < error_chunk) {
      error = e;
      error_chunk = chunk;
    }
    stop = true;
  }

  // Claims and runs chunks until none is left or the loop stops; the caller (worker 0) ticks
  // after each of its chunks.
  void work(int worker, const std::function<void(int)>* tick) {
    while (!stop) {
      const int c = next.fetch_add(1);
      if (c >= num_chunks) break;
      try {
        (*body)(c, worker);
        done.fetch_add(1);
        if (tick && *tick) (*tick)(done.load());
      } catch (...) {
        fail(c, std::current_exception());
        break;
      }
    }
  }
};

// The persistent workers. A loop is posted as the current job; each pool thread that wakes while
// it is posted joins it (once), and the caller takes it down and waits until every thread that
// joined has left before its stack frame (body, tick, the job) goes away.
class Pool {
 public:
  explicit Pool(int threads) {
    for (int w = 1; w < threads; ++w) m_threads.emplace_back([this, w] { run(w); });
  }
  ~Pool() {
    {
      std::lock_guard<std::mutex> lock(m_mutex);
      m_stopping = true;
    }
    m_wake.notify_all();
    for (auto& t : m_threads) t.join();
  }
  Pool(const Pool&) = delete;
  Pool& operator=(const Pool&) = delete;

  // Runs `job` on the pool and the calling thread; false (nothing run) when the pool is busy.
  bool run_job(Job& job, const std::function<void(int)>& tick) {
    // Not a mutex: the caller's own body may start a loop, which must find the pool busy.
    if (m_busy.exchange(true)) return false;
    struct Release {
      std::atomic<bool>& flag;
      ~Release() { flag.store(false); }
    } release{m_busy};
    {
      std::lock_guard<std::mutex> lock(m_mutex);
      m_job = &job;
      ++m_generation;
    }
    m_wake.notify_all();
    job.work(0, &tick);
    job.next.store(job.num_chunks);  // close the queue
    std::unique_lock<std::mutex> lock(m_mutex);
    m_job = nullptr;  // threads not yet awake find nothing
    m_left.wait(lock, [this] { return m_inside == 0; });
    return true;
  }

 private:
  void run(int worker) {
    std::uint64_t seen = 0;
    std::unique_lock<std::mutex> lock(m_mutex);
    for (;;) {
      m_wake.wait(lock, [&] { return m_stopping || (m_job && m_generation != seen); });
      if (m_stopping) return;
      seen = m_generation;
      Job* job = m_job;
      if (worker >= job->threads) continue;
      ++m_inside;
      lock.unlock();
      job->work(worker, nullptr);
      lock.lock();
      if (--m_inside == 0) m_left.notify_all();
    }
  }

  std::atomic<bool> m_busy{false};  // a loop is running on the pool
  std::mutex m_mutex;
  std::condition_variable m_wake;
  std::condition_variable m_left;
  Job* m_job = nullptr;
  std::uint64_t m_generation = 0;
  int m_inside = 0;  // pool threads inside the current job
  bool m_stopping = false;
  std::vector<std::thread> m_threads;
};

Pool& pool() {
  static Pool instance(worker_count());
  return instance;
}

}  // namespace

int worker_count() {
  static const int count = configured_workers();
  return count;
}

int worker_count(int num_chunks, bool serial) {
  return serial ? 1 : std::max(1, std::min(worker_count(), num_chunks));
}

void parallel_chunks(int num_chunks, const std::function<void(int, int)>& body,
                     const std::function<void(int)>& tick, bool serial) {
  if (num_chunks <= 0) return;
  Job job;
  job.num_chunks = num_chunks;
  job.threads = worker_count(num_chunks, serial);
  job.body = &body;
  if (job.threads == 1 || !pool().run_job(job, tick)) {
    job.threads = 1;
    job.work(0, &tick);
  }
  if (job.error) std::rethrow_exception(job.error);
  // Once more at the end, so that a loop whose chunks all ran on pool threads (short chunks, a
  // caller slow to get a core) still reports and polls for cancellation.
  if (tick) tick(job.done.load());
}

void parallel_for(int n, const std::function<void(int)>& body, const Control& control) {
  if (n <= 0) return;
  control.check();
  parallel_chunks(
      n, [&](int i, int) { body(i); }, [&](int done) { control.update(double(done) / n); });
  control.finish();
}

}  // namespace motionmap
