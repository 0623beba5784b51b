#pragma once
// MotionMap Studio's main window: the 3-D view and the map side by side, a Motion menu choosing
// the embedding method and its parameters, playback (timer, slider, speed, loop, Space, ←/→) and
// the map gestures (click to jump, drag to blend a pose, Shift-drag or sketch mode to sketch a
// new motion, a magnifying lens). Maps are computed by pipeline::map_clips on a worker thread and
// cached per method and parameters, with their synth::MapBlender; a sketch is synthesized by
// synth::synthesize on a second worker. Both show a progress bar and a Cancel button in the
// status bar, so the GUI thread only ever runs short calls (a locate + blend per mouse move).
#include <atomic>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include <QElapsedTimer>
#include <QMainWindow>
#include <QTimer>

#include "background_job.h"
#include "motionmap/pipeline/clip_map.h"
#include "motionmap/render/map_plot.h"
#include "motionmap/synth/blender.h"
#include "motionmap/synth/synthesize.h"

class QActionGroup;
class QCheckBox;
class QComboBox;
class QLabel;
class QProgressBar;
class QPushButton;
class QSlider;
class QSplitter;
class QMenu;

namespace motionmap::studio {

class MapView;
class SkeletonView;

/// The map parameters the Motion → Parameters dialog edits (the rest are the library's defaults).
struct MapParameters {
  int k = 20;                  ///< neighbours (Isomap, LE, LLE)
  std::optional<double> heat;  ///< LE heat-kernel width; nothing = the library's automatic one
  features::FeatureKind features = features::FeatureKind::Quaternions;
  features::DistanceKind distance = features::DistanceKind::PointCloud;
  std::string exclude;  ///< regular expression of joints left out

  /// The library options for `method` (no callbacks).
  pipeline::ClipMapOptions options(embed::Method method) const;
  bool operator==(const MapParameters&) const = default;
};

/// How a drag blends and a sketch becomes a motion (Motion → Synthesis…): the library's options
/// and defaults, as `motionmap pose` / `synth` take them. The blend part goes into each map's
/// blender (changing it recomputes the map, or takes it from the cache); the motion part applies
/// to the next sketch.
struct SynthParameters {
  synth::BlendOptions blend;   ///< mode, K, reach (the up axis is the map's)
  synth::SynthOptions motion;  ///< speed (of a sketch not timed as drawn), output fps, smoothing
  /// A sketch keeps the timing of the gesture; false: it is followed at motion.speed (0: the
  /// clip's own median map speed).
  bool timedAsDrawn = true;
};

/// A computed map of the open clip, with what the app needs to use it.
struct MapResult {
  pipeline::ClipMap map;
  pipeline::ClipMapOptions options;  ///< as computed (callbacks cleared), for the CSV export
  std::unique_ptr<synth::MapBlender> blender;
  std::string parameters;                    ///< pipeline::describe_parameters
  double seconds = 0.0;                      ///< wall time of map_clips and the blender's set-up
  std::vector<std::vector<int>> rowOfFrame;  ///< [clip][frame]: the map row shown for that frame
};

class MainWindow : public QMainWindow {
  Q_OBJECT
 public:
  explicit MainWindow(QWidget* parent = nullptr);
  ~MainWindow() override;

  /// Loads a .bvh or .amc (io::load_clip) and starts its map. False (error shown) on failure, or
  /// when the user keeps an unexported synthesized motion.
  bool openFile(const QString& path);
  /// Shows `clip` and starts its map (tests, the built-in sample). Does not ask: callers that
  /// replace a clip on a user's action call confirmDiscard() first.
  void openClip(Clip clip);
  /// Loads another clip of the same skeleton into the map (File → Add clip). False (error shown)
  /// on failure or a different hierarchy.
  bool addFile(const QString& path);
  /// Adds `clip` (same joint hierarchy as the first) to the map, which is recomputed with every
  /// clip (each a trajectory of its own, red → blue, with a start marker). The synthesized motion
  /// is kept. False (error shown) for a clip of another hierarchy or without a clip open.
  bool addClip(Clip clip);
  /// The clip playing (the one whose frames the slider shows).
  const Clip* clip() const { return m_clips ? &(*m_clips)[std::size_t(m_clipIndex)] : nullptr; }
  int clipCount() const { return m_clips ? int(m_clips->size()) : 0; }
  int currentClip() const { return m_clipIndex; }
  /// Plays clip `index` (of the map's clips) from `frame`.
  void setCurrentClip(int index, int frame = 0);

