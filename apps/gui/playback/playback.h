#pragma once
// The playback clock of the motion shown: the current frame, play/pause, speed, loop and an
// in/out range. While playing, a timer ticks at least every 16 ms and the frame shown is the one
// the clock has reached (start frame + elapsed × speed ÷ frame time), never a count of ticks, so
// playback keeps the motion's rate whatever the tick rate. Playing and looping stay within the
// in/out range (the whole motion when none is set); stepping and jumps may go anywhere. No
// widgets: the window shows frameChanged.
//
//   Playback playback;
//   connect(&playback, &Playback::frameChanged, [&](int f) { view.setPose(motion, f); });
//   playback.setMotion(motion.num_frames, motion.frame_time);
//   playback.setFrame(0);
//   playback.play();
#include <functional>
#include <optional>

#include <QElapsedTimer>
#include <QObject>
#include <QTimer>

namespace motionmap::studio {

class Playback : public QObject {
  Q_OBJECT
 public:
  /// Seconds since an arbitrary start, never decreasing.
  using Clock = std::function<double()>;
  /// Ticks at least this often (ms), so a 30 fps clip at 1× still repaints at 60 Hz when sped up.
  static constexpr int kMaxTickMs = 16;

  explicit Playback(QObject* parent = nullptr);

  /// The motion played: `frames` frames, `frameTime` seconds apart. The frame number stays (the
  /// next setFrame clamps it); frameCountChanged is emitted when the count changes. The in/out
  /// points stay while the count and the frame time stay (the window tells the same clip again
  /// when clips join its map), and are cleared for a motion of another length or rate.
  void setMotion(int frames, double frameTime);
  int frameCount() const { return m_frames; }
  double frameTime() const { return m_frameTime; }

  int frame() const { return m_frame; }
  /// Shows `frame` (clamped to the motion; nothing without frames) and, while playing, goes on
  /// from there. frameChanged is emitted even when the number stays: the motion behind it may
  /// be another one.
  void setFrame(int frame);
  /// Pauses and moves `delta` frames (the arrow keys), anywhere in the motion.
  void step(int delta);
  /// Home: to the first frame of the in/out range; from there (or without an in point) to the
  /// motion's first frame. Goes on playing when playing.
  void goToStart();
  /// End: to the last frame of the range; from there (or without an out point) to the motion's
  /// last frame. Goes on playing when playing.
  void goToEnd();

  /// The in point (I): playback starts and loops back here. An out point before it is cleared.
  void setInPoint(int frame);
  /// The out point (O): playback stops or loops here. An in point after it is cleared.
  void setOutPoint(int frame);
  void clearInPoint();
  void clearOutPoint();
  std::optional<int> inPoint() const { return m_in; }
  std::optional<int> outPoint() const { return m_out; }
  /// The frames playback stays within: [in point or 0, out point or the last frame].
  int rangeStart() const;
  int rangeEnd() const;

  /// Plays from the current frame; from the range's start when the frame is outside the range,
  /// or stopped at its end without loop. Needs a range of two frames or more.
  void play();
  void pause();
  bool isPlaying() const { return m_timer.isActive(); }
  /// 1 = the motion's frame rate; clamped to [0.05, 8] (not finite: 1).
  void setSpeed(double speed);
  double speed() const { return m_speed; }
  /// Whether playback starts over at the range's end (else it stops on its last frame).
  void setLoop(bool loop);
  bool loop() const { return m_loop; }

  /// Shows the frame the clock has reached (the timer calls it while playing).
  void tick();
  /// Replaces the clock (tests: a clock they advance by hand). The default is a QElapsedTimer.
  void setClock(Clock clock);
  /// The timer's interval while playing (ms).
  int tickInterval() const { return m_timer.interval(); }

 signals:
  /// The frame shown (see setFrame).
  void frameChanged(int frame);
  void frameCountChanged(int frames);
  void playingChanged(bool playing);
  void speedChanged(double speed);
  void loopChanged(bool loop);
  /// The in or out point was set or cleared, or the motion changed (rangeStart(), rangeEnd()).
  void rangeChanged();

 private:
  /// Sets and emits `frame` (clamped), without touching the clock's anchor.
  void show(int frame);
  /// Playing from here: the clock's anchor is now and the current frame.
  void anchor();

  int m_frames = 0;
  double m_frameTime = 1.0 / 30.0;
  int m_frame = 0;
  std::optional<int> m_in;   ///< the in point (I), within the motion
  std::optional<int> m_out;  ///< the out point (O), within the motion, never before m_in
  double m_speed = 1.0;
  bool m_loop = true;
  QTimer m_timer;
  QElapsedTimer m_elapsed;  ///< the default clock
  Clock m_clock;
  double m_startTime = 0.0;  ///< the clock at play() or the last jump
  int m_startFrame = 0;      ///< the frame then
};

}  // namespace motionmap::studio
