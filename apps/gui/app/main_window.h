#pragma once
// MotionMap Studio's main window: the 3-D view and the map side by side, the transport bar under
// them (play, frame slider, frame and time, speed, loop), the Takes panel at the right, the File,
// Edit, Motion, View, Playback and Help menus (the playback keys are window shortcuts:
// PlaybackActions), and the map gestures (hover and click to find a frame, drag to blend a pose,
// Shift-drag or sketch mode to sketch a new motion, a magnifying lens). The window computes
// nothing itself and holds no feature: it wires the widgets to controllers without widgets —
// MapController (maps computed by pipeline::map_clips on a worker thread and cached per method
// and parameters, with their synth::MapBlender), MapChoice (the method and parameters chosen,
// their settings and undo), the MapSource shown (ComputedMapSource over the MapController's
// clips, or SavedMapSource for a map file), SynthesisController (a sketch synthesized on a second
// worker), TakesController (takes and the undo history), ExportController, Playback (the
// clock) with MotionPlayer (the clip or the current take plays), ExplorePanels (search,
// selection, nearest frames, colour by label and its legend, two clips compared), KeyPoseStrip
// (View → Key poses: the clip's key poses under the views; a click plays from one) and
// StatusLine. Both workers show a progress bar and a Cancel button in the status bar, so the GUI
// thread only ever runs short calls (a locate + blend per mouse move). New features belong in those
// controllers (or new ones), not here.
#include <functional>
#include <memory>
#include <optional>

#include <QMainWindow>
#include <QPointF>

#include "app/status_line.h"
#include "common/parameters.h"
#include "export/animation_export.h"
#include "export/export_controller.h"
#include "export/export_names.h"
#include "map/map_choice.h"
#include "map/map_controller.h"
#include "map/map_source.h"
#include "playback/motion_player.h"
#include "playback/playback.h"
#include "takes/synthesis_controller.h"
#include "takes/takes_controller.h"

class QLabel;
class QSplitter;

namespace motionmap::mapfile {
class SavedMap;
}
namespace motionmap::studio {

class ExplorePanels;
class FileMenu;
class JointDrag;
class KeysController;
class MapGestures;
class JobProgress;
class MapView;
class MotionMenu;
class SkeletonView;
class TakesPanel;

class MainWindow : public QMainWindow {
  Q_OBJECT
 public:
  explicit MainWindow(QWidget* parent = nullptr);
  ~MainWindow() override;

  /// Loads a .bvh or .amc (io::load_clip) and starts its map; a map file (.h5, .hdf5: what
  /// `motionmap map --save` writes) opens with openMapFile. False (error shown) on failure, or
  /// when the user keeps an unexported synthesized motion.
  bool openFile(const QString& path);
  /// Opens a saved map (mapfile::read_map_file) without refitting it: its points drawn as a
  /// density image, its first clip loaded (on demand, SHA-256 checked against the map file) and
  /// shown with its trajectory on top. Hover names the clip and frame under the mouse, a click
  /// loads that clip and jumps to the frame, a drag blends the nearest samples
  /// (mapfile::SavedMap::pose_at, K = the synthesis parameters' neighbors); sketches, key poses
  /// and joint drags blend on it (its blender built on a worker, mapfile::make_blender). The
  /// Motion menu's methods need clips mapped here (open clips for that). False (error shown) for
  /// a file read_map_file refuses or whose first clip cannot be loaded.
  bool openMapFile(const QString& path);
  /// "Recompute from clips…": the saved map's clips loaded (checked against the map file, with a
  /// progress dialog when interactive) and mapped here with `method` and the current parameters,
  /// as if opened together; the Motion menu then works as on any computed map. Offered when a
  /// method or parameters are chosen on a saved map. False (error shown) when a clip cannot be
  /// loaded, on Cancel, or without a saved map.
  bool recomputeFromClips(embed::Method method);
  /// The saved map shown (nullptr when the map is one computed here).
  const mapfile::SavedMap* savedMap() const { return m_saved ? m_saved->map().get() : nullptr; }
  /// A saved map's clip is being loaded (on a worker thread) for a click or a drag.
  bool isLoadingClip() const { return m_source->isLoadingClip(); }
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
  const Clip* clip() const { return m_source->clip(); }
  int clipCount() const { return m_source->clipCount(); }
  int currentClip() const { return m_source->currentClip(); }
  /// Plays clip `index` (of the map's clips) from `frame`. On a saved map a clip not in the cache
  /// is loaded on a worker thread first (isLoadingClip(); the jump happens when it arrives); one
  /// that cannot be loaded (missing, changed since the map was made) is shown as an error and the
  /// clip before stays.
  void setCurrentClip(int index, int frame = 0);

