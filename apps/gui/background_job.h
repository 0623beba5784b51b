#pragma once
// One background computation at a time, for work the GUI thread must not wait for (a map, a
// synthesized motion): its worker thread, its cancel flag, and a generation number that tells the
// results it queues to the GUI thread from those of a newer job.
//
//   m_job.start([this](const BackgroundJob::Ticket& t) {
//     auto result = compute([&] { return t.cancelled(); });
//     QMetaObject::invokeMethod(this, [this, g = t.generation, result] {
//       if (!m_job.current(g)) return;  // stopped, or replaced by a newer job
//       m_job.finish();
//       show(result);
//     }, Qt::QueuedConnection);
//   });
#include <atomic>
#include <functional>
#include <memory>
#include <thread>

namespace motionmap::studio {

class BackgroundJob {
 public:
  /// What a job's thread is given.
  struct Ticket {
    std::shared_ptr<const std::atomic<bool>> cancel;
    int generation = 0;
    bool cancelled() const { return cancel->load(); }
  };

  BackgroundJob() = default;
  BackgroundJob(const BackgroundJob&) = delete;
  BackgroundJob& operator=(const BackgroundJob&) = delete;
  ~BackgroundJob() { stop(); }

  /// Stops a running job (see stop()), then runs work(ticket) on a new thread.
  void start(std::function<void(const Ticket&)> work) {
    stop();
    m_cancel = std::make_shared<std::atomic<bool>>(false);
    m_thread = std::thread(std::move(work), Ticket{m_cancel, ++m_generation});
  }

  /// Asks a running job to stop, waits for its thread, and makes the results it queued stale.
  /// Returns whether a job was running.
  bool stop() {
    if (!m_thread.joinable()) return false;
    m_cancel->store(true);
    m_thread.join();
    ++m_generation;
    return true;
  }

  /// Joins the thread of a job whose result has arrived (the thread is ending).
  void finish() {
    if (m_thread.joinable()) m_thread.join();
  }

  bool running() const { return m_thread.joinable(); }
  /// Whether results of the job with this generation are still wanted.
  bool current(int generation) const { return generation == m_generation; }

 private:
  std::thread m_thread;
  std::shared_ptr<std::atomic<bool>> m_cancel;
  int m_generation = 0;
};

}  // namespace motionmap::studio
