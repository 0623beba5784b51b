#include "app/main_window.h"

#include <QAction>
#include <QCloseEvent>
#include <QDir>
#include <QDragEnterEvent>
#include <QFileInfo>
#include <QMenu>
#include <QMimeData>
#include <QSettings>
#include <QSplitter>
#include <QStatusBar>
#include <QVBoxLayout>

#include "app/file_menu.h"
#include "app/help_dialogs.h"
#include "app/job_progress.h"
#include "app/menus.h"
#include "app/parameter_dialogs.h"
#include "app/status_line.h"
#include "app/window_dialogs.h"
#include "explore/explore_panels.h"
#include "explore/map_coordinates.h"
#include "explore/saved_clips.h"
#include "map/joint_drag.h"
#include "map/map_gestures.h"
#include "map/map_source.h"
#include "map/map_view.h"
#include "motionmap/io/load.h"
#include "motionmap/sample/sample_clip.h"
#include "playback/key_pose_strip.h"
#include "playback/motion_player.h"
#include "playback/playback_actions.h"
#include "playback/transport_bar.h"
#include "scene/camera_menu.h"
#include "scene/joint_panel.h"
#include "scene/skeleton_view.h"
#include "takes/keys_controller.h"
#include "takes/takes_panel.h"

namespace motionmap::studio {

MainWindow::MainWindow(QWidget* parent) : QMainWindow(parent) {
  buildUi();
  connectControllers();
  const QSettings settings;
  restoreGeometry(settings.value("geometry").toByteArray());
  m_splitter->restoreState(settings.value("splitter").toByteArray());
  setAcceptDrops(true);
  showMenuToolTips(this);
}

// The controllers stop their workers as they go.
MainWindow::~MainWindow() = default;

void MainWindow::buildUi() {
  setWindowTitle(tr("MotionMap Studio"));
  resize(1280, 720);
  m_skeletonView = new SkeletonView;
  m_mapView = new MapView;
  m_splitter = new QSplitter(Qt::Horizontal);
  m_splitter->addWidget(m_skeletonView);
  m_splitter->addWidget(m_mapView);
  m_splitter->setSizes({640, 640});

  auto* central = new QWidget;
  auto* layout = new QVBoxLayout(central);
  layout->setContentsMargins(4, 4, 4, 4);
  layout->addWidget(m_splitter, 1);
  layout->addWidget(new TransportBar(&m_playback));
  setCentralWidget(central);
  m_takes = new TakesController(&m_synthesis, this);
  m_choice = new MapChoice(&m_maps, m_takes, this);
  m_takesPanel = new TakesPanel(m_takes);
  addDockWidget(Qt::RightDockWidgetArea, m_takesPanel);
  resizeDocks({m_takesPanel}, {200}, Qt::Horizontal);  // room for its buttons, the rest the views
  m_explore = new ExplorePanels(
      this, m_mapView, m_skeletonView, &m_playback, [this] { return m_source; }, &m_maps);
  connect(m_explore, &ExplorePanels::clipRequested, this, &MainWindow::setCurrentClip);
  connect(m_explore, &ExplorePanels::message, this, [this](const QString& text) {
    if (m_status) m_status->setText(text);
  });
  connect(m_explore, &ExplorePanels::failed, this, &MainWindow::showError);
  m_exports = new ExportController(this, m_skeletonView, m_mapView, &m_playback, m_takes, &m_maps,
                                   [this] { return playingMotion(); });

  buildMenus();
  buildStatusBar();
  m_gestures = new MapGestures(&m_maps, m_mapView, m_skeletonView, &m_playback, this);
  m_computed = new ComputedMapSource(&m_maps, m_mapView, m_skeletonView, this);
  useSource(m_computed);
  connect(m_gestures, &MapGestures::frameClicked, this, &MainWindow::setCurrentClip);
  connect(m_gestures, &MapGestures::failed, this, &MainWindow::showError);
  m_jointDrag =
      new JointDrag([this] { return m_source; }, m_mapView, m_skeletonView, &m_playback, this);
  connect(m_jointDrag, &JointDrag::failed, this, &MainWindow::showError);
  connect(m_jointDrag, &JointDrag::reached, this,
          [this](const QString& summary) { m_status->setText(summary); });
  connect(m_mapView, &MapView::sketchFinished, this, &MainWindow::synthesizeAlong);
  connect(m_mapView, &MapView::controlPointMoved, this, &MainWindow::moveControlPoint);
  m_keys = new KeysController([this] { return m_source; }, m_mapView, m_takes, &m_synthesis,
                              [this] { return synthParameters(); }, this);
  connect(m_mapView, &MapView::keyClicked, this, &MainWindow::placeKey);
  // Space over the map is held back for Space+drag panning: a tap still plays / pauses.
  connect(m_mapView, &MapView::spaceTapped, this, [this] { isPlaying() ? pause() : play(); });
  connect(m_keys, &KeysController::failed, this, &MainWindow::showError);
  connect(m_keys, &KeysController::started, this, [this] {
    m_synthProgress->start();
    updateStatus();
  });
  connect(m_takes, &TakesController::changed, this, &MainWindow::updateTakePaths);
  m_player = new MotionPlayer(
      &m_playback, m_skeletonView, m_mapView, m_takes, [this] { return m_source; },
      [this] { return currentMap(); }, this);
  connect(m_takesPanel, &TakesPanel::exportRequested, this, &MainWindow::exportTake);
  m_takesPanel->setSuggestion([this](int row) {
    ExportContext c = m_files->context();  // the export folder, the clip's name
    c.naming.take = m_takes->list().at(row).name;
    return QDir(c.folder).filePath(motionFileName(c.naming));
  });
}

void MainWindow::buildMenus() {
  m_files = new FileMenu(this);
  connect(m_files, &FileMenu::openRequested, this, &MainWindow::openFile);
  connect(m_files, &FileMenu::sampleRequested, this, [this] {
    if (confirmDiscard()) openClip(sample::make_sample_clip(sample::SampleKind::Swing));
  });
  connect(m_files, &FileMenu::addRequested, this, [this](const QStringList& paths) {
    for (const QString& path : paths) {
      if (!addFile(path)) break;
    }
  });
  connect(m_files, &FileMenu::exportMotionRequested, this, &MainWindow::exportMotion);
  connect(m_files, &FileMenu::exportMapRequested, this, &MainWindow::exportMap);
  connect(m_files, &FileMenu::exportPictureRequested, this, &MainWindow::exportPicture);
  connect(m_files, &FileMenu::exportAnimationRequested, this, &MainWindow::exportAnimation);
  m_files->setContextSource([this] { return exportContext(); });
  addEditMenu(this, m_takes, m_takesPanel);

  m_motionMenu = new MotionMenu(this, method());
  connect(m_motionMenu, &MotionMenu::methodChosen, this, &MainWindow::setMethod);
  connect(m_motionMenu, &MotionMenu::parametersRequested, this, &MainWindow::parametersDialog);
  connect(m_motionMenu, &MotionMenu::synthesisRequested, this, &MainWindow::synthesisDialog);
  connect(m_motionMenu, &MotionMenu::retimeKeysRequested, this, &MainWindow::retimeKeysDialog);
  connect(m_motionMenu, &MotionMenu::showClipRequested, this, [this] {
    if (m_player->playsTake()) setCurrentClip(currentClip(), 0);
  });
  QMenu* view = addViewMenu(this, m_skeletonView, m_mapView);
  auto* keyPoses = new KeyPoseStrip(
      this, [this] { return m_source; }, [this] { return m_player && !m_player->playsTake(); });
  view->addAction(keyPoses->toggleViewAction());
  connect(keyPoses, &KeyPoseStrip::clipRequested, this, &MainWindow::setCurrentClip);
  connect(this, &MainWindow::frameChanged, keyPoses, &KeyPoseStrip::showFrame);
  m_explore->addViewActions(view);
  addCameraMenu(view, m_skeletonView);
  addJointsPanel(this, m_skeletonView, view);
  new PlaybackActions(this, &m_playback);  // Space, arrows, Home/End, I/O: window shortcuts
  addHelpMenu(this);
}

void MainWindow::buildStatusBar() {
  m_status = new StatusLine(this);
  statusBar()->addWidget(m_status, 1);
  statusBar()->addPermanentWidget(new MapCoordinates(m_mapView));
  m_mapProgress = new JobProgress(statusBar(), tr("Cancel"));
  connect(m_mapProgress, &JobProgress::cancelClicked, this, &MainWindow::cancelComputation);
  m_synthProgress = new JobProgress(statusBar(), tr("Cancel synthesis"), tr("Synthesizing %p%"));
  connect(m_synthProgress, &JobProgress::cancelClicked, this, &MainWindow::cancelSynthesis);
}

void MainWindow::connectControllers() {
  connect(m_player, &MotionPlayer::frameShown, this, &MainWindow::frameChanged);
  connect(m_player, &MotionPlayer::motionShown, m_files, &FileMenu::setMotionShown);
  connect(m_player, &MotionPlayer::takeShown, m_files->exportMotionAction(), &QAction::setEnabled);
  connect(m_player, &MotionPlayer::statusChanged, this, &MainWindow::updateStatus);
  connect(m_exports, &ExportController::failed, this, &MainWindow::showError);
  connect(m_exports, &ExportController::wrote, m_status, &QLabel::setText);
  connect(m_exports, &ExportController::exportedTo, m_files, &FileMenu::rememberExportDir);

  connect(&m_maps, &MapController::started, this, &MainWindow::onMapStarted);
  connect(&m_maps, &MapController::progress, this, [this](double fraction, const QString& stage) {
    m_mapProgress->setProgress(fraction, stage + " %p%");
    emit progressChanged(fraction);
  });
  connect(&m_maps, &MapController::stopped, m_mapProgress, &JobProgress::stop);
  connect(&m_maps, &MapController::finished, this, &MainWindow::onMapFinished);
  connect(&m_maps, &MapController::failed, this, &MainWindow::onMapFailed);
  connect(&m_maps, &MapController::cancelled, this, &MainWindow::onMapCancelled);
  connect(m_choice, &MapChoice::methodChanged, m_motionMenu, &MotionMenu::setMethod);
  connect(m_choice, &MapChoice::cachedMapReady, this, [this](embed::Method method) {
    showMap();
    emit mapReady(method);
  });
  connect(m_choice, &MapChoice::refused, this, [this](embed::Method wanted) {
    if (const auto shown = m_source->shownMethod()) m_motionMenu->setMethod(*shown);
    // A saved map cannot change: offer to map its clips again instead.
    if (m_saved && m_status->interactive() &&
        askRecompute(this, *m_saved->map(), methodLabel(wanted))) {
      recomputeFromClips(wanted);
      return;
    }
    showError(m_source->refusal(MapSource::Change::Recompute));
  });
  connect(m_choice, &MapChoice::synthChanged, this,
          [this] { m_gestures->setNeighbors(synthParameters().blend.neighbors); });
  connect(m_choice, &MapChoice::failed, this, &MainWindow::showError);

  connect(&m_synthesis, &SynthesisController::progress, this, [this](double fraction) {
    m_synthProgress->setProgress(fraction);
    emit synthesisProgress(fraction);
  });
  connect(&m_synthesis, &SynthesisController::stopped, m_synthProgress, &JobProgress::stop);
  connect(&m_synthesis, &SynthesisController::finished, this, &MainWindow::onSynthesized);
  connect(&m_synthesis, &SynthesisController::failed, this, [this](const QString& error) {
    updateStatus();
    showError(error);
    emit synthesisFinished(false);
  });
  connect(&m_synthesis, &SynthesisController::cancelled, this, [this] {
    updateStatus();
    m_status->setText(tr("Synthesis cancelled"));
    emit synthesisFinished(false);
  });
}

void MainWindow::useSource(MapSource* source) {
  if (m_source) disconnect(m_source, nullptr, this, nullptr);
  m_source = source;
  m_choice->setRecomputable(source->refusal(MapSource::Change::Recompute).isEmpty());
  // The Motion menu checks the method of the map shown (a saved map's own).
  m_motionMenu->setMethod(source->shownMethod().value_or(method()));
  connect(source, &MapSource::clipReady, this, &MainWindow::setCurrentClip);
  connect(source, &MapSource::failed, this, &MainWindow::showError);
  connect(source, &MapSource::busy, this, [this](const QString& text) { m_status->setText(text); });
}

bool MainWindow::openMapFile(const QString& path) {
  if (!confirmDiscard()) return false;
  return attempt([&] {
    auto* saved = new SavedMapSource(path, m_mapView, m_skeletonView, this,  // throws first
                                     [this] { return synthParameters().blend; });
    m_files->remember(path);
    m_maps.stop();
    m_maps.setClips(nullptr);
    dropSynthesizedMotion();
    m_files->exportMapAction()->setEnabled(false);
    m_gestures->setSavedMap(saved->map(), synthParameters().blend.neighbors, saved->loader());
    m_keys->clearPending();
    SavedMapSource* before = std::exchange(m_saved, saved);
    useSource(saved);
    delete before;
    saved->show();
    setWindowTitle(tr("MotionMap Studio — %1").arg(saved->title()));
    setCurrentClip(0, saved->firstFrame());
  });
}

bool MainWindow::recomputeFromClips(embed::Method method) {
  if (!m_saved || !confirmDiscard()) return false;
  std::optional<std::vector<Clip>> clips;
  if (!attempt([&] {
        clips = loadSavedClips(*m_saved->map(), m_status->interactive() ? this : nullptr);
      }) ||
      !clips) {
    return false;  // a clip missing or changed (shown), or cancelled
  }
  closeSavedMap();
  dropSynthesizedMotion();
  if (const QString why = m_computed->openAll(std::move(*clips)); !why.isEmpty()) {
    showError(why);
    return false;
  }
  setWindowTitle(tr("MotionMap Studio — %1").arg(m_computed->title()));
  setCurrentClip(0, 0);
  m_mapView->clearMap(tr("Computing the map…"));
  setMethod(method);
  return true;
}

void MainWindow::closeSavedMap() {
  if (!m_saved) return;
  m_gestures->setSavedMap(nullptr, synthParameters().blend.neighbors, nullptr);
  useSource(m_computed);
  delete std::exchange(m_saved, nullptr);
  m_mapView->clearMap();
}

bool MainWindow::openFile(const QString& path) {
  const QString suffix = QFileInfo(path).suffix().toLower();
  if (suffix == QLatin1String("h5") || suffix == QLatin1String("hdf5")) return openMapFile(path);
  if (!confirmDiscard()) return false;
  return attempt([&] {
    Clip clip = io::load_clip(path.toStdString());
    m_files->remember(path);
    openClip(std::move(clip));
  });
}

void MainWindow::dropSynthesizedMotion() {
  m_synthesis.stop();
  m_synthesis.clear();
  m_player->stop();
  m_takes->clear();  // the takes and their history belong to the clips before
  m_keys->clearPending();
  m_choice->dropPending();
  m_files->exportMotionAction()->setEnabled(false);
}

void MainWindow::openClip(Clip clip) {
  closeSavedMap();
  dropSynthesizedMotion();
  m_computed->open(std::move(clip));
  clipsChanged(0);
}

bool MainWindow::addFile(const QString& path) {
  bool added = false;
  attempt([&] {
    Clip clip = io::load_clip(path.toStdString());
    m_files->remember(path);
    added = addClip(std::move(clip));
  });
  return added;
}

bool MainWindow::addClip(Clip clip) {
  QString why = m_source->refusal(MapSource::Change::AddClip);
  if (why.isEmpty()) why = m_computed->add(std::move(clip));
  if (!why.isEmpty()) {
    showError(why);
    return false;
  }
  clipsChanged(currentFrame());
  return true;
}

void MainWindow::clipsChanged(int frame) {
  setWindowTitle(tr("MotionMap Studio — %1").arg(m_computed->title()));
  if (!m_player->playsTake()) setCurrentClip(currentClip(), frame);
  m_mapView->clearMap(tr("Computing the map…"));
  setMethod(method());
}

void MainWindow::setCurrentClip(int index, int frame) {
  if (m_player->playClip(index, frame)) updateStatus();
}

void MainWindow::onMapStarted(embed::Method method) {
  m_computed->showComputing(method);
  m_mapProgress->start();
  m_files->exportMapAction()->setEnabled(false);
  updateStatus();
}

void MainWindow::onMapFinished(std::shared_ptr<const MapResult> result) {
  m_keys->clearPending();  // placed on the map before
  showMap();
  emit computationFinished(true);
  emit mapReady(result->options.embed.method);
}

void MainWindow::onMapFailed(const QString& message) {
  // The map before (MapController), with its method and parameters (MapChoice), is back.
  if (!showMap()) m_mapView->clearMap(tr("The map could not be computed"));
  showError(message);
  emit computationFinished(false);
}

void MainWindow::onMapCancelled() {
  if (!showMap())
    m_mapView->clearMap(tr("Cancelled. Choose a method in the Motion menu to compute the map."));
  m_status->setText(tr("Computation cancelled"));
  emit computationFinished(false);
}

bool MainWindow::showMap() {
  if (!m_computed->show()) return false;
  updateTakePaths();
  m_files->exportMapAction()->setEnabled(true);
  // The frame again (a dragged pose is replaced), with the pointer on its point of this map.
  m_player->showFrame(currentFrame());
  updateStatus();
  return true;
}

void MainWindow::updateStatus() {
  const QStringList source = m_source->statusParts();
  if (source.isEmpty()) return;  // no clip yet
  // A take playing comes first, its notes with it: the line is cut at the window's edge.
  QStringList parts = m_player->statusParts();
  parts << source;
  if (isSynthesizing()) parts << tr("synthesizing…");
  m_status->showParts(parts);
}

bool MainWindow::confirmDiscard() {
  if (!m_status->interactive()) return true;
  return askDiscard(this, m_takes->list().unexportedNames(),
                    [this](const QString& folder) { return m_exports->exportUnexported(folder); });
}

bool MainWindow::synthesizeAlong(const synth::MapPath& path) {
  // A newer sketch replaces one still being synthesized; the takes before stay.
  if (!m_synthesis.start(m_source->blendSupply(), path, synthParameters())) return false;
  m_takes->sketchStarted();
  m_synthProgress->start();
  updateStatus();
  return true;
}

void MainWindow::onSynthesized() {
  // A new take (made current) or an edited one: playCurrentTake follows when it is current.
  m_takes->takeResult(m_synthesis.resultMap()->parameters);
  updateStatus();
  emit motionSynthesized();
  emit synthesisFinished(true);
}

void MainWindow::updateTakePaths() {
  m_mapView->setTakePaths(m_takes->pathsOn(currentMap()));
}

bool MainWindow::placeKey(const Eigen::Vector2d& point, const QPointF& pixel) {
  return m_keys->click(point, pixel);
}

void MainWindow::retimeKeysDialog() {
  const Take* take = m_keys->keyedTake();
  if (!take || !take->result) {
    showError(tr("Retiming needs an in-between take: Ctrl-click two frames on the map"));
    return;
  }
  QString error;
  if (const auto times = askKeyTimes(this, *take, error)) {
    m_keys->retime(*times);
    return;
  }
  if (!error.isEmpty()) showError(error);
}

bool MainWindow::moveControlPoint(int control, const Eigen::Vector2d& to) {
  if (m_keys->keyedTake()) return m_keys->moveKey(control, to, m_mapView->toWidget(to));
  if (!m_takes->editControlPoint(control, to, synthParameters())) return false;
  m_synthProgress->start();
  updateStatus();
  return true;
}

void MainWindow::parametersDialog() {
  QString error;
  // The library validates: a bad value comes back as its error message.
  const MapResult* map = currentMap();  // k's range: the frames mapped (unknown before a map)
  const int frames = map ? map->map.features->num_samples() : 0;
  if (const auto p = editMapParameters(this, parameters(), frames, error)) return setParameters(*p);
  if (!error.isEmpty()) showError(error);
}

void MainWindow::synthesisDialog() {
  if (const auto p = editSynthParameters(this, synthParameters())) setSynthParameters(*p);
}

ExportContext MainWindow::exportContext() const {
  return m_exports->context(clip(), m_source->shownMethod(),
                            m_player->playsTake() && synthesized());
}

void MainWindow::closeEvent(QCloseEvent* event) {
  if (!confirmDiscard()) return event->ignore();
  m_synthesis.stop();
  m_maps.stop();
  QSettings settings;
  settings.setValue("geometry", saveGeometry());
  settings.setValue("splitter", m_splitter->saveState());
  settings.setValue("lastDir", m_files->lastDir());
  event->accept();
}

void MainWindow::dragEnterEvent(QDragEnterEvent* event) {
  if (event->mimeData()->hasUrls()) event->acceptProposedAction();
}

void MainWindow::dropEvent(QDropEvent* event) {
  FileMenu::openDropped(
      event->mimeData()->urls(), m_maps.clips() && (event->modifiers() & Qt::ControlModifier),
      [this](const QString& path) { return openFile(path); },
      [this](const QString& path) { return addFile(path); });
}

}  // namespace motionmap::studio
