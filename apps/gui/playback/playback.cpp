#include "playback/playback.h"

#include <algorithm>
#include <cmath>

namespace motionmap::studio {

Playback::Playback(QObject* parent) : QObject(parent) {
  m_elapsed.start();
  m_clock = [this] { return double(m_elapsed.nsecsElapsed()) * 1e-9; };
  m_timer.setTimerType(Qt::PreciseTimer);
  connect(&m_timer, &QTimer::timeout, this, &Playback::tick);
}

void Playback::setMotion(int frames, double frameTime) {
  const int before = m_frames;
  const double timeBefore = m_frameTime;
  m_frames = std::max(0, frames);
  m_frameTime = frameTime;
  // In/out points belong to a motion: another length or rate is another motion.
  const bool hadRange = m_in || m_out;
  if (m_frames != before || m_frameTime != timeBefore) {
    m_in.reset();
    m_out.reset();
  }
  if (m_frames != before) emit frameCountChanged(m_frames);
  if (m_frames != before || hadRange != bool(m_in || m_out)) emit rangeChanged();
}

void Playback::setClock(Clock clock) {
  m_clock = std::move(clock);
  anchor();
}

void Playback::anchor() {
  m_startFrame = m_frame;
  m_startTime = m_clock();
}

void Playback::show(int frame) {
  if (m_frames <= 0) return;
  m_frame = std::clamp(frame, 0, m_frames - 1);
  emit frameChanged(m_frame);
}

void Playback::setFrame(int frame) {
  show(frame);
  anchor();  // a jump while playing goes on from there
}

void Playback::step(int delta) {
  pause();
  setFrame(m_frame + delta);
}

void Playback::goToStart() {
  setFrame(m_frame != rangeStart() ? rangeStart() : 0);
}

void Playback::goToEnd() {
  setFrame(m_frame != rangeEnd() ? rangeEnd() : m_frames - 1);
}

void Playback::setInPoint(int frame) {
  if (m_frames <= 0) return;
  m_in = std::clamp(frame, 0, m_frames - 1);
  if (m_out && *m_out < *m_in) m_out.reset();
  emit rangeChanged();
}

void Playback::setOutPoint(int frame) {
  if (m_frames <= 0) return;
  m_out = std::clamp(frame, 0, m_frames - 1);
  if (m_in && *m_in > *m_out) m_in.reset();
  emit rangeChanged();
}

void Playback::clearInPoint() {
  if (!m_in) return;
  m_in.reset();
  emit rangeChanged();
}

void Playback::clearOutPoint() {
  if (!m_out) return;
  m_out.reset();
  emit rangeChanged();
}

int Playback::rangeStart() const {
  return m_in.value_or(0);
}

int Playback::rangeEnd() const {
  return m_out.value_or(std::max(0, m_frames - 1));
}

void Playback::play() {
  const int first = rangeStart();
  const int last = rangeEnd();
  if (m_frames < 2 || last <= first) return;
  // Outside the range, or stopped at its end without loop: play the range from its start.
  if (m_frame < first || m_frame > last || (!m_loop && m_frame >= last)) show(first);
  anchor();
  m_timer.setInterval(std::clamp(int(std::lround(m_frameTime * 1000.0 / m_speed)), 1, kMaxTickMs));
  const bool wasPlaying = isPlaying();
  m_timer.start();
  if (!wasPlaying) emit playingChanged(true);
}

void Playback::pause() {
  const bool wasPlaying = isPlaying();
  m_timer.stop();
  if (wasPlaying) emit playingChanged(false);
}

void Playback::setSpeed(double speed) {
  const double before = m_speed;
  m_speed = std::clamp(std::isfinite(speed) ? speed : 1.0, 0.05, 8.0);
  if (isPlaying()) play();  // re-anchors the clock at the current frame
  if (m_speed != before) emit speedChanged(m_speed);
}

void Playback::setLoop(bool loop) {
  if (loop == m_loop) return;
  m_loop = loop;
  emit loopChanged(loop);
}

void Playback::tick() {
  if (m_frames == 0) return pause();
  // The frame is the clock's, so playback keeps the motion's rate whatever the tick rate.
  const double elapsed = m_clock() - m_startTime;
  const long long target = m_startFrame + (long long)std::floor(elapsed * m_speed / m_frameTime);
  const int first = rangeStart();
  const int last = rangeEnd();
  if (target <= last) {
    if (target != m_frame) show(int(target));
  } else if (m_loop) {
    // Back to the in point, keeping the clock's phase (target > last >= first).
    show(int(first + (target - first) % (last - first + 1)));
  } else {
    show(last);
    pause();
  }
}

}  // namespace motionmap::studio