  /// Shows the map of `method` with the current parameters: at once when cached, else computed
  /// on the worker thread.
  void setMethod(embed::Method method) { m_choice->setMethod(method); }
  embed::Method method() const { return m_choice->method(); }
  /// Changes the map parameters and shows (computes, or takes from the cache) the current
  /// method's map with them.
  void setParameters(const MapParameters& parameters) { m_choice->setParameters(parameters); }
  const MapParameters& parameters() const { return m_choice->parameters(); }
  /// Changes how drags blend and sketches are synthesized. A value the library rejects (K
  /// checked against the map shown) is shown as its error and false returned; the previous
  /// parameters then stay. A new blend recomputes the map, or takes it from the cache.
  bool setSynthParameters(const SynthParameters& parameters) {
    return m_choice->setSynthParameters(parameters);
  }
  const SynthParameters& synthParameters() const { return m_choice->synthParameters(); }
  /// The map shown, as takes blend on it (nullptr while computing, without a clip, or while a
  /// saved map's blender is built).
  const MapResult* currentMap() const { return m_source ? m_source->blendMap().get() : nullptr; }
  bool isComputing() const { return m_maps.isComputing(); }
  void cancelComputation() { m_maps.cancel(); }
  /// The map controller (its signals, e.g. progress with the stage's name; tests).
  const MapController& maps() const { return m_maps; }

  /// Frame of the motion playing (the clip, or a synthesized motion).
  /// The playback clock (frame, in/out range, speed, loop), for scripts and tests.
  Playback& playback() { return m_playback; }
  int currentFrame() const { return m_playback.frame(); }
  void setFrame(int frame) { m_playback.setFrame(frame); }
  void play() { m_playback.play(); }
  void pause() { m_playback.pause(); }
  bool isPlaying() const { return m_playback.isPlaying(); }
  /// Playback speed (1 = the clip's frame rate); clamped to [0.05, 8].
  void setPlaybackSpeed(double speed) { m_playback.setSpeed(speed); }
  double playbackSpeed() const { return m_playback.speed(); }
  /// Whether playback starts over at the end (else it stops on the last frame).
  void setLoop(bool loop) { m_playback.setLoop(loop); }
  bool loop() const { return m_playback.loop(); }
  const Motion* playingMotion() const { return m_player->playingMotion(); }

  /// The current take's motion (nothing before the first sketch, or with no take selected).
  const synth::SynthResult* synthesized() const { return m_player->synthesized(); }
  /// Some take was not exported since its motion last changed.
  bool hasUnsavedMotion() const { return !m_takes->list().unexportedNames().isEmpty(); }
  /// Asks before takes that were not exported are dropped (another clip, closing); true to go
  /// on (always when there are none, or when not interactive).
  bool confirmDiscard();
  /// Starts synthesizing the motion along `path` (synth::synthesize with the synthesis
  /// parameters; without its times unless timedAsDrawn) on a worker; when done it becomes a new
  /// take (the takes before stay), the current one, and plays. False if nothing started.
  bool synthesizeAlong(const synth::MapPath& path);
  /// The takes and the undo history (Edit → Undo / Redo).
  TakesController* takes() const { return m_takes; }
  TakesPanel* takesPanel() const { return m_takesPanel; }
  /// Drags the current take's control point `control` to map point `to` (as the mouse does):
  /// the take is re-synthesized on the worker and, when done, its motion replaced (one undo
  /// step). False if nothing started.
  bool moveControlPoint(int control, const Eigen::Vector2d& to);
  bool isSynthesizing() const { return m_synthesis.isRunning(); }
  /// Stops a running synthesis; the previous synthesized motion (if any) stays.
  void cancelSynthesis() { m_synthesis.cancel(); }
  /// Writes the current take's motion as BVH. False (error shown) on failure.
  bool exportMotion(const QString& path) { return exportTake(m_takes->list().current(), path); }
  /// Writes the motion of the take at `row` as BVH; it then counts as exported. False (error
  /// shown) on failure.
  bool exportTake(int row, const QString& path) { return m_exports->exportTake(row, path); }
  /// Writes the map shown: .csv (pipeline::write_map_csv), .png, .svg or .pdf
  /// (render::save_map_plot). False (error shown) on failure.
  bool exportMap(const QString& path) { return m_exports->exportMap(path); }

