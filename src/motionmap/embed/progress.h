#pragma once
// Stage bookkeeping for one embedding: stage timings, the caller's progress callback (kept
// non-decreasing) and its cancel callback. Used only from the calling thread.
#include <chrono>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "motionmap/embed/embed.h"

namespace motionmap::embed {

class Progress {
 public:
  /// No callbacks, no timings: for calling routines directly (tests, benchmarks).
  Progress() = default;
  /// Reports through options.progress / options.cancel and appends stage times to `timings`.
  Progress(const EmbedOptions& options, std::vector<StageTime>* timings);
  ~Progress() = default;
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  /// Ends the current stage (recording its time) and starts `name`, which covers the overall
  /// fractions [begin, end]. @throws Cancelled.
  void stage(std::string_view name, double begin, double end);
  /// Reports `fraction` (0 … 1) of the current stage; throttled to about every 0.5 % overall.
  /// @throws Cancelled.
  void update(double fraction);
  /// Polls the cancel callback. @throws Cancelled.
  void check_cancel() const;
  /// Ends the last stage and reports 1.0.
  void finish();

 private:
  void end_stage();
  void report(double overall, bool force);

  std::function<void(double, std::string_view)> m_progress;
  std::function<bool()> m_cancel;
  std::vector<StageTime>* m_timings = nullptr;
  std::string m_stage;
  double m_begin = 0.0;
  double m_end = 0.0;
  double m_last = -1.0;
  bool m_running = false;
  std::chrono::steady_clock::time_point m_start;
};

}  // namespace motionmap::embed