  /// Shows the map of `method` with the current parameters: at once when cached, else computed
  /// on the worker thread.
  void setMethod(embed::Method method);
  embed::Method method() const { return m_method; }
  /// Changes the map parameters and shows (computes, or takes from the cache) the current
  /// method's map with them.
  void setParameters(const MapParameters& parameters);
  const MapParameters& parameters() const { return m_parameters; }
  /// Changes how drags blend and sketches are synthesized. A value the library rejects (K
  /// checked against the map shown) is shown as its error and false returned; the previous
  /// parameters then stay. A new blend recomputes the map, or takes it from the cache.
  bool setSynthParameters(const SynthParameters& parameters);
  const SynthParameters& synthParameters() const { return m_synthParameters; }
  /// The map shown (nullptr while computing or without a clip).
  const MapResult* currentMap() const;
  bool isComputing() const { return m_mapJob.running(); }
  void cancelComputation();

  /// Frame of the motion playing (the clip, or a synthesized motion).
  int currentFrame() const { return m_frame; }
  void setFrame(int frame);
  void play();
  void pause();
  bool isPlaying() const { return m_timer.isActive(); }
  /// Playback speed (1 = the clip's frame rate); clamped to [0.05, 8].
  void setPlaybackSpeed(double speed);
  double playbackSpeed() const { return m_speed; }
  /// Whether playback starts over at the end (else it stops on the last frame).
  void setLoop(bool loop);
  bool loop() const { return m_loop; }
  const Motion* playingMotion() const;

  /// The last synthesized motion (nothing before the first sketch).
  const synth::SynthResult* synthesized() const { return m_synth ? &*m_synth : nullptr; }
  bool hasUnsavedMotion() const { return m_synth && m_unsaved; }
  /// Asks before a synthesized motion that was not exported is replaced or dropped; true to go
  /// on (always when there is none, or when not interactive).
  bool confirmDiscard();
  /// Starts synthesizing the motion along `path` (synth::synthesize with the synthesis
  /// parameters; without its times unless timedAsDrawn) on a worker; when done it
  /// replaces the last one (asked first, see confirmDiscard) and plays. False if nothing started.
  bool synthesizeAlong(const synth::MapPath& path);
  bool isSynthesizing() const { return m_synthJob.running(); }
  /// Stops a running synthesis; the previous synthesized motion (if any) stays.
  void cancelSynthesis();
  /// Writes the synthesized motion as BVH. False (error shown) on failure.
  bool exportMotion(const QString& path);
  /// Writes the map shown: .csv (pipeline::write_map_csv), .png, .svg or .pdf
  /// (render::save_map_plot). False (error shown) on failure.
  bool exportMap(const QString& path);

  /// When false, errors go to the status line only and discard questions are skipped
  /// (tests; also MOTIONMAP_STUDIO_NO_CONFIRM=1).
  void setInteractive(bool interactive) { m_interactive = interactive; }
  QString lastError() const { return m_lastError; }
  QString statusText() const;
  MapView* mapView() const { return m_mapView; }
  SkeletonView* skeletonView() const { return m_skeletonView; }
  /// Both views as one image (the GL view through grabFramebuffer when it has a context).
  QImage screenshot();

 signals:
  void mapReady(motionmap::embed::Method method);
  void computationFinished(bool ok);
  void progressChanged(double fraction);
  void frameChanged(int frame);
  void motionSynthesized();
  /// A synthesis ended: ok = its motion is shown; false when it failed or was cancelled.
  void synthesisFinished(bool ok);
  void synthesisProgress(double fraction);

