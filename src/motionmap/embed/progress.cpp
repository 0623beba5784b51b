#include "motionmap/embed/progress.h"

#include <algorithm>

#include "motionmap/core/error.h"

namespace motionmap::embed {

Progress::Progress(const EmbedOptions& options, std::vector<StageTime>* timings)
    : m_progress(options.progress), m_cancel(options.cancel), m_timings(timings) {}

void Progress::stage(std::string_view name, double begin, double end) {
  end_stage();
  m_stage = std::string(name);
  m_begin = begin;
  m_end = std::max(begin, end);
  m_running = true;
  m_start = std::chrono::steady_clock::now();
  report(begin, true);
  check_cancel();
}

void Progress::update(double fraction) {
  report(m_begin + std::clamp(fraction, 0.0, 1.0) * (m_end - m_begin), false);
  check_cancel();
}

void Progress::check_cancel() const {
  if (m_cancel && m_cancel()) throw Cancelled();
}

void Progress::finish() {
  end_stage();
  report(1.0, true);
}

void Progress::end_stage() {
  if (!m_running) return;
  m_running = false;
  if (m_timings) {
    const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - m_start;
    m_timings->push_back({m_stage, elapsed.count()});
  }
}

void Progress::report(double overall, bool force) {
  if (!m_progress) return;
  // Never step backwards, and skip reports too close to the previous one: a GUI redraws on each.
  overall = std::clamp(overall, std::max(m_last, 0.0), 1.0);
  if (!force && overall < m_last + 0.005) return;
  if (force && overall == m_last && overall == 1.0) return;
  m_last = overall;
  m_progress(overall, m_stage);
}

}  // namespace motionmap::embed
