#include "main_window.h"

#include <cmath>
#include <fstream>

#include <QAction>
#include <QActionGroup>
#include <QApplication>
#include <QCheckBox>
#include <QCloseEvent>
#include <QComboBox>
#include <QDragEnterEvent>
#include <QFileDialog>
#include <QFileInfo>
#include <QHBoxLayout>
#include <QKeyEvent>
#include <QLabel>
#include <QMenuBar>
#include <QMessageBox>
#include <QMimeData>
#include <QPainter>
#include <QProgressBar>
#include <QPushButton>
#include <QSettings>
#include <QSlider>
#include <QSplitter>
#include <QStatusBar>
#include <QVBoxLayout>

#include "map_view.h"
#include "motionmap/core/error.h"
#include "motionmap/io/bvh.h"
#include "motionmap/io/load.h"
#include "motionmap/pipeline/map_csv.h"
#include "motionmap/sample/sample_clip.h"
#include "parameter_dialogs.h"
#include "skeleton_view.h"

namespace motionmap::studio {

namespace {
constexpr int kMaxRecent = 8;
constexpr double kNearPixels = 12.0;
constexpr double kSpeeds[] = {0.25, 0.5, 1.0, 2.0, 4.0};
}  // namespace

MainWindow::MainWindow(QWidget* parent) : QMainWindow(parent) {
  if (qEnvironmentVariableIntValue("MOTIONMAP_STUDIO_NO_CONFIRM") != 0) m_interactive = false;
  QSettings settings;
  m_lastDir = settings.value("lastDir").toString();
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

  m_playButton = new QPushButton(tr("Play"));
  m_playButton->setFocusPolicy(Qt::NoFocus);
  m_slider = new QSlider(Qt::Horizontal);
  m_slider->setEnabled(false);
  m_slider->setFocusPolicy(Qt::NoFocus);
  m_speedBox = new QComboBox;
  m_speedBox->setFocusPolicy(Qt::NoFocus);
  m_speedBox->setToolTip(tr("Playback speed"));
  for (double s : kSpeeds) m_speedBox->addItem(QString("%1×").arg(s), s);
  m_speedBox->setCurrentIndex(2);
  m_loopBox = new QCheckBox(tr("Loop"));
  m_loopBox->setFocusPolicy(Qt::NoFocus);
  m_loopBox->setChecked(m_playback.loop());
  auto* transport = new QHBoxLayout;
  transport->addWidget(m_playButton);
  transport->addWidget(m_slider, 1);
  transport->addWidget(m_speedBox);
  transport->addWidget(m_loopBox);
  auto* central = new QWidget;
  auto* layout = new QVBoxLayout(central);
  layout->setContentsMargins(4, 4, 4, 4);
  layout->addWidget(m_splitter, 1);
  layout->addLayout(transport);
  setCentralWidget(central);
  connect(m_playButton, &QPushButton::clicked, this, [this] { isPlaying() ? pause() : play(); });
  connect(m_slider, &QSlider::valueChanged, this, [this](int v) {
    if (v != currentFrame()) setFrame(v);
  });
  connect(m_speedBox, &QComboBox::currentIndexChanged, this,
          [this](int i) { setPlaybackSpeed(m_speedBox->itemData(i).toDouble()); });
  connect(m_loopBox, &QCheckBox::toggled, this, &MainWindow::setLoop);

  buildMenus();
  buildStatusBar();
  connect(m_mapView, &MapView::hovered, this, &MainWindow::onHover);
  connect(m_mapView, &MapView::clicked, this, &MainWindow::onClick);
  connect(m_mapView, &MapView::dragged, this, &MainWindow::onDrag);
  connect(m_mapView, &MapView::sketchFinished, this, &MainWindow::synthesizeAlong);
}

void MainWindow::buildMenus() {
  QMenu* file = menuBar()->addMenu(tr("&File"));
  file->addAction(tr("&Open…"), QKeySequence::Open, this, &MainWindow::openDialog);
  file->addAction(tr("Open &sample golf swing"), this, [this] {
    if (confirmDiscard()) openClip(sample::make_sample_clip(sample::SampleKind::Swing));
  });
  m_recentMenu = file->addMenu(tr("Open &recent"));
  file->addAction(tr("&Add clip to the map…"), QKeySequence(tr("Ctrl+Shift+O")), this,
                  &MainWindow::addDialog);
  m_exportAction = file->addAction(tr("&Export motion…"), QKeySequence(tr("Ctrl+E")), this,
                                   &MainWindow::exportDialog);
  m_exportAction->setEnabled(false);
  m_exportMapAction = file->addAction(tr("Export &map…"), QKeySequence(tr("Ctrl+Shift+E")), this,
                                      &MainWindow::exportMapDialog);
  m_exportMapAction->setEnabled(false);
  file->addSeparator();
  file->addAction(tr("&Quit"), QKeySequence::Quit, this, &QWidget::close);
  updateRecentMenu();

  QMenu* motion = menuBar()->addMenu(tr("&Motion"));
  m_methodGroup = new QActionGroup(this);
  for (embed::Method m : embed::all_methods()) {
    QAction* action = motion->addAction(methodLabel(m));
    action->setCheckable(true);
    action->setChecked(m == m_method);
    action->setData(int(m));
    m_methodGroup->addAction(action);
    connect(action, &QAction::triggered, this, [this, m] { setMethod(m); });
  }
  motion->addSeparator();
  motion->addAction(tr("&Parameters…"), this, &MainWindow::parametersDialog);
  motion->addAction(tr("S&ynthesis…"), this, &MainWindow::synthesisDialog);
  motion->addAction(tr("Show &clip"), this, &MainWindow::showClipMotion);

  QMenu* view = menuBar()->addMenu(tr("&View"));
  QAction* follow = view->addAction(tr("&Follow root"));
  follow->setCheckable(true);
  follow->setChecked(true);
  connect(follow, &QAction::toggled, m_skeletonView, &SkeletonView::setFollowRoot);
  QAction* sketch = view->addAction(tr("&Sketch mode (drag draws a path)"));
  sketch->setCheckable(true);
  sketch->setShortcut(QKeySequence(tr("S")));
  connect(sketch, &QAction::toggled, m_mapView, &MapView::setSketchMode);
  QAction* lens = view->addAction(tr("&Magnifier (wheel: power)"));
  lens->setCheckable(true);
  lens->setShortcut(QKeySequence(tr("M")));
  connect(lens, &QAction::toggled, m_mapView, &MapView::setLensEnabled);
  QAction* shading = view->addAction(tr("Shade &trustworthy blends"));
  shading->setCheckable(true);
  shading->setToolTip(
      tr("Green where a dragged or sketched point is within the blender's reach of the data; "
         "outside, the blend is taken at the data's edge"));
  connect(shading, &QAction::toggled, m_mapView, &MapView::setShadingVisible);
}

void MainWindow::buildStatusBar() {
  m_status = new QLabel(tr("No clip"));
  m_progress = new QProgressBar;
  m_progress->setRange(0, 1000);
  m_progress->setMaximumWidth(200);
  m_progress->hide();
  m_cancelButton = new QPushButton(tr("Cancel"));
  m_cancelButton->hide();
  connect(m_cancelButton, &QPushButton::clicked, this, &MainWindow::cancelComputation);
  m_synthProgress = new QProgressBar;
  m_synthProgress->setRange(0, 1000);
  m_synthProgress->setMaximumWidth(200);
  m_synthProgress->setFormat(tr("Synthesizing %p%"));
  m_synthProgress->hide();
  m_synthCancelButton = new QPushButton(tr("Cancel synthesis"));
  m_synthCancelButton->hide();
  connect(m_synthCancelButton, &QPushButton::clicked, this, &MainWindow::cancelSynthesis);
  statusBar()->addWidget(m_status, 1);
  statusBar()->addPermanentWidget(m_progress);
  statusBar()->addPermanentWidget(m_cancelButton);
  statusBar()->addPermanentWidget(m_synthProgress);
  statusBar()->addPermanentWidget(m_synthCancelButton);
}

void MainWindow::connectControllers() {
  connect(&m_playback, &Playback::frameChanged, this, &MainWindow::showFrame);
  connect(&m_playback, &Playback::playingChanged, this,
          [this](bool playing) { m_playButton->setText(playing ? tr("Pause") : tr("Play")); });

  connect(&m_maps, &MapController::started, this, &MainWindow::onMapStarted);
  connect(&m_maps, &MapController::progress, this, [this](double fraction, const QString& stage) {
    m_progress->setValue(int(fraction * 1000));
    m_progress->setFormat(stage + " %p%");
    emit progressChanged(fraction);
  });
  connect(&m_maps, &MapController::stopped, this, [this] {
    m_progress->hide();
    m_cancelButton->hide();
  });
  connect(&m_maps, &MapController::finished, this, &MainWindow::onMapFinished);
  connect(&m_maps, &MapController::failed, this, &MainWindow::onMapFailed);
  connect(&m_maps, &MapController::cancelled, this, &MainWindow::onMapCancelled);

  connect(&m_synthesis, &SynthesisController::progress, this, [this](double fraction) {
    m_synthProgress->setValue(int(fraction * 1000));
    emit synthesisProgress(fraction);
  });
  connect(&m_synthesis, &SynthesisController::stopped, this, [this] {
    m_synthProgress->hide();
    m_synthCancelButton->hide();
  });
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

bool MainWindow::openFile(const QString& path) {
  if (!confirmDiscard()) return false;
  try {
    Clip clip = io::load_clip(path.toStdString());
    m_lastDir = QFileInfo(path).absolutePath();
    addRecentFile(QFileInfo(path).absoluteFilePath());
    openClip(std::move(clip));
    return true;
  } catch (const std::exception& e) {
    showError(QString::fromStdString(e.what()));
    return false;
  }
}

void MainWindow::openClip(Clip clip) {
  m_synthesis.stop();
  m_synthesis.clear();
  pause();
  m_unsaved = false;
  m_playingSynth = false;
  m_exportAction->setEnabled(false);
  auto clips = std::make_shared<std::vector<Clip>>();
  clips->push_back(std::move(clip));
  m_maps.setClips(std::move(clips));
  m_clipIndex = 0;
  m_skeletonView->setSkeleton(this->clip()->skeleton);
  clipsChanged(0);
}

bool MainWindow::addFile(const QString& path) {
  try {
    Clip clip = io::load_clip(path.toStdString());
    m_lastDir = QFileInfo(path).absolutePath();
    addRecentFile(QFileInfo(path).absoluteFilePath());
    return addClip(std::move(clip));
  } catch (const std::exception& e) {
    showError(QString::fromStdString(e.what()));
    return false;
  }
}

bool MainWindow::addClip(Clip clip) {
  const auto& open = m_maps.clips();
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
  if (!m_maps.clips() || index < 0 || index >= clipCount()) return;
  if (index != m_clipIndex) {
    m_clipIndex = index;
    m_skeletonView->setSkeleton(clip()->skeleton, /*keepCamera=*/true);  // its own bone lengths
  }
  m_playingSynth = false;
  updateMotion();
  m_slider->setEnabled(clip()->motion.num_frames > 0);
  setFrame(frame);
  updateStatus();
}

void MainWindow::setMethod(embed::Method method) {
  m_method = method;
  for (QAction* a : m_methodGroup->actions()) a->setChecked(a->data().toInt() == int(method));
  QSettings().setValue("method", QString::fromUtf8(embed::method_name(method).data()));
  if (m_maps.request(method, m_parameters, m_synthParameters.blend)) {  // cached
    saveParameters();
    showMap();
    emit mapReady(method);
  }
}

void MainWindow::setParameters(const MapParameters& parameters) {
  m_parameters = parameters;
  setMethod(m_method);
}

bool MainWindow::setSynthParameters(const SynthParameters& parameters) {
  try {
    parameters.motion.validate();
    // K is checked against the samples of the map shown; a new clip's map checks it again.
    const MapResult* map = currentMap();
    parameters.blend.validate(map ? map->map.features->num_samples()
                                  : std::numeric_limits<int>::max());
  } catch (const std::exception& e) {
    showError(QString::fromStdString(e.what()));
    return false;
  }
  const bool newBlend = MapController::cacheKey(m_method, m_parameters, parameters.blend) !=
                        MapController::cacheKey(m_method, m_parameters, m_synthParameters.blend);
  m_synthParameters = parameters;
  if (newBlend) {
    setMethod(m_method);  // a blender with the new options: computed, or from the cache
  } else {
    saveParameters();
  }
  return true;
}

void MainWindow::onMapStarted(embed::Method method) {
  m_mapView->clearMap(tr("Computing the %1 map…").arg(methodLabel(method)));
  m_progress->setValue(0);
  m_progress->show();
  m_cancelButton->show();
  m_exportMapAction->setEnabled(false);
  updateStatus();
}

void MainWindow::onMapFinished(std::shared_ptr<const MapResult> result) {
  saveParameters();  // the parameters of a map computed without error are the next session's
  showMap();
  emit computationFinished(true);
  emit mapReady(result->options.embed.method);
}

void MainWindow::onMapFailed(const QString& message) {
  m_mapView->clearMap(tr("The map could not be computed"));
  showError(message);
  updateStatus();
  emit computationFinished(false);
}

void MainWindow::onMapCancelled() {
  m_mapView->clearMap(tr("Cancelled. Choose a method in the Motion menu to compute the map."));
  m_status->setText(tr("Computation cancelled"));
  emit computationFinished(false);
}

render::MapPlotOptions MainWindow::plotOptions(const MapResult& map) const {
  render::MapPlotOptions options;
  options.title = methodLabel(map.map.embedding.method);
  options.time_legend = true;
  if (clipCount() > 1) {  // several clips: colour by clip, named in the legend
    for (const Clip& clip : *m_maps.clips())
      options.clip_names << QFileInfo(QString::fromStdString(clip.path)).fileName();
  }
  // What the library wants the user to know (a bind pose left out, a joined graph) under the map.
  for (const auto& note : map.map.features->notes) options.notes << QString::fromStdString(note);
  for (const auto& warning : map.map.embedding.warnings)
    options.notes << QString::fromStdString(warning);
  return options;
}

void MainWindow::showMap() {
  const MapResult* map = currentMap();
  if (!map) return;
  m_mapView->setMap(map->map.embedding.coordinates, map->map.features->segment_starts,
                    plotOptions(*map));
  // A blend is computed from the data where a sample lies within the blender's reach; farther
  // out, MapBlender::locate moves the point to the data's edge (PointValidity::clamped).
  m_mapView->setShadingReach(map->blender->reach_distance());
  m_exportMapAction->setEnabled(true);
  updatePointer();
  updateStatus();
}

void MainWindow::updateStatus() {
  if (!m_maps.clips()) return;
  QStringList parts;
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

void MainWindow::showError(const QString& message) {
  m_lastError = message;
  m_status->setText(tr("Error: %1").arg(message));
  if (m_interactive) QMessageBox::warning(this, tr("MotionMap Studio"), message);
}

bool MainWindow::confirmDiscard() {
  if (!hasUnsavedMotion() || !m_interactive) return true;
  return QMessageBox::question(
             this, tr("MotionMap Studio"),
             tr("The synthesized motion (%1 frames) has not been exported. Discard it?")
                 .arg(synthesized()->motion.num_frames)) == QMessageBox::Yes;
}

const Motion* MainWindow::playingMotion() const {
  if (m_playingSynth && synthesized()) return &synthesized()->motion;
  return clip() ? &clip()->motion : nullptr;
}

void MainWindow::updateMotion() {
  const Motion* motion = playingMotion();
  const int frames = motion ? motion->num_frames : 0;
  m_playback.setMotion(frames, motion ? motion->frame_time : 0.0);
  m_slider->setRange(0, std::max(0, frames - 1));
}

void MainWindow::showFrame(int frame) {
  const Motion* motion = playingMotion();
  if (!motion) return;
  m_skeletonView->setPose(*motion, frame);
  if (m_slider->value() != frame) {
    const QSignalBlocker block(m_slider);
    m_slider->setValue(frame);
  }
  updatePointer();
  emit frameChanged(frame);
}

void MainWindow::updatePointer() {
  const MapResult* map = currentMap();
  if (!map) return m_mapView->setPointer(std::nullopt);
  const int frame = currentFrame();
  if (m_playingSynth && synthesized()) {
    // Its map points belong to the map it was sketched on.
    const auto& validity = synthesized()->validity;
    const bool sameMap = m_synthesis.resultMap().get() == map && frame < int(validity.size());
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

void MainWindow::setPlaybackSpeed(double speed) {
  m_playback.setSpeed(speed);
  for (int i = 0; i < m_speedBox->count(); ++i) {
    if (m_speedBox->itemData(i).toDouble() == playbackSpeed() && m_speedBox->currentIndex() != i) {
      const QSignalBlocker block(m_speedBox);
      m_speedBox->setCurrentIndex(i);
    }
  }
}

void MainWindow::setLoop(bool loop) {
  m_playback.setLoop(loop);
  if (m_loopBox->isChecked() != loop) {
    const QSignalBlocker block(m_loopBox);
    m_loopBox->setChecked(loop);
  }
}

void MainWindow::showClipMotion() {
  if (!m_playingSynth) return;
  setCurrentClip(m_clipIndex, 0);
}

int MainWindow::sampleNear(const Eigen::Vector2d& point, const QPointF& pixel) const {
  const MapResult* map = currentMap();
  if (!map || !point.allFinite()) return -1;
  // The blender knows the nearest sample (library search); the app only judges the pixel distance.
  const int sample = map->blender->locate(point).validity.nearest_sample;
  const QPointF at = m_mapView->toWidget(map->blender->sample_point(sample));
  return QLineF(at, pixel).length() <= kNearPixels ? sample : -1;
}

void MainWindow::onHover(const Eigen::Vector2d& point, const QPointF& pixel) {
  const int sample = sampleNear(point, pixel);
  const MapResult* map = currentMap();
  if (sample < 0) return m_mapView->setHoverText({});
  const features::FeatureSet& set = *map->map.features;
  const int clip = set.clip_of[std::size_t(sample)];
  m_mapView->setHoverText(
      clipCount() > 1 ? tr("clip %1, frame %2").arg(clip + 1).arg(set.frame_of[std::size_t(sample)])
                      : tr("frame %1").arg(set.frame_of[std::size_t(sample)]));
}

void MainWindow::onClick(const Eigen::Vector2d& point, const QPointF& pixel) {
  const int sample = sampleNear(point, pixel);
  if (sample < 0) return;
  const features::FeatureSet& set = *currentMap()->map.features;
  setCurrentClip(set.clip_of[std::size_t(sample)], set.frame_of[std::size_t(sample)]);
}

void MainWindow::onDrag(const Eigen::Vector2d& point) {
  const MapResult* map = currentMap();
  if (!map || isPlaying() || !point.allFinite()) return;
  try {
    const synth::MapWeights weights = map->blender->locate(point);
    m_skeletonView->setPose(map->blender->pose(weights), 0);
    const synth::PointValidity& validity = weights.validity;
    m_mapView->setPointer(validity.point);
    m_mapView->setHoverText(validity.clamped ? tr("blend (outside the data: moved to its edge)")
                                             : tr("blend"));
  } catch (const std::exception& e) {
    showError(QString::fromStdString(e.what()));
  }
}

bool MainWindow::synthesizeAlong(const synth::MapPath& path) {
  std::shared_ptr<const MapResult> map = m_maps.current();
  if (!map || !confirmDiscard()) return false;
  // A newer sketch replaces one still being synthesized.
  if (!m_synthesis.start(std::move(map), path, m_synthParameters)) return false;
  m_synthProgress->setValue(0);
  m_synthProgress->show();
  m_synthCancelButton->show();
  updateStatus();
  return true;
}

void MainWindow::onSynthesized() {
  // The user agreed to replace an unexported motion when the sketch ended (synthesizeAlong).
  pause();
  m_unsaved = true;
  m_playingSynth = true;
  m_exportAction->setEnabled(true);
  updateMotion();
  setFrame(0);
  updateStatus();
  emit motionSynthesized();
  emit synthesisFinished(true);
  play();
}

bool MainWindow::exportMotion(const QString& path) {
  const std::shared_ptr<const MapResult>& map = m_synthesis.resultMap();
  if (!synthesized() || !map) return false;
  try {
    io::write_bvh(io::from_motion(map->blender->skeleton(), synthesized()->motion),
                  path.toStdString());
    m_unsaved = false;
    m_status->setText(tr("Wrote %1").arg(path));
    return true;
  } catch (const std::exception& e) {
    showError(QString::fromStdString(e.what()));
    return false;
  }
}

bool MainWindow::exportMap(const QString& path) {
  const MapResult* map = currentMap();
  if (!map || !m_maps.clips()) return false;
  try {
    if (QFileInfo(path).suffix().compare("csv", Qt::CaseInsensitive) == 0) {
      std::ofstream out(path.toStdString());
      if (!out) throw Error("cannot write " + path.toStdString());
      std::vector<std::string> files;
      for (const Clip& c : *m_maps.clips())
        files.push_back(QFileInfo(QString::fromStdString(c.path)).fileName().toStdString());
      pipeline::write_map_csv(out, map->map, map->options, files);
      if (!out.flush()) throw Error("cannot write " + path.toStdString());
    } else {
      render::MapPlotOptions options = plotOptions(*map);
      options.notes << QString::fromStdString(map->parameters);
      render::save_map_plot(path.toStdString(), map->map.embedding.coordinates,
                            map->map.features->segment_starts, options);
    }
    m_status->setText(tr("Wrote %1").arg(path));
    return true;
  } catch (const std::exception& e) {
    showError(QString::fromStdString(e.what()));
    return false;
  }
}

void MainWindow::openDialog() {
  const QString path = QFileDialog::getOpenFileName(
      this, tr("Open clip"), m_lastDir, tr("Motion capture (*.bvh *.amc);;All files (*)"));
  if (!path.isEmpty()) openFile(path);
}

void MainWindow::addDialog() {
  const QStringList paths =
      QFileDialog::getOpenFileNames(this, tr("Add clips of the same skeleton"), m_lastDir,
                                    tr("Motion capture (*.bvh *.amc);;All files (*)"));
  for (const QString& path : paths) {
    if (!addFile(path)) break;
  }
}

void MainWindow::exportDialog() {
  const QString path =
      QFileDialog::getSaveFileName(this, tr("Export motion"), m_lastDir, tr("BVH (*.bvh)"));
  if (!path.isEmpty()) exportMotion(path);
}

void MainWindow::exportMapDialog() {
  const QString path =
      QFileDialog::getSaveFileName(this, tr("Export map"), m_lastDir,
                                   tr("PNG image (*.png);;SVG drawing (*.svg);;CSV table (*.csv)"));
  if (!path.isEmpty()) exportMap(path);
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

void MainWindow::addRecentFile(const QString& path) {
  QSettings settings;
  QStringList recent = settings.value("recentFiles").toStringList();
  recent.removeAll(path);
  recent.prepend(path);
  while (recent.size() > kMaxRecent) recent.removeLast();
  settings.setValue("recentFiles", recent);
  settings.setValue("lastDir", m_lastDir);
  updateRecentMenu();
}

void MainWindow::updateRecentMenu() {
  m_recentMenu->clear();
  const QStringList recent = QSettings().value("recentFiles").toStringList();
  for (const QString& path : recent) {
    m_recentMenu->addAction(QFileInfo(path).fileName(), this, [this, path] { openFile(path); })
        ->setToolTip(path);
  }
  m_recentMenu->setEnabled(!recent.isEmpty());
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

void MainWindow::closeEvent(QCloseEvent* event) {
  if (!confirmDiscard()) return event->ignore();
  m_synthesis.stop();
  m_maps.stop();
  QSettings settings;
  settings.setValue("geometry", saveGeometry());
  settings.setValue("splitter", m_splitter->saveState());
  settings.setValue("lastDir", m_lastDir);
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

void MainWindow::keyPressEvent(QKeyEvent* event) {
  switch (event->key()) {
    case Qt::Key_Space:
      isPlaying() ? pause() : play();
      break;
    case Qt::Key_Left:
      m_playback.step(-1);
      break;
    case Qt::Key_Right:
      m_playback.step(+1);
      break;
    default:
      QMainWindow::keyPressEvent(event);
  }
}

}  // namespace motionmap::studio
