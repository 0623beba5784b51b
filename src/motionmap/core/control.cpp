#include "motionmap/core/control.h"

#include <algorithm>

#include "motionmap/core/error.h"

namespace motionmap {

Control::Control(ProgressFn progress, CancelFn cancel)
    : m_shared(std::make_shared<Shared>(Shared{std::move(progress), std::move(cancel)})) {}

Control Control::part(double begin, double end) const {
  Control sub = *this;
  begin = std::clamp(begin, 0.0, 1.0);
  end = std::clamp(end, begin, 1.0);
  sub.m_begin = m_begin + begin * (m_end - m_begin);
  sub.m_end = m_begin + end * (m_end - m_begin);
  return sub;
}

Control Control::stage(std::string_view name, double begin, double end) const {
  Control sub = part(begin, end);
  sub.m_stage = std::string(name);
  sub.report(sub.m_begin, true);
  sub.check();
  return sub;
}

void Control::update(double fraction) const {
  report(m_begin + std::clamp(fraction, 0.0, 1.0) * (m_end - m_begin), false);
  check();
}

void Control::finish() const {
  report(m_end, true);
}

void Control::check() const {
  if (cancelled()) throw Cancelled();
}

bool Control::cancelled() const {
  return m_shared && m_shared->cancel && m_shared->cancel();
}

void Control::report(double overall, bool force) const {
  if (!reports()) return;
  Shared& s = *m_shared;
  // Never step backwards, and skip reports too close to the previous one.
  overall = std::clamp(overall, std::max(s.last, 0.0), 1.0);
  if (!force && overall < s.last + 0.01) return;
  if (force && overall == s.last && overall == 1.0) return;
  s.last = overall;
  s.progress(overall, m_stage);
}

}  // namespace motionmap
