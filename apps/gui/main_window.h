#pragma once
// MotionMap Studio's main window: the 3-D view and the map side by side, a Motion menu choosing
// the embedding method, playback (timer, slider, Space, ←/→) and the map gestures (click to
// jump, drag to blend a pose, Shift-drag to sketch a new motion). Maps are computed by
// embed::map_clips on a worker thread (progress bar and Cancel in the status bar) and cached per
// method, with their synth::MapBlender.
#include <atomic>
#include <map>
#include <memory>
#include <optional>
#include <thread>

#include <QMainWindow>
#include <QTimer>

#include "motionmap/embed/clip_map.h"
#include "motionmap/synth/blender.h"
#include "motionmap/synth/synthesize.h"

class QActionGroup;
class QLabel;
class QProgressBar;
class QPushButton;
class QSlider;
class QMenu;

namespace motionmap::studio {

class MapView;
class SkeletonView;

/// A computed map of the open clip, with what the app needs to use it.
struct MapResult {
  embed::ClipMap map;
  std::unique_ptr<synth::MapBlender> blender;
  std::string parameters;        ///< embed::describe_parameters
  double seconds = 0.0;          ///< wall time of map_clips
  std::vector<int> rowOfFrame;   ///< per clip frame: the map row shown for it
};

class MainWindow : public QMainWindow {
  Q_OBJECT
 public:
  explicit MainWindow(QWidget* parent = nullptr);
  ~MainWindow() override;

  /// Loads a .bvh or .amc (io::load_clip) and starts its map. False (error shown) on failure.
  bool openFile(const QString& path);
  /// Shows `clip` and starts its map (tests, the built-in sample).
  void openClip(Clip clip);
  const Clip* clip() const { return m_clip.get(); }

  /// Shows the map of `method`: at once when cached, else computed on the worker thread.
  void setMethod(embed::Method method);
  embed::Method method() const { return m_method; }
  /// The map shown (nullptr while computing or without a clip).
  const MapResult* currentMap() const;
  bool isComputing() const { return m_worker.joinable(); }
  void cancelComputation();

  /// Frame of the motion playing (the clip, or a synthesized motion).
  int currentFrame() const { return m_frame; }
  void setFrame(int frame);
  void play();
  void pause();
  bool isPlaying() const { return m_timer.isActive(); }
  const Motion* playingMotion() const;

  /// The last synthesized motion (nothing before the first sketch).
  const synth::SynthResult* synthesized() const { return m_synth ? &*m_synth : nullptr; }
  bool hasUnsavedMotion() const { return m_synth && m_unsaved; }
  /// Synthesizes the motion along `path` (synth::synthesize) and plays it.
  void synthesizeAlong(const synth::MapPath& path);
  /// Writes the synthesized motion as BVH. False (error shown) on failure.
  bool exportMotion(const QString& path);

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

 protected:
  void closeEvent(QCloseEvent* event) override;
  void dragEnterEvent(QDragEnterEvent* event) override;
  void dropEvent(QDropEvent* event) override;
  void keyPressEvent(QKeyEvent* event) override;

 private:
  void buildUi();
  void startComputation(embed::Method method);
  void stopWorker();
  void onComputed(int generation, embed::Method method, std::shared_ptr<MapResult> result, QString error,
                  bool cancelled);
  void showMap();
  void showError(const QString& message);
  bool confirmDiscard();
  void updateStatus();
  void updatePointer();
  void onTick();
  void onHover(const Eigen::Vector2d& point, const QPointF& pixel);
  void onClick(const Eigen::Vector2d& point, const QPointF& pixel);
  void onDrag(const Eigen::Vector2d& point);
  void showClipMotion();
  void openDialog();
  void exportDialog();
  void addRecentFile(const QString& path);
  void updateRecentMenu();
  /// The map row nearest `pixel` within 12 px of the trajectory, or −1.
  int sampleNear(const Eigen::Vector2d& point, const QPointF& pixel) const;

  std::shared_ptr<const Clip> m_clip;
  embed::Method m_method = embed::Method::Isomap;
  std::map<embed::Method, std::shared_ptr<MapResult>> m_maps;
  std::thread m_worker;
  std::shared_ptr<std::atomic<bool>> m_cancel;
  int m_generation = 0;

  std::optional<synth::SynthResult> m_synth;
  embed::Method m_synthMethod = embed::Method::Pca;  ///< the map m_synth was sketched on
  bool m_playingSynth = false;
  bool m_unsaved = false;
  int m_frame = 0;
  QTimer m_timer;
  bool m_interactive = true;
  QString m_lastError;
  QString m_lastDir;

  MapView* m_mapView = nullptr;
  SkeletonView* m_skeletonView = nullptr;
  QSlider* m_slider = nullptr;
  QPushButton* m_playButton = nullptr;
  QLabel* m_status = nullptr;
  QProgressBar* m_progress = nullptr;
  QPushButton* m_cancelButton = nullptr;
  QActionGroup* m_methodGroup = nullptr;
  QAction* m_exportAction = nullptr;
  QMenu* m_recentMenu = nullptr;
};

/// The menu label of `method`: "PCA", "SVD", "MDS", "Isomap", "LE", "LLE".
QString methodLabel(embed::Method method);

}  // namespace motionmap::studio
