#include "playback.h"

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
  m_frames = std::max(0, frames);
  m_frameTime = frameTime;
  if (m_frames != before) emit frameCountChanged(m_frames);
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

void Playback::play() {
  if (m_frames < 2) return;
  if (!m_loop && m_frame >= m_frames - 1) show(0);  // play again from the start
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
  if (target < m_frames) {
    if (target != m_frame) show(int(target));
  } else if (m_loop) {
    show(int(target % m_frames));
  } else {
    show(m_frames - 1);
    pause();
  }
}

}  // namespace motionmap::studio