 protected:
  void closeEvent(QCloseEvent* event) override;
  void dragEnterEvent(QDragEnterEvent* event) override;
  void dropEvent(QDropEvent* event) override;
  void keyPressEvent(QKeyEvent* event) override;

 private:
  void buildUi();
  std::string cacheKey(embed::Method method) const;
  void startComputation(embed::Method method);
  void stopWorker();
  void stopSynthWorker();
  void onComputed(int generation, embed::Method method, std::string key,
                  std::shared_ptr<MapResult> result, QString error, bool cancelled);
  void onSynthesized(int generation, std::shared_ptr<const MapResult> map,
                     std::shared_ptr<synth::SynthResult> result, QString error, bool cancelled);
  /// Shows `frame` of the playing motion (clamped), without touching the playback clock.
  void showFrame(int frame);
  /// The render options the map is drawn (and exported) with.
  render::MapPlotOptions plotOptions(const MapResult& map) const;
  void showMap();
  void showError(const QString& message);
  void updateStatus();
  void updatePointer();
  void onTick();
  void onHover(const Eigen::Vector2d& point, const QPointF& pixel);
  void onClick(const Eigen::Vector2d& point, const QPointF& pixel);
  void onDrag(const Eigen::Vector2d& point);
  void showClipMotion();
  void openDialog();
  void exportDialog();
  void exportMapDialog();
  void parametersDialog();
  void synthesisDialog();
  /// Map and synthesis parameters to and from QSettings: the ones of the last map computed
  /// without error are the next session's.
  void loadParameters();
  void saveParameters() const;
  void addDialog();
  void clipsChanged();
  void addRecentFile(const QString& path);
  void updateRecentMenu();
  /// The map row nearest `pixel` within 12 px of the trajectory, or −1.
  int sampleNear(const Eigen::Vector2d& point, const QPointF& pixel) const;

  std::shared_ptr<const std::vector<Clip>> m_clips;  ///< the map's clips, shared with the worker
  int m_clipIndex = 0;
  embed::Method m_method = embed::Method::Isomap;
  MapParameters m_parameters;
  SynthParameters m_synthParameters;
  std::map<std::string, std::shared_ptr<MapResult>> m_maps;  ///< by cacheKey
  /// The feature sets of m_clips, one per feature key, shared by the maps of every method.
  std::shared_ptr<pipeline::FeatureCache> m_featureCache =
      std::make_shared<pipeline::FeatureCache>();
  BackgroundJob m_mapJob;  ///< the map (and its blender) being computed

  std::optional<synth::SynthResult> m_synth;
  std::shared_ptr<const MapResult> m_synthMap;  ///< the map m_synth was sketched on
  BackgroundJob m_synthJob;                     ///< the motion being synthesized
  bool m_playingSynth = false;
  bool m_unsaved = false;

  int m_frame = 0;
  QTimer m_timer;
  QElapsedTimer m_playClock;  ///< since play() or the last loop
  int m_playStartFrame = 0;
  double m_speed = 1.0;
  bool m_loop = true;
  bool m_interactive = true;
  QString m_lastError;
  QString m_lastDir;

  MapView* m_mapView = nullptr;
  SkeletonView* m_skeletonView = nullptr;
  QSplitter* m_splitter = nullptr;
  QSlider* m_slider = nullptr;
  QPushButton* m_playButton = nullptr;
  QComboBox* m_speedBox = nullptr;
  QCheckBox* m_loopBox = nullptr;
  QLabel* m_status = nullptr;
  QProgressBar* m_progress = nullptr;
  QPushButton* m_cancelButton = nullptr;
  QProgressBar* m_synthProgress = nullptr;
  QPushButton* m_synthCancelButton = nullptr;
  QActionGroup* m_methodGroup = nullptr;
  QAction* m_exportAction = nullptr;
  QAction* m_exportMapAction = nullptr;
  QMenu* m_recentMenu = nullptr;
};

/// The menu label of `method`: "PCA", "SVD", "MDS", "Isomap", "LE", "LLE".
QString methodLabel(embed::Method method);

}  // namespace motionmap::studio
