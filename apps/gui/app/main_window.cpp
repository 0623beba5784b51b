#include "app/main_window.h"

#include <QAction>
#include <QCloseEvent>
#include <QDir>
#include <QDragEnterEvent>
#include <QFileDialog>
#include <QFileInfo>
#include <QInputDialog>
#include <QLabel>
#include <QLineEdit>
#include <QMenuBar>
#include <QMessageBox>
#include <QMimeData>
#include <QPushButton>
#include <QSettings>
#include <QSplitter>
#include <QStatusBar>
#include <QVBoxLayout>

#include "app/file_menu.h"
#include "app/help_dialogs.h"
#include "app/job_progress.h"
#include "app/menus.h"
#include "app/parameter_dialogs.h"
#include "explore/clip_search.h"
#include "explore/map_coordinates.h"
#include "explore/nearest_panel.h"
#include "explore/saved_clips.h"
#include "explore/selection_panel.h"
#include "map/joint_drag.h"
#include "map/map_gestures.h"
#include "map/map_source.h"
#include "map/map_view.h"
#include "motionmap/io/load.h"
#include "motionmap/sample/sample_clip.h"
#include "playback/playback_actions.h"
#include "playback/transport_bar.h"
#include "scene/camera_menu.h"
#include "scene/joint_panel.h"
#include "scene/skeleton_view.h"
#include "takes/keys_controller.h"
#include "takes/takes_panel.h"

namespace motionmap::studio {

MainWindow::MainWindow(QWidget* parent) : QMainWindow(parent) {
  if (qEnvironmentVariableIntValue("MOTIONMAP_STUDIO_NO_CONFIRM") != 0) m_interactive = false;
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
  // Box and lasso selections of the map's frames, listed, played and exported (a dock, shown with
  // the first selection).
  auto* selection = new SelectionPanel(
      m_mapView, &m_playback, [this] { return m_source; },
      [this](int clip, int frame) { setCurrentClip(clip, frame); });
  addDockWidget(Qt::RightDockWidgetArea, selection);
  selection->hide();
  connect(selection, &SelectionPanel::message, this, [this](const QString& text) {
    if (m_status) m_status->setText(text);
  });
  connect(selection, &SelectionPanel::failed, this, &MainWindow::showError);
  auto* nearest = new NearestPanel(
      m_mapView, [this] { return m_source; },
      [this](int clip, int frame) { setCurrentClip(clip, frame); });
  addDockWidget(Qt::RightDockWidgetArea, nearest);
  nearest->hide();
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
  connect(ClipSearch::addTo(this, m_mapView, [this] { return m_source; }),
          &ClipSearch::clipRequested, this, &MainWindow::setCurrentClip);
  connect(m_takes, &TakesController::changed, this, &MainWindow::updateTakePaths);
  connect(&m_takes->list(), &TakeList::currentMotionChanged, this, &MainWindow::playCurrentTake);
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
    if (m_playingSynth) setCurrentClip(currentClip(), 0);
  });
  QMenu* view = addViewMenu(this, m_skeletonView, m_mapView);
  view->addAction(findChild<SelectionPanel*>()->toggleViewAction());
  view->addAction(findChild<NearestPanel*>()->toggleViewAction());
  addCameraMenu(view, m_skeletonView);
  addJointsPanel(this, m_skeletonView, view);
  new PlaybackActions(this, &m_playback);  // Space, arrows, Home/End, I/O: window shortcuts
  addHelpMenu(this);
}

void MainWindow::buildStatusBar() {
  m_status = new QLabel(tr("No clip"));
  statusBar()->addWidget(m_status, 1);
  statusBar()->addPermanentWidget(new MapCoordinates(m_mapView));
  m_mapProgress = new JobProgress(statusBar(), tr("Cancel"));
  connect(m_mapProgress, &JobProgress::cancelClicked, this, &MainWindow::cancelComputation);
  m_synthProgress = new JobProgress(statusBar(), tr("Cancel synthesis"), tr("Synthesizing %p%"));
  connect(m_synthProgress, &JobProgress::cancelClicked, this, &MainWindow::cancelSynthesis);
}