  /// When false, errors go to the status line only and discard questions are skipped
  /// (tests; also MOTIONMAP_STUDIO_NO_CONFIRM=1).
  void setInteractive(bool interactive) { m_status->setInteractive(interactive); }
  QString lastError() const { return m_status->lastError(); }
  QString statusText() const { return m_status->text(); }
  QString statusToolTip() const { return m_status->toolTip(); }
  MapView* mapView() const { return m_mapView; }
  SkeletonView* skeletonView() const { return m_skeletonView; }
  JointDrag* jointDrag() const { return m_jointDrag; }
  KeysController* keys() const { return m_keys; }
  /// A Ctrl-click on the map: a key pose placed or removed (KeysController::click).
  bool placeKey(const Eigen::Vector2d& point, const QPointF& pixel);
  /// Motion → Retime Keys…: the current in-between take's key times, edited as text.
  void retimeKeysDialog();
  /// Both views as one image (the GL view through grabFramebuffer when it has a context).
  QImage screenshot() { return m_exports->screenshot(); }
  /// File → Export picture and Export animation (picture_export.h, animation_export.h).
  /// The picture of `kind` as the views show it now.
  QImage renderPicture(PictureKind kind) { return m_exports->renderPicture(kind); }
  /// Shows `frame` of the motion playing (pausing playback) and renders it.
  QImage renderFrameImage(int frame, PictureKind kind) {
    return m_exports->renderFrameImage(frame, kind);
  }
  /// Writes renderPicture(kind) as PNG. False (error shown) on failure.
  bool exportPicture(const QString& path, PictureKind kind) {
    return m_exports->exportPicture(path, kind);
  }
  /// Writes the motion playing, frames settings.first..last (−1: its first / last), as the
  /// window shows it (both views), with a progress dialog and Cancel; the frame shown and
  /// playback are restored afterwards. False when cancelled (status says so) or on an error
  /// (shown; nothing is left written).
  bool exportAnimation(const AnimationSettings& settings) {
    return m_exports->exportAnimation(settings);
  }
  /// The names, frames and rate the export dialogs start from.
  ExportContext exportContext() const;
  FileMenu* fileMenu() const { return m_files; }
  /// Search, selection, nearest frames, colour by label and its legend, two clips compared.
  ExplorePanels* explore() const { return m_explore; }

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

 private:
  void buildUi();
  void buildMenus();
  void buildStatusBar();
  void connectControllers();
  /// The map controller's signals: a computation starts, its map is ready, it failed or was
  /// cancelled.
  void onMapStarted(embed::Method method);
  void onMapFinished(std::shared_ptr<const MapResult> result);
  void onMapFailed(const QString& message);
  void onMapCancelled();
  /// A synthesized motion is ready: a new take, or an edited one; it plays.
  void onSynthesized();
  /// The map view draws the takes sketched on the map shown.
  void updateTakePaths();
  /// The map shown comes from `source` (its clip, its frames' points, its status, what it
  /// refuses).
  void useSource(MapSource* source);
  /// The controller's current map drawn (after a failure or cancel: the one before, back with
  /// its method and parameters). False when there is none.
  bool showMap();
  void showError(const QString& message) { m_status->showError(message); }
  /// Runs `work`; false, with the error it threw shown, when it throws.
  bool attempt(const std::function<void()>& work) { return m_status->attempt(work); }
  void updateStatus();
  void parametersDialog();
  void synthesisDialog();
  /// The clips changed (opened or added): a new title, the clip shown from `frame`, a new map.
  void clipsChanged(int frame);

  MapController m_maps;                     ///< the clips, their maps and the map being computed
  ComputedMapSource* m_computed = nullptr;  ///< m_maps' clips and maps, as a source
  SavedMapSource* m_saved = nullptr;        ///< a map file shown (File → Open map), or none
  MapSource* m_source = nullptr;            ///< the one shown: m_saved, else m_computed
  MapGestures* m_gestures = nullptr;
  JointDrag* m_jointDrag = nullptr;
  KeysController* m_keys = nullptr;
  /// Leaves the saved map (another clip opened).
  void closeSavedMap();
  // Stops playback and any synthesis, and forgets the synthesized motion (for new content; the
  // caller has asked before discarding an unexported one).
  void dropSynthesizedMotion();
  SynthesisController m_synthesis;
  Playback m_playback;
  MotionPlayer* m_player = nullptr;  ///< the clip or the current take plays
  TakesController* m_takes = nullptr;
  MapChoice* m_choice = nullptr;  ///< the method and parameters (Motion menu), their undo
  TakesPanel* m_takesPanel = nullptr;

  MapView* m_mapView = nullptr;
  SkeletonView* m_skeletonView = nullptr;
  QSplitter* m_splitter = nullptr;
  StatusLine* m_status = nullptr;
  JobProgress* m_mapProgress = nullptr;
  JobProgress* m_synthProgress = nullptr;
  MotionMenu* m_motionMenu = nullptr;
  FileMenu* m_files = nullptr;
  ExplorePanels* m_explore = nullptr;  ///< search, selection, nearest frames
  ExportController* m_exports = nullptr;
};

}  // namespace motionmap::studio
