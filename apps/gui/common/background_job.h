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
#include <exception>
#include <functional>
#include <memory>
#include <thread>

#include <QObject>
#include <QString>

#include "motionmap/core/control.h"
#include "motionmap/core/error.h"

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

/// What a job's work ended with: its value, an error message, or a cancel.
template <class T>
struct JobOutcome {
  std::shared_ptr<T> value;  ///< set when the work finished
  QString error;             ///< what it threw, when it failed
  bool cancelled = false;
};

/// The body of a job's thread: runs work(control), where `control` forwards progress to
/// `receiver`'s thread as report(fraction, stage) while the job is still wanted and cancels when
/// the ticket is cancelled; then, on receiver's thread and only if the job is still wanted, joins
/// the job's thread and calls done(outcome).
template <class T>
void runJob(QObject* receiver, BackgroundJob& job, const BackgroundJob::Ticket& ticket,
            std::function<void(double, const QString&)> report,
            std::function<std::shared_ptr<T>(const Control&)> work,
            std::function<void(const JobOutcome<T>&)> done) {
  const int generation = ticket.generation;
  JobOutcome<T> outcome;
  try {
    const Control control(
        [receiver, &job, generation, report](double fraction, std::string_view stage) {
          const QString text = QString::fromUtf8(stage.data(), qsizetype(stage.size()));
          QMetaObject::invokeMethod(
              receiver,
              [&job, generation, report, fraction, text] {
                if (job.current(generation)) report(fraction, text);
              },
              Qt::QueuedConnection);
        },
        [ticket] { return ticket.cancelled(); });
    outcome.value = work(control);
    if (ticket.cancelled()) throw Cancelled();
  } catch (const Cancelled&) {
    outcome.value.reset();
    outcome.cancelled = true;
  } catch (const std::exception& e) {
    outcome.value.reset();
    outcome.error = QString::fromStdString(e.what());
  }
  QMetaObject::invokeMethod(
      receiver,
      [&job, generation, outcome, done] {
        if (!job.current(generation)) return;  // stopped, or replaced by a newer job
        job.finish();
        done(outcome);
      },
      Qt::QueuedConnection);
}

}  // namespace motionmap::studio
