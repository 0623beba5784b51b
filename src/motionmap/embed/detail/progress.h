#pragma once
// Stage bookkeeping for one embedding: the stage timings of Embedding::timings, and the Control
// each stage reports through. Used only from the calling thread.
#include <chrono>
#include <string>
#include <string_view>
#include <vector>

#include "motionmap/core/control.h"
#include "motionmap/embed/types.h"

namespace motionmap::embed {

class Progress {
 public:
  /// No callbacks, no timings: for calling routines directly (tests, benchmarks).
  Progress() = default;
  /// Reports through `control` and appends stage times to `timings` (may be null).
  Progress(const Control& control, std::vector<StageTime>* timings);
  ~Progress() = default;
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  /// Ends the current stage (recording its time) and starts `name`, which covers the overall
  /// fractions [begin, end]. @throws Cancelled.
  void stage(std::string_view name, double begin, double end);
  /// Reports `fraction` (0 … 1) of the current stage. @throws Cancelled.
  void update(double fraction) const { m_current.update(fraction); }
  /// Polls for cancellation. @throws Cancelled.
  void check_cancel() const { m_current.check(); }
  /// The current stage's control, for the routines it calls.
  const Control& control() const { return m_current; }
  /// Ends the last stage and reports 1.0.
  void finish();

 private:
  void end_stage();

  Control m_whole;
  Control m_current;
  std::vector<StageTime>* m_timings = nullptr;
  bool m_running = false;
  std::chrono::steady_clock::time_point m_start;
};

}  // namespace motionmap::embed
