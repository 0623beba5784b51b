#include "app/main_window.h"

#include <QAction>
#include <QCloseEvent>
#include <QDir>
#include <QDragEnterEvent>
#include <QFileInfo>
#include <QLabel>
#include <QMenuBar>
#include <QMessageBox>
#include <QMimeData>
#include <QPainter>
#include <QSettings>
#include <QSplitter>
#include <QStatusBar>
#include <QVBoxLayout>

#include "app/file_menu.h"
#include "app/help_dialogs.h"
#include "app/job_progress.h"
#include "app/menus.h"
#include "app/parameter_dialogs.h"
#include "export/map_export.h"
#include "export/picture_export.h"
#include "map/clip_loader.h"
#include "map/map_gestures.h"
#include "map/map_view.h"
#include "motionmap/io/bvh.h"
#include "motionmap/io/load.h"
#include "motionmap/mapfile/saved_map.h"
#include "motionmap/sample/sample_clip.h"
#include "playback/playback_actions.h"
#include "playback/transport_bar.h"
#include "scene/camera_menu.h"
#include "scene/joint_panel.h"
#include "scene/skeleton_view.h"
#include "takes/takes_panel.h"

namespace motionmap::studio {

namespace {
/// Clips of a saved map kept loaded: a drag blends samples of many clips (a library's variants of
/// one motion lie side by side on its map); 32 clips of 6 000 frames are about 300 MB.
constexpr int kSavedMapCachedClips = 32;
}  // namespace

MainWindow::MainWindow(QWidget* parent) : QMainWindow(parent) {
  if (qEnvironmentVariableIntValue("MOTIONMAP_STUDIO_NO_CONFIRM") != 0) m_interactive = false;
  QSettings settings;
  if (const auto m =
          embed::parse_method(settings.value("method", "isomap").toString().toStdString()))
    m_method = *m;
  m_parameters = readMapParameters(settings);
  m_synthParameters = readSynthParameters(settings);
  buildUi();
  connectControllers();
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
  m_takesPanel = new TakesPanel(m_takes);
  addDockWidget(Qt::RightDockWidgetArea, m_takesPanel);
  m_takesPanel->hide();  // until the first sketch (Edit → Takes panel shows it)

  buildMenus();
  buildStatusBar();
  m_gestures = new MapGestures(&m_maps, m_mapView, m_skeletonView, &m_playback, this);
  m_loader = new ClipLoader(this);
  connect(m_loader, &ClipLoader::loaded, this, [this](int c) {
    if (c != m_wantClip) return;
    m_wantClip = -1;
    setCurrentClip(c, m_wantFrame);
  });
  connect(m_loader, &ClipLoader::failed, this, [this](int c, const QString& message) {
    if (c != m_wantClip) return;
    m_wantClip = -1;
    updateStatus();
    showError(message);
  });
  connect(m_gestures, &MapGestures::frameClicked, this, &MainWindow::setCurrentClip);
  connect(m_gestures, &MapGestures::failed, this, &MainWindow::showError);
  connect(m_mapView, &MapView::sketchFinished, this, &MainWindow::synthesizeAlong);
  connect(m_mapView, &MapView::controlPointMoved, this, &MainWindow::moveControlPoint);
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

  m_motionMenu = new MotionMenu(this, m_method);
  connect(m_motionMenu, &MotionMenu::methodChosen, this, &MainWindow::setMethod);
  connect(m_motionMenu, &MotionMenu::parametersRequested, this, &MainWindow::parametersDialog);
  connect(m_motionMenu, &MotionMenu::synthesisRequested, this, &MainWindow::synthesisDialog);
  connect(m_motionMenu, &MotionMenu::showClipRequested, this, &MainWindow::showClipMotion);
  QMenu* view = addViewMenu(this, m_skeletonView, m_mapView);
  addCameraMenu(view, m_skeletonView);
  addJointsPanel(this, m_skeletonView, view);
  new PlaybackActions(this, &m_playback);  // Space, arrows, Home/End, I/O: window shortcuts
  addHelpMenu(this);
}

void MainWindow::buildStatusBar() {
  m_status = new QLabel(tr("No clip"));
  statusBar()->addWidget(m_status, 1);
  m_mapProgress = new JobProgress(statusBar(), tr("Cancel"));
  connect(m_mapProgress, &JobProgress::cancelClicked, this, &MainWindow::cancelComputation);
  m_synthProgress = new JobProgress(statusBar(), tr("Cancel synthesis"), tr("Synthesizing %p%"));
  connect(m_synthProgress, &JobProgress::cancelClicked, this, &MainWindow::cancelSynthesis);
}

void MainWindow::connectControllers() {
  connect(&m_playback, &Playback::frameChanged, this, &MainWindow::showFrame);

  connect(&m_maps, &MapController::started, this, &MainWindow::onMapStarted);
  connect(&m_maps, &MapController::progress, this, [this](double fraction, const QString& stage) {
    m_mapProgress->setProgress(fraction, stage + " %p%");
    emit progressChanged(fraction);
  });
  connect(&m_maps, &MapController::stopped, m_mapProgress, &JobProgress::stop);
  connect(&m_maps, &MapController::finished, this, &MainWindow::onMapFinished);
  connect(&m_maps, &MapController::failed, this, &MainWindow::onMapFailed);
  connect(&m_maps, &MapController::cancelled, this, &MainWindow::onMapCancelled);

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

const Clip* MainWindow::clip() const {
  if (m_saved) return m_savedClip.get();
  return m_maps.clips() ? &(*m_maps.clips())[std::size_t(m_clipIndex)] : nullptr;
}

int MainWindow::clipCount() const {
  if (m_saved) return m_saved->num_clips();
  return m_maps.clips() ? int(m_maps.clips()->size()) : 0;
}

bool MainWindow::isLoadingClip() const {
  return m_loader->pending() > 0;
}

bool MainWindow::openMapFile(const QString& path) {
  if (!confirmDiscard()) return false;
  return attempt([&] {
    auto saved = std::make_shared<const mapfile::SavedMap>(
        mapfile::read_map_file(path.toStdString(), {.model = false}), kSavedMapCachedClips);
    // Its first clip: loaded now, so a map whose clips are gone says so at once.
    std::shared_ptr<const Clip> first = saved->clip(0);
    m_files->remember(path);
    m_maps.stop();
    m_maps.setClips(nullptr);
    dropSynthesizedMotion();
    m_files->exportMapAction()->setEnabled(false);
    m_saved = saved;
    m_savedClip.reset();
    m_clipIndex = -1;
    m_wantClip = -1;
    m_loader->setMap(m_saved);
    m_gestures->setSavedMap(m_saved, m_synthParameters.blend.neighbors, m_loader);
    const mapfile::MapFile& file = m_saved->file();
    render::MapPlotOptions options;
    options.line_width = 1.0;  // the density shows between the strokes
    m_mapView->setDensityMap(std::shared_ptr<const Eigen::MatrixXd>(m_saved, &file.coordinates),
                             Eigen::MatrixXd(0, 2), options);
    m_mapView->setShadingAvailable(false);
    setWindowTitle(tr("MotionMap Studio — %1 (%2 points, %3 clips)")
                       .arg(QFileInfo(path).fileName())
                       .arg(file.num_samples())
                       .arg(m_saved->num_clips()));
    setCurrentClip(0, file.frame_of.empty() ? 0 : file.frame_of.front());
  });
}

void MainWindow::closeSavedMap() {
  if (!m_saved) return;
  m_saved.reset();
  m_savedClip.reset();
  m_savedRowOfFrame.clear();
  m_wantClip = -1;
  m_loader->setMap(nullptr);
  m_gestures->setSavedMap(nullptr, m_synthParameters.blend.neighbors, nullptr);
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
  m_pendingMapChange.reset();
  m_files->exportMotionAction()->setEnabled(false);
}

void MainWindow::openClip(Clip clip) {
  closeSavedMap();
  dropSynthesizedMotion();
  auto clips = std::make_shared<std::vector<Clip>>();
  clips->push_back(std::move(clip));
  m_maps.setClips(std::move(clips));
  m_clipIndex = 0;
  m_skeletonView->setSkeleton(this->clip()->skeleton);
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
  const auto& open = m_maps.clips();
  if (m_saved) {
    showError(
        tr("A saved map is open: clips cannot join it without refitting (open a clip to "
           "start a new map, or place clips on the map with `motionmap map NEW --onto`)"));
    return false;
  }
  if (!open) {
    showError(tr("Open a clip first: added clips join its map"));
    return false;
  }
  if (!clip.skeleton.same_hierarchy(open->front().skeleton)) {
    showError(
        tr("%1 has another skeleton than %2 (joint names or parents differ): it cannot join the "
           "map")
            .arg(QString::fromStdString(clip.path), QString::fromStdString(open->front().path)));
    return false;
  }
  // A new set: the worker may still read the old one, so it is copied, never changed in place.
  auto clips = std::make_shared<std::vector<Clip>>(*open);
  clips->push_back(std::move(clip));
  m_maps.setClips(std::move(clips));
  clipsChanged(currentFrame());
  return true;
}

void MainWindow::clipsChanged(int frame) {
  const std::vector<Clip>& clips = *m_maps.clips();
  QString title = QFileInfo(QString::fromStdString(clips.front().path)).fileName();
  if (clips.size() > 1) title += tr(" + %n more", nullptr, int(clips.size()) - 1);
  setWindowTitle(tr("MotionMap Studio — %1").arg(title));
  if (!m_playingSynth) setCurrentClip(m_clipIndex, frame);
  m_mapView->clearMap(tr("Computing the map…"));
  setMethod(m_method);
}

void MainWindow::setCurrentClip(int index, int frame) {
  if (m_saved) {
    if (index < 0 || index >= clipCount()) return;
    if (index != m_clipIndex || !m_savedClip) {
      if (const auto why = m_loader->failure(index)) return showError(*why);
      if (!m_loader->request(index)) {  // loading on the worker: the jump follows its arrival
        m_wantClip = index;
        m_wantFrame = frame;
        m_status->setText(
            tr("Loading clip %1 of %2 (%3)…")
                .arg(index + 1)
                .arg(clipCount())
                .arg(QString::fromStdString(m_saved->file().clips[std::size_t(index)].path)));
        return;
      }
      m_wantClip = -1;
      std::shared_ptr<const Clip> loaded;
      if (!attempt([&] { loaded = m_saved->clip(index); })) return;  // the clip before stays
      const bool first = !m_savedClip;
      m_savedClip = std::move(loaded);
      m_clipIndex = index;
      m_skeletonView->setSkeleton(m_savedClip->skeleton, /*keepCamera=*/!first);
      const mapfile::MapFile& file = m_saved->file();
      const mapfile::ClipRecord& record = file.clips[std::size_t(index)];
      m_savedRowOfFrame.assign(std::size_t(m_savedClip->motion.num_frames), -1);
      for (int r = record.first_sample; r < record.first_sample + record.samples; ++r)
        m_savedRowOfFrame[std::size_t(file.frame_of[std::size_t(r)])] = r;
      m_mapView->setTrajectory(file.coordinates.middleRows(record.first_sample, record.samples));
    }
    m_playingSynth = false;
    m_takes->list().setCurrent(-1);  // the clip plays: no take is current
    updateMotion();
    setFrame(frame);
    updateStatus();
    return;
  }
  if (!m_maps.clips() || index < 0 || index >= clipCount()) return;
  if (index != m_clipIndex) {
    m_clipIndex = index;
    m_skeletonView->setSkeleton(clip()->skeleton, /*keepCamera=*/true);  // its own bone lengths
  }
  m_playingSynth = false;
  m_takes->list().setCurrent(-1);  // the clip plays: no take is current
  updateMotion();
  setFrame(frame);
  updateStatus();
}

void MainWindow::setMethod(embed::Method method) {
  if (m_saved) {
    m_motionMenu->setMethod(m_saved->file().options.embed.method);
    showError(tr("The saved map is shown as it was made (%1); open clips to compute maps of "
                 "other methods")
                  .arg(QString::fromStdString(m_saved->file().parameters)));
    return;
  }
  const MapState before = mapState();
  m_method = method;
  m_motionMenu->setMethod(method);
  if (method != before.method) recordMapChange(before, tr("method %1").arg(methodLabel(method)));
  QSettings().setValue("method", QString::fromUtf8(embed::method_name(method).data()));
  if (m_maps.request(method, m_parameters, m_synthParameters.blend)) {  // cached
    commitMapChange();
    saveParameters();
    showMap();
    emit mapReady(method);
  }
}

void MainWindow::setParameters(const MapParameters& parameters) {
  const MapState before = mapState();
  m_parameters = parameters;
  if (!m_saved && !(parameters == before.parameters)) recordMapChange(before, tr("map parameters"));
  setMethod(m_method);
}

void MainWindow::recordMapChange(const MapState& before, const QString& text) {
  if (m_takes->applying()) return;  // an undo or redo: already in the history
  if (m_pendingMapChange) {
    m_pendingMapChange->text = text;  // from the map still shown, to the latest asked for
  } else {
    m_pendingMapChange = PendingMapChange{before, text};
  }
}

void MainWindow::commitMapChange() {
  if (!m_pendingMapChange) return;
  const PendingMapChange change = *std::exchange(m_pendingMapChange, std::nullopt);
  const MapState now = mapState();
  if (change.before.method == now.method && change.before.parameters == now.parameters &&
      sameSynthParameters(change.before.synth, now.synth))
    return;
  m_takes->recordMapChange(change.before, now, change.text,
                           [this](const MapState& state) { applyMapState(state); });
}

MapState MainWindow::mapState() const {
  return {m_method, m_parameters, m_synthParameters};
}

void MainWindow::applyMapState(const MapState& state) {
  m_pendingMapChange.reset();  // an undo or redo replaces a change whose map was still computing
  m_parameters = state.parameters;
  m_synthParameters = state.synth;
  if (m_saved) {
    m_gestures->setSavedMap(m_saved, m_synthParameters.blend.neighbors, m_loader);
    return saveParameters();
  }
  setMethod(state.method);  // its map from the cache when it was shown before
}

bool MainWindow::setSynthParameters(const SynthParameters& parameters) {
  const bool valid = attempt([&] {
    parameters.motion.validate();
    // K is checked against the samples of the map shown; a new clip's map checks it again.
    const MapResult* map = currentMap();
    parameters.blend.validate(map ? map->map.features->num_samples()
                                  : std::numeric_limits<int>::max());
  });
  if (!valid) return false;
  if (!sameSynthParameters(parameters, m_synthParameters))
    recordMapChange(mapState(), tr("synthesis parameters"));
  if (m_saved) {
    m_synthParameters = parameters;
    m_gestures->setSavedMap(m_saved, parameters.blend.neighbors, m_loader);
    commitMapChange();
    saveParameters();
    return true;
  }
  const bool newBlend = MapController::cacheKey(m_method, m_parameters, parameters.blend) !=
                        MapController::cacheKey(m_method, m_parameters, m_synthParameters.blend);
  m_synthParameters = parameters;
  if (newBlend) {
    setMethod(m_method);        // a blender with the new options: computed, or from the cache
  } else if (!isComputing()) {  // else it joins the change whose map is being computed
    commitMapChange();
    saveParameters();
  }
  return true;
}

void MainWindow::onMapStarted(embed::Method method) {
  // The map before stays on screen, greyed, until the new one replaces it (or fails: it is back).
  const QString text = tr("Computing the %1 map…").arg(methodLabel(method));
  if (m_mapView->hasMap()) {
    m_mapView->setBusyText(text);
    m_mapView->setPointer(std::nullopt);
  } else {
    m_mapView->clearMap(text);
  }
  m_mapProgress->start();
  m_files->exportMapAction()->setEnabled(false);
  updateStatus();
}

void MainWindow::onMapFinished(std::shared_ptr<const MapResult> result) {
  commitMapChange();
  saveParameters();  // the parameters of a map computed without error are the next session's
  showMap();
  emit computationFinished(true);
  emit mapReady(result->options.embed.method);
}

void MainWindow::onMapFailed(const QString& message) {
  m_pendingMapChange.reset();
  if (!restoreShownMap()) m_mapView->clearMap(tr("The map could not be computed"));
  showError(message);
  emit computationFinished(false);
}

void MainWindow::onMapCancelled() {
  m_pendingMapChange.reset();
  if (!restoreShownMap())
    m_mapView->clearMap(tr("Cancelled. Choose a method in the Motion menu to compute the map."));
  m_status->setText(tr("Computation cancelled"));
  emit computationFinished(false);
}

bool MainWindow::restoreShownMap() {
  // The map before a failed or cancelled computation is current again (MapController): its
  // method and parameters come back with it, so what is shown is what the menus say.
  const std::optional<MapRequest> shown = m_maps.shownRequest();
  if (shown) {
    m_method = shown->method;
    m_motionMenu->setMethod(m_method);
    QSettings().setValue("method", QString::fromUtf8(embed::method_name(m_method).data()));
    m_parameters = shown->parameters;
    m_synthParameters.blend = shown->blend;
    showMap();
  }
  updateStatus();
  return shown.has_value();
}

void MainWindow::showMap() {
  const MapResult* map = currentMap();
  if (!map) return;
  m_mapView->setMap(map->map.embedding.coordinates, map->map.features->segment_starts,
                    mapPlotOptions(*map, *m_maps.clips()));
  m_mapView->setShadingAvailable(true);
  updateTakePaths();
  m_files->exportMapAction()->setEnabled(true);
  // The frame again (a dragged pose is replaced), with the pointer on its point of this map.
  showFrame(currentFrame());
  updateStatus();
}

void MainWindow::updateStatus() {
  QStringList parts;
  if (m_saved) {
    const mapfile::MapFile& file = m_saved->file();
    parts << tr("map file: %1 points, %2 clips").arg(file.num_samples()).arg(m_saved->num_clips())
          << QString::fromStdString(file.parameters);
    if (m_savedClip) {
      parts << tr("clip %1 of %2: %3")
                   .arg(m_clipIndex + 1)
                   .arg(m_saved->num_clips())
                   .arg(QFileInfo(QString::fromStdString(m_savedClip->path)).fileName())
            << tr("%1 frames").arg(m_savedClip->motion.num_frames)
            << tr("%1 fps").arg(m_savedClip->motion.fps(), 0, 'g', 4);
    }
    m_status->setText(parts.join(QStringLiteral(" · ")));
    return;
  }
  if (!m_maps.clips()) return;
  if (clipCount() > 1) parts << tr("clip %1 of %2").arg(m_clipIndex + 1).arg(clipCount());
  parts << tr("%1 frames").arg(clip()->motion.num_frames)
        << tr("%1 fps").arg(clip()->motion.fps(), 0, 'g', 4);
  if (const MapResult* map = currentMap()) {
    parts << QString::fromStdString(map->parameters) << tr("%1 s").arg(map->seconds, 0, 'f', 2);
    if (map->map.metrics) {
      parts << tr("trustworthiness %1")
                   .arg(map->map.metrics->neighborhood.trustworthiness, 0, 'f', 3);
    }
  } else if (isComputing()) {
    parts << tr("computing %1…").arg(methodLabel(m_method));
  }
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
                           ? tr("%1 has not been exported. Discard it?").arg(unexported.front())
                           : tr("%1 takes have not been exported (%2). Discard them?")
                                 .arg(unexported.size())
                                 .arg(unexported.join(", "));
  return QMessageBox::question(this, tr("MotionMap Studio"), text) == QMessageBox::Yes;
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
  if (m_saved) {
    const int frame = currentFrame();
    const int row = frame >= 0 && frame < int(m_savedRowOfFrame.size())
                        ? m_savedRowOfFrame[std::size_t(frame)]
                        : -1;
    if (row < 0) return m_mapView->setPointer(std::nullopt);
    const auto& xy = m_saved->file().coordinates;
    return m_mapView->setPointer(Eigen::Vector2d(xy(row, 0), xy(row, 1)));
  }
  const MapResult* map = currentMap();
  if (!map) return m_mapView->setPointer(std::nullopt);
  const int frame = currentFrame();
  if (m_playingSynth && synthesized()) {
    // Its map points belong to the map it was sketched on.
    const auto& validity = synthesized()->validity;
    const bool sameMap =
        m_takes->list().currentTake()->map.get() == map && frame < int(validity.size());
    m_mapView->setPointer(sameMap ? std::optional(validity[std::size_t(frame)].point)
                                  : std::nullopt);
    return;
  }
  if (m_clipIndex < int(map->rowOfFrame.size()) &&
      frame < int(map->rowOfFrame[std::size_t(m_clipIndex)].size())) {
    m_mapView->setPointer(
        map->blender->sample_point(map->rowOfFrame[std::size_t(m_clipIndex)][std::size_t(frame)]));
  }
}

void MainWindow::showClipMotion() {
  if (!m_playingSynth) return;
  setCurrentClip(m_clipIndex, 0);
}

bool MainWindow::synthesizeAlong(const synth::MapPath& path) {
  if (m_saved) {
    showError(tr("Sketching on a saved map is not supported in Studio; write the path as CSV and "
                 "run `motionmap synth --map %1 --path PATH.csv -o new.bvh`")
                  .arg(QString::fromStdString(m_saved->file().path)));
    return false;
  }
  std::shared_ptr<const MapResult> map = m_maps.current();
  if (!map) return false;
  // A newer sketch replaces one still being synthesized; the takes before stay.
  if (!m_synthesis.start(std::move(map), path, m_synthParameters)) return false;
  m_takes->sketchStarted();
  m_synthProgress->start();
  updateStatus();
  return true;
}

void MainWindow::onSynthesized() {
  // A new take (made current) or an edited one: playCurrentTake follows when it is current.
  const bool first = m_takes->list().count() == 0;
  m_takes->takeResult(m_synthesis.resultMap()->parameters);
  if (first) m_takesPanel->show();
  updateStatus();
  emit motionSynthesized();
  emit synthesisFinished(true);
}

void MainWindow::playCurrentTake() {
  const Take* take = m_takes->list().currentTake();
  m_files->exportMotionAction()->setEnabled(take != nullptr);
  if (!take) {
    if (m_playingSynth) setCurrentClip(m_clipIndex, 0);  // its take is gone: the clip again
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
  m_mapView->setTakePaths(m_saved ? std::vector<MapView::TakePath>{}
                                  : m_takes->pathsOn(currentMap()));
}

bool MainWindow::moveControlPoint(int control, const Eigen::Vector2d& to) {
  if (!m_takes->editControlPoint(control, to, m_synthParameters)) return false;
  m_synthProgress->start();
  updateStatus();
  return true;
}

bool MainWindow::exportMotion(const QString& path) {
  return exportTake(m_takes->list().current(), path);
}

bool MainWindow::exportTake(int row, const QString& path) {
  if (row < 0 || row >= m_takes->list().count()) return false;
  const Take& take = m_takes->list().at(row);
  if (!take.result || !take.map) return false;
  return attempt([&] {
    io::write_bvh(io::from_motion(take.map->blender->skeleton(), take.result->motion),
                  path.toStdString());
    m_files->rememberExportDir(QFileInfo(path).absolutePath());
    m_takes->list().setExported(row, true);
    m_status->setText(tr("Wrote %1").arg(path));
  });
}

bool MainWindow::exportMap(const QString& path) {
  const MapResult* map = currentMap();
  if (!map) return false;
  return attempt([&] {
    writeMap(path, *map, *m_maps.clips());
    m_status->setText(tr("Wrote %1").arg(path));
  });
}

void MainWindow::parametersDialog() {
  QString error;
  // The library validates: a bad value comes back as its error message.
  if (const auto p = editMapParameters(this, m_parameters, error)) return setParameters(*p);
  if (!error.isEmpty()) showError(error);
}

void MainWindow::synthesisDialog() {
  if (const auto p = editSynthParameters(this, m_synthParameters)) setSynthParameters(*p);
}

void MainWindow::saveParameters() const {
  QSettings settings;
  writeParameters(settings, m_parameters, m_synthParameters);
}

QImage MainWindow::screenshot() {
  QImage image = grab().toImage();
  // Paint the 3-D view's own rendering over its place: a window grab may leave a GL child blank.
  const QImage view = m_skeletonView->renderImage();
  if (!view.isNull()) {
    QPainter painter(&image);
    painter.drawImage(QRect(m_skeletonView->mapTo(this, QPoint(0, 0)), m_skeletonView->size()),
                      view);
  }
  return image;
}

QImage MainWindow::renderPicture(PictureKind kind) {
  return studio::renderPicture(m_skeletonView, m_mapView, kind);
}

QImage MainWindow::renderFrameImage(int frame, PictureKind kind) {
  pause();
  setFrame(frame);  // shows the pose and moves the pointer now (Playback::frameChanged)
  return renderPicture(kind);
}

bool MainWindow::exportPicture(const QString& path, PictureKind kind) {
  return attempt([&] {
    const QImage image = renderPicture(kind);
    savePicture(image, path);
    m_status->setText(tr("Wrote %1 (%2 × %3)").arg(path).arg(image.width()).arg(image.height()));
  });
}

bool MainWindow::exportAnimation(const AnimationSettings& settings) {
  const Motion* motion = playingMotion();
  if (!motion) {
    showError(tr("Open a clip first: the animation is the motion playing"));
    return false;
  }
  const bool wasPlaying = isPlaying();
  const int frameBefore = currentFrame();
  AnimationResult result;
  const bool ok = attempt([&] {
    result = writeAnimationWithProgress(
        this, settings, motion->num_frames, 1.0 / motion->frame_time, [&](int frame) {
          // The progress dialog lets events through: a synthesis finishing would swap the motion.
          if (playingMotion() != motion)
            throw Error("the motion playing changed during the export (a synthesis finished)");
          return renderFrameImage(frame, PictureKind::Both);
        });
  });
  if (playingMotion() == motion) {
    setFrame(frameBefore);
    if (wasPlaying) play();
  }
  if (ok) m_status->setText(animationSummary(result, settings));
  return ok && !result.cancelled;
}

ExportContext MainWindow::exportContext() const {
  ExportContext c;
  if (const Clip* shown = clip()) c.naming.clip = clipBaseName(shown->path);
  if (const MapResult* map = currentMap())
    c.naming.method = QString::fromUtf8(embed::method_name(map->options.embed.method).data());
  else if (m_saved)
    c.naming.method =
        QString::fromUtf8(embed::method_name(m_saved->file().options.embed.method).data());
  c.naming.frame = currentFrame();
  c.naming.synthesized = m_playingSynth && synthesized();
  if (const Take* take = m_takes->list().currentTake()) c.naming.take = take->name;
  if (const Motion* motion = playingMotion()) {
    // The playback's in/out range (I / O), else the whole motion playing.
    c.first = m_playback.inPoint().value_or(0);
    c.last = m_playback.outPoint().value_or(motion->num_frames - 1);
    c.fps = 1.0 / motion->frame_time;
  }
  return c;
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
