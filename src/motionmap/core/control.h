#pragma once
// Progress and cancellation of one long computation, passed beside the options of every long
// call (features, each map method, metrics, synthesis, the kriging set-up):
//
//   motionmap::Control control(
//       [](double fraction, std::string_view stage) { std::printf("%3.0f%% %s\n", 100 * fraction,
//                                                                 std::string(stage).c_str()); },
//       [&] { return stop_requested.load(); });
//   auto map = motionmap::pipeline::map_clips(clips, options, control);   // may throw Cancelled
//
// A Control is a cheap handle: copies share the caller's two callbacks. A computation made of
// parts hands each part `control.part(begin, end)` or `control.stage(name, begin, end)`, whose
// fractions 0…1 are reported as [begin, end] of the whole, so the caller sees one bar that never
// steps backwards. Both callbacks are only ever called from the thread that made the call (the
// parallel loops report and poll on their calling thread), so a GUI can forward them as they are.
#include <functional>
#include <memory>
#include <string>
#include <string_view>

namespace motionmap {

class Control {
 public:
  /// Overall fraction done (0…1, non-decreasing) and the current stage's name.
  using ProgressFn = std::function<void(double fraction, std::string_view stage)>;
  /// Returns true to stop the computation, which then throws Cancelled.
  using CancelFn = std::function<bool()>;

  /// Reports nothing and never cancels.
  Control() = default;
  explicit Control(ProgressFn progress, CancelFn cancel = {});

  /// The same callbacks for a part of this computation: its fractions 0…1 are this one's
  /// [begin, end], under this control's stage name. Reports nothing by itself.
  Control part(double begin, double end) const;
  /// Starts the stage `name` over [begin, end] of this control's range: reports its start, polls
  /// for cancellation, and returns the control the stage reports through. @throws Cancelled.
  Control stage(std::string_view name, double begin, double end) const;

  /// Reports `fraction` (clamped to 0…1) of this control's range, then polls for cancellation.
  /// Reports closer than 1 % overall to the previous one are skipped (a GUI redraws on each).
  /// @throws Cancelled.
  void update(double fraction) const;
  /// Reports the end of this control's range (never skipped).
  void finish() const;
  /// @throws Cancelled when the cancel callback returns true.
  void check() const;
  /// Whether the cancel callback returns true (false without one).
  bool cancelled() const;
  /// Whether there is a progress callback to report to.
  bool reports() const { return m_shared && m_shared->progress; }

  const std::string& stage_name() const { return m_stage; }

 private:
  struct Shared {
    ProgressFn progress;
    CancelFn cancel;
    double last = -1.0;  // the last overall fraction reported
  };
  void report(double overall, bool force) const;

  std::shared_ptr<Shared> m_shared;
  double m_begin = 0.0;
  double m_end = 1.0;
  std::string m_stage;
};

}  // namespace motionmap
