#include "motionmap/embed/detail/progress.h"

namespace motionmap::embed {

Progress::Progress(const Control& control, std::vector<StageTime>* timings)
    : m_whole(control), m_current(control), m_timings(timings) {}

void Progress::stage(std::string_view name, double begin, double end) {
  end_stage();
  m_current = m_whole.stage(name, begin, end);
  m_running = true;
  m_start = std::chrono::steady_clock::now();
}

void Progress::finish() {
  end_stage();
  m_current.finish();  // under the last stage's name
  m_whole.finish();    // (skipped when that stage already ended at 1)
}

void Progress::end_stage() {
  if (!m_running) return;
  m_running = false;
  if (m_timings) {
    const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - m_start;
    m_timings->push_back({m_current.stage_name(), elapsed.count()});
  }
}

}  // namespace motionmap::embed
