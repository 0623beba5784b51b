#pragma once
// Sketches become motions: synth::synthesize along a map path on a worker thread, with progress
// and cancel through the library's Control, reported by Qt signals on the controller's thread.
// It keeps the last motion made and the map it was sketched on (its blender's skeleton is the
// motion's). No widgets: the window shows what the signals say, and tests drive it with an event
// loop alone.
//
//   SynthesisController synthesis;
//   connect(&synthesis, &SynthesisController::finished, [&] { play(synthesis.result()->motion); });
//   synthesis.start(maps.current(), sketch, synthParameters);
#include <memory>
#include <optional>
#include <utility>

#include <QObject>
#include <QString>

#include "common/background_job.h"
#include "common/parameters.h"
#include "map/map_controller.h"
#include "motionmap/synth/synthesize.h"
#include "takes/takes.h"

namespace motionmap::studio {

class SynthesisController : public QObject {
  Q_OBJECT
 public:
  explicit SynthesisController(QObject* parent = nullptr);
  /// Stops a running synthesis (waits for its worker).
  ~SynthesisController() override;

  /// Starts synthesizing the motion along `path` on `map` with `parameters.motion`, keeping the
  /// path's times only when parameters.timedAsDrawn, on the worker thread. A synthesis still
  /// running is stopped first (a newer sketch replaces it). progress, then finished, failed or
  /// cancelled follow. False (nothing started) without a map or its blender. `take` tags the
  /// result (resultTake()): −1 for a new sketch, else the id of the take being re-synthesized.
  bool start(std::shared_ptr<const MapResult> map, const synth::MapPath& path,
             const SynthParameters& parameters, int take = -1) {
    return start(MapSupply{std::move(map), {}}, path, parameters, take);
  }
  /// The same on the map `map` supplies: one not ready yet (a saved map's blender, built on
  /// first use) is made on the worker first, within the synthesis' progress and cancel; an error
  /// making it (a clip of a saved map missing) is failed(). resultMap() is the map made.
  bool start(MapSupply map, const synth::MapPath& path, const SynthParameters& parameters,
             int take = -1);
  /// Starts re-making the motion `previous` of take `take` along its edited `path` (a control
  /// point moved), as start() does, but when `previous` was synthesized on `map` with
  /// `parameters.motion` only the part of the motion the edit changes is re-made
  /// (synth::edit_path: the frames outside resultWindow() stay bit for bit); otherwise the whole
  /// path is synthesized.
  bool startEdit(std::shared_ptr<const MapResult> map,
                 std::shared_ptr<const synth::SynthResult> previous, const synth::MapPath& path,
                 const SynthParameters& parameters, int take);
  /// Starts in-betweening `keys` (≥ 2) on `map` (synth::inbetween, with `parameters.motion`'s
  /// foot clean-up), on the worker thread, as start() does: the result's path is the route its
  /// frames follow (a point per frame, timed at the frame rate) and resultKeys() and
  /// resultKeyFrames() say where the keys fell. `take` as for start().
  bool startInbetween(std::shared_ptr<const MapResult> map, TakeKeys keys,
                      const SynthParameters& parameters, int take = -1) {
    return startInbetween(MapSupply{std::move(map), {}}, std::move(keys), parameters, take);
  }
  bool startInbetween(MapSupply map, TakeKeys keys, const SynthParameters& parameters,
                      int take = -1);
  bool isRunning() const { return m_job.running(); }
  /// Stops a running synthesis without a signal; its result is dropped. Returns whether one
  /// was running.
  bool stop();
  /// Stops a running synthesis and emits cancelled() (nothing when none is running). The last
  /// motion stays.
  void cancel();

  /// The last motion synthesized (nullptr before the first, or after clear()).
  const synth::SynthResult* result() const { return m_result.get(); }
  /// The same, shared (a take keeps it without a copy).
  const std::shared_ptr<const synth::SynthResult>& sharedResult() const { return m_result; }
  /// The path result() follows, as given to start() (its times even when not timed as drawn).
  const synth::MapPath& resultPath() const { return m_resultPath; }
  /// The keys of result() when it was in-betweened (no keys: a sketch's), and their frames.
  const TakeKeys& resultKeys() const { return m_resultKeys; }
  const std::vector<int>& resultKeyFrames() const { return m_resultKeyFrames; }
  /// The `take` given to start() for result().
  int resultTake() const { return m_resultTake; }
  /// The frames [first, end) that result() re-made when it came from a local edit (startEdit());
  /// nothing when it was synthesized whole.
  const std::optional<std::pair<int, int>>& resultWindow() const { return m_resultWindow; }
  /// The `take` of the synthesis running (or of the last one started).
  int runningTake() const { return m_runningTake; }
  /// The map result() was sketched on (a saved map's: the one its blender was built for).
  const std::shared_ptr<const MapResult>& resultMap() const { return m_resultMap; }
  /// Forgets the last motion (a new clip). A running synthesis goes on.
  void clear();

 signals:
  /// Fraction done (0…1) of the running synthesis.
  void progress(double fraction);
  /// The worker ended (finished, failed or cancelled) or was stopped; sent before the result.
  void stopped();
  /// A new motion is result(), replacing the one before.
  void finished();
  /// The library's error message; the previous motion stays.
  void failed(const QString& message);
  /// The synthesis was cancelled; the previous motion stays.
  void cancelled();

 private:
  /// What an in-betweening makes besides the motion (written by the worker, read on its result).
  struct Keyed {
    TakeKeys keys;
    synth::MapPath path;
    std::vector<int> keyFrames;
  };
  void onResult(std::shared_ptr<const MapResult> map, synth::MapPath path, int take,
                std::shared_ptr<const Keyed> keyed, const JobOutcome<synth::SynthResult>& outcome,
                std::optional<std::pair<int, int>> window = std::nullopt);

  std::shared_ptr<const synth::SynthResult> m_result;
  synth::MapPath m_resultPath;
  TakeKeys m_resultKeys;
  std::vector<int> m_resultKeyFrames;
  int m_resultTake = -1;
  std::optional<std::pair<int, int>> m_resultWindow;
  int m_runningTake = -1;
  std::shared_ptr<const MapResult> m_resultMap;
  BackgroundJob m_job;  ///< the motion being synthesized
};

}  // namespace motionmap::studio