void MainWindow::connectControllers() {
  connect(&m_playback, &Playback::frameChanged, this, &MainWindow::showFrame);
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
    if (m_saved && m_interactive && askRecompute(this, *m_saved->map(), methodLabel(wanted))) {
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

const mapfile::SavedMap* MainWindow::savedMap() const {
  return m_saved ? m_saved->map().get() : nullptr;
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
  if (!attempt([&] { clips = loadSavedClips(*m_saved->map(), m_interactive ? this : nullptr); }) ||
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
  pause();
  m_playingSynth = false;
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
  if (!m_playingSynth) setCurrentClip(currentClip(), frame);
  m_mapView->clearMap(tr("Computing the map…"));
  setMethod(method());
}

void MainWindow::setCurrentClip(int index, int frame) {
  if (!m_source->selectClip(index, frame)) return;  // out of range, failed, or loading
  m_playingSynth = false;
  m_takes->list().setCurrent(-1);  // the clip plays: no take is current
  updateMotion();
  setFrame(frame);
  updateStatus();
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
  showFrame(currentFrame());
  updateStatus();
  return true;
}

void MainWindow::updateStatus() {
  QStringList parts = m_source->statusParts();
  if (parts.isEmpty()) return;  // no clip yet
  if (m_playingSynth && synthesized()) {
    parts << tr("synthesized: %1 frames, %2 outside the data")
                 .arg(synthesized()->motion.num_frames)
                 .arg(synthesized()->clamped_frames);
  }
  if (isSynthesizing()) parts << tr("synthesizing…");
  m_status->setText(parts.join(QStringLiteral(" · ")));
}

QString MainWindow::statusText() const {
  return m_status->text();
}

bool MainWindow::attempt(const std::function<void()>& work) {
  try {
    work();
    return true;
  } catch (const std::exception& e) {
    showError(QString::fromStdString(e.what()));
    return false;
  }
}

void MainWindow::showError(const QString& message) {
  m_lastError = message;
  m_status->setText(tr("Error: %1").arg(message));
  if (m_interactive) QMessageBox::warning(this, tr("MotionMap Studio"), message);
}

bool MainWindow::confirmDiscard() {
  const QStringList unexported = m_takes->list().unexportedNames();
  if (unexported.isEmpty() || !m_interactive) return true;
  const QString text = unexported.size() == 1
                           ? tr("%1 has not been exported.").arg(unexported.front())
                           : tr("%1 takes have not been exported (%2).")
                                 .arg(unexported.size())
                                 .arg(unexported.join(", "));
  QMessageBox box(QMessageBox::Question, tr("MotionMap Studio"), text,
                  QMessageBox::Save | QMessageBox::Discard | QMessageBox::Cancel, this);
  box.button(QMessageBox::Save)
      ->setText(unexported.size() == 1 ? tr("Export…") : tr("Export All…"));
  box.setDefaultButton(QMessageBox::Save);
  switch (box.exec()) {
    case QMessageBox::Discard:
      return true;
    case QMessageBox::Save: {
      const QString folder =
          QFileDialog::getExistingDirectory(this, tr("Export the takes as BVH into"));
      return !folder.isEmpty() && m_exports->exportUnexported(folder);
    }
    default:
      return false;
  }
}

const synth::SynthResult* MainWindow::synthesized() const {
  const Take* take = m_takes->list().currentTake();
  return take ? take->result.get() : nullptr;
}

const Motion* MainWindow::playingMotion() const {
  if (m_playingSynth && synthesized()) return &synthesized()->motion;
  return clip() ? &clip()->motion : nullptr;
}

void MainWindow::updateMotion() {
  const Motion* motion = playingMotion();
  m_playback.setMotion(motion ? motion->num_frames : 0, motion ? motion->frame_time : 0.0);
  m_files->setMotionShown(motion != nullptr);
  if (motion) m_skeletonView->setMotion(*motion);  // bones, clip bounds, trails
}

void MainWindow::showFrame(int frame) {
  const Motion* motion = playingMotion();
  if (!motion) return;
  m_skeletonView->setPose(*motion, frame);
  updatePointer();
  emit frameChanged(frame);
}

void MainWindow::updatePointer() {
  const int frame = currentFrame();
  m_mapView->setPointer(m_playingSynth && synthesized() ? m_takes->pointOn(currentMap(), frame)
                                                        : m_source->framePoint(frame));
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

void MainWindow::playCurrentTake() {
  const Take* take = m_takes->list().currentTake();
  m_files->exportMotionAction()->setEnabled(take != nullptr);
  if (!take) {
    if (m_playingSynth) setCurrentClip(currentClip(), 0);  // its take is gone: the clip again
    return;
  }
  pause();
  m_playingSynth = true;
  updateMotion();
  setFrame(0);
  updateStatus();
  play();
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
  // The keys' times now (seconds from the first key), as the dialog's starting text.
  QStringList now;
  const double dt = take->result->motion.frame_time;
  for (const int frame : take->controls)
    now << QString::number((frame - take->controls.front()) * dt, 'g', 4);
  bool ok = false;
  const QString text = QInputDialog::getText(
      this, tr("Retime keys"),
      tr("Each key's time in seconds from the first, separated by commas (empty: the frames' own "
         "speed along the route):"),
      QLineEdit::Normal, now.join(", "), &ok);
  if (!ok) return;
  std::vector<double> times;
  for (const QString& part : text.split(',', Qt::SkipEmptyParts)) {
    bool number = false;
    const double t = part.trimmed().toDouble(&number);
    if (!number) return showError(tr("'%1' is not a number of seconds").arg(part.trimmed()));
    times.push_back(t);
  }
  m_keys->retime(times);
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
  return m_exports->context(clip(), m_source->shownMethod(), m_playingSynth && synthesized());
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
  // The first file opens (replacing the clip), more files dropped together join its map;
  // with Ctrl held every file joins the open map.
  const auto urls = event->mimeData()->urls();
  bool add = m_maps.clips() && (event->modifiers() & Qt::ControlModifier);
  for (const QUrl& url : urls) {
    if (!url.isLocalFile()) continue;
    if (!(add ? addFile(url.toLocalFile()) : openFile(url.toLocalFile()))) break;
    add = true;
  }
}

}  // namespace motionmap::studio
