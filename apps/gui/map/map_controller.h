#pragma once
// The maps of the open clips: each computed by pipeline::map_clips on a worker thread with its
// synth::MapBlender, reported through Qt signals on the thread the controller lives in, and kept
// by method and parameters so that going back to one is instant. No widgets: the window shows
// what the signals say, and tests drive it with an event loop alone.
//
//   MapController maps;
//   connect(&maps, &MapController::finished, [](std::shared_ptr<const MapResult> r) { … });
//   maps.setClips(clips);
//   if (maps.request(embed::Method::Isomap, parameters, blend)) show(maps.current());  // cached
//   // else: started, progress…, then finished, failed or cancelled
//
// A computation that fails or is cancelled (or stopped) leaves the map current before it current
// again, with the method and parameters it was made with (shownRequest()): a bad parameter or a
// cancel never leaves the window without its map.
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <QObject>
#include <QString>

#include "common/background_job.h"
#include "common/parameters.h"
#include "motionmap/pipeline/clip_map.h"
#include "motionmap/synth/blender.h"

namespace motionmap::studio {

/// A gplvm map's GP (pipeline::map_gplvm, mapfile::SavedMap::gplvm) into `blend`: the map's rule
/// of where it is valid, and — while the chosen mode is the default (local) — its blends (the gp
/// mode: the GP's predictive mean). Nothing for other maps (`gp` null).
void gplvm_blend(synth::BlendOptions& blend, std::shared_ptr<const MapGp> gp);

/// A computed map of the open clips, with what the app needs to use it.
struct MapResult {
  pipeline::ClipMap map;
  pipeline::ClipMapOptions options;  ///< as computed (callbacks cleared), for the CSV export
  std::unique_ptr<synth::MapBlender> blender;
  std::string parameters;                    ///< pipeline::describe_parameters
  double seconds = 0.0;                      ///< wall time of map_clips and the blender's set-up
  std::vector<std::vector<int>> rowOfFrame;  ///< [clip][frame]: the map row shown for that frame
};

/// The map a synthesis blends on, for a worker thread: `ready`, or made by `make` there (a saved
/// map's blender, built on first use: it may read clips; `make` polls the Control it is given and
/// throws what the build throws).
struct MapSupply {
  std::shared_ptr<const MapResult> ready;
  std::function<std::shared_ptr<const MapResult>(const Control&)> make;
  explicit operator bool() const { return ready != nullptr || bool(make); }
};

/// What a map was asked for with (MapController::request's arguments).
struct MapRequest {
  embed::Method method = embed::Method::Isomap;
  MapParameters parameters;
  synth::BlendOptions blend;
};

class MapController : public QObject {
  Q_OBJECT
 public:
  /// Above this many frames in all (metrics are O(#frames²) on top of the map) maps come
  /// without metrics.
  static constexpr int kMaxMetricsFrames = 5000;

  explicit MapController(QObject* parent = nullptr);
  /// Stops a running computation (waits for its worker; see BackgroundJob::stop).
  ~MapController() override;

  /// The clips every map is of (all of the same skeleton). Stops a running computation without a
  /// signal, and forgets the maps and feature sets of the clips before.
  void setClips(std::shared_ptr<const std::vector<Clip>> clips);
  const std::shared_ptr<const std::vector<Clip>>& clips() const { return m_clips; }

  /// Makes the map of `method` with `parameters` and `blend` (its up axis is the map's) the
  /// current one. When it is cached: stops a running computation, returns true and current() is
  /// that map at once (no signal). Otherwise starts computing it on the worker thread (after
  /// stopping the one running) and returns false: started, then progress, and finished, failed
  /// or cancelled follow. Without clips: false, nothing happens.
  bool request(embed::Method method, const MapParameters& parameters,
               const synth::BlendOptions& blend);

  /// The map asked for last, once computed; nullptr while computing and without clips. After a
  /// failure, a cancel or a stop: the map current before that computation began (nullptr if
  /// there was none).
  std::shared_ptr<const MapResult> current() const;
  /// What current() was asked for with: the method, parameters and blend to show beside it (and
  /// to go back to when a computation fails or is cancelled). Nothing while current() is nullptr.
  std::optional<MapRequest> shownRequest() const;
  bool isComputing() const { return m_job.running(); }
  /// Stops a running computation (emits stopped() only); its results are dropped and the map
  /// current before it is current again. Returns whether one was running.
  bool stop();
  /// Stops a running computation and emits cancelled() (nothing when none is running).
  void cancel();
  /// Maps held (computed, for these clips).
  int cachedMaps() const { return int(m_maps.size()); }

  /// The key a map is cached under: the method, the map parameters and the blender's options.
  static std::string cacheKey(embed::Method method, const MapParameters& parameters,
                              const synth::BlendOptions& blend);

 signals:
  /// A computation of `method` begins; sent just before its worker starts (isComputing() is
  /// still false).
  void started(motionmap::embed::Method method);
  /// The computation's overall fraction done (0…1) and its stage (the library's names).
  void progress(double fraction, const QString& stage);
  /// The worker ended (finished, failed or cancelled) or was stopped; sent before the result.
  void stopped();
  /// The map asked for is ready: it is current() from now on.
  void finished(std::shared_ptr<const motionmap::studio::MapResult> result);
  /// The library's error message; current() is the map before the computation (if any) again.
  void failed(const QString& message);
  /// The computation was cancelled; current() is the map before it (if any) again.
  void cancelled();

 private:
  void onResult(const std::string& key, const JobOutcome<MapResult>& outcome);

  std::shared_ptr<const std::vector<Clip>> m_clips;                ///< shared with the worker
  std::map<std::string, std::shared_ptr<const MapResult>> m_maps;  ///< by cacheKey
  std::string m_currentKey;                                        ///< of the map asked for last
  /// The map made current last by a finish or the cache, and its request: what a failed,
  /// cancelled or stopped computation goes back to.
  std::string m_shownKey;
  std::optional<MapRequest> m_shownRequest;
  MapRequest m_asked;  ///< the request being computed (becomes m_shownRequest when it finishes)
  /// The feature sets of m_clips, one per feature key, shared by the maps of every method.
  std::shared_ptr<pipeline::FeatureCache> m_featureCache =
      std::make_shared<pipeline::FeatureCache>();
  BackgroundJob m_job;  ///< the map (and its blender) being computed
};

}  // namespace motionmap::studio
