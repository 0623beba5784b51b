#include "main_window.h"

#include <cmath>
#include <fstream>

#include <QAction>
#include <QActionGroup>
#include <QApplication>
#include <QCheckBox>
#include <QCloseEvent>
#include <QComboBox>
#include <QDialog>
#include <QDialogButtonBox>
#include <QDoubleSpinBox>
#include <QDragEnterEvent>
#include <QElapsedTimer>
#include <QFileDialog>
#include <QFileInfo>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QKeyEvent>
#include <QLabel>
#include <QLineEdit>
#include <QMenuBar>
#include <QMessageBox>
#include <QMimeData>
#include <QPainter>
#include <QProgressBar>
#include <QPushButton>
#include <QSettings>
#include <QSlider>
#include <QSpinBox>
#include <QSplitter>
#include <QStatusBar>
#include <QVBoxLayout>

#include "map_view.h"
#include "motionmap/core/error.h"
#include "motionmap/io/bvh.h"
#include "motionmap/io/load.h"
#include "motionmap/pipeline/map_csv.h"
#include "motionmap/sample/sample_clip.h"
#include "skeleton_view.h"

namespace motionmap::studio {

namespace {
constexpr int kMaxRecent = 8;
constexpr double kNearPixels = 12.0;
/// Metrics are O(#frames²) on top of the map; beyond this the status bar shows none.
constexpr int kMaxMetricsFrames = 5000;
/// Playback ticks at least this often (ms), so a 30 fps clip at 1× still repaints at 60 Hz
/// when sped up, and frames are chosen by the clock, never by counting ticks.
constexpr int kMaxTickMs = 16;
constexpr double kSpeeds[] = {0.25, 0.5, 1.0, 2.0, 4.0};
}  // namespace

QString methodLabel(embed::Method method) {
  switch (method) {
    case embed::Method::Pca:
      return QStringLiteral("PCA");
    case embed::Method::Svd:
      return QStringLiteral("SVD");
    case embed::Method::Mds:
      return QStringLiteral("MDS");
    case embed::Method::Isomap:
      return QStringLiteral("Isomap");
    case embed::Method::LaplacianEigenmap:
      return QStringLiteral("LE");
    case embed::Method::Lle:
      return QStringLiteral("LLE");
  }
  return {};
}

pipeline::ClipMapOptions MapParameters::options(embed::Method method) const {
  pipeline::ClipMapOptions o;
  o.embed.method = method;
  o.embed.k = k;
  o.embed.heat = heat;
  o.features.features = features;
  o.features.distance = distance;
  o.features.exclude = exclude;
  return o;
}

MainWindow::MainWindow(QWidget* parent) : QMainWindow(parent) {
  if (qEnvironmentVariableIntValue("MOTIONMAP_STUDIO_NO_CONFIRM") != 0) m_interactive = false;
  QSettings settings;
  m_lastDir = settings.value("lastDir").toString();
  if (const auto m =
          embed::parse_method(settings.value("method", "isomap").toString().toStdString()))
    m_method = *m;
  loadParameters();
  buildUi();
  restoreGeometry(settings.value("geometry").toByteArray());
  m_splitter->restoreState(settings.value("splitter").toByteArray());
  setAcceptDrops(true);
  m_timer.setTimerType(Qt::PreciseTimer);
  connect(&m_timer, &QTimer::timeout, this, &MainWindow::onTick);
}

MainWindow::~MainWindow() {
  stopSynthWorker();
  stopWorker();
}

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
  m_loopBox->setChecked(m_loop);
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
    if (v != m_frame) setFrame(v);
  });
  connect(m_speedBox, &QComboBox::currentIndexChanged, this,
          [this](int i) { setPlaybackSpeed(m_speedBox->itemData(i).toDouble()); });
  connect(m_loopBox, &QCheckBox::toggled, this, &MainWindow::setLoop);

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

  connect(m_mapView, &MapView::hovered, this, &MainWindow::onHover);
  connect(m_mapView, &MapView::clicked, this, &MainWindow::onClick);
  connect(m_mapView, &MapView::dragged, this, &MainWindow::onDrag);
  connect(m_mapView, &MapView::sketchFinished, this, &MainWindow::synthesizeAlong);
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
  stopSynthWorker();
  stopWorker();
  pause();
  m_synth.reset();
  m_synthMap.reset();
  m_unsaved = false;
  m_playingSynth = false;
  m_exportAction->setEnabled(false);
  auto clips = std::make_shared<std::vector<Clip>>();
  clips->push_back(std::move(clip));
  m_clips = std::move(clips);
  m_clipIndex = 0;
  m_frame = 0;
  m_skeletonView->setSkeleton(this->clip()->skeleton);
  clipsChanged();
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
  if (!m_clips) {
    showError(tr("Open a clip first: added clips join its map"));
    return false;
  }
  if (!clip.skeleton.same_hierarchy(m_clips->front().skeleton)) {
    showError(
        tr("%1 has another skeleton than %2 (joint names or parents differ): it cannot join the "
           "map")
            .arg(QString::fromStdString(clip.path), QString::fromStdString(m_clips->front().path)));
    return false;
  }
  // A new set: the worker may still read the old one, so it is copied, never changed in place.
  stopWorker();
  auto clips = std::make_shared<std::vector<Clip>>(*m_clips);
  clips->push_back(std::move(clip));
  m_clips = std::move(clips);
  clipsChanged();
  return true;
}

void MainWindow::clipsChanged() {
  m_maps.clear();  // maps (and blenders) belong to one set of clips
  m_featureCache = std::make_shared<pipeline::FeatureCache>();
  QString title = QFileInfo(QString::fromStdString(m_clips->front().path)).fileName();
  if (m_clips->size() > 1) title += tr(" + %n more", nullptr, int(m_clips->size()) - 1);
  setWindowTitle(tr("MotionMap Studio — %1").arg(title));
  if (!m_playingSynth) setCurrentClip(m_clipIndex, m_frame);
  m_mapView->clearMap(tr("Computing the map…"));
  setMethod(m_method);
}

void MainWindow::setCurrentClip(int index, int frame) {
  if (!m_clips || index < 0 || index >= clipCount()) return;
  if (index != m_clipIndex) {
    m_clipIndex = index;
    m_skeletonView->setSkeleton(clip()->skeleton, /*keepCamera=*/true);  // its own bone lengths
  }
  m_playingSynth = false;
  m_slider->setRange(0, std::max(0, clip()->motion.num_frames - 1));
  m_slider->setEnabled(clip()->motion.num_frames > 0);
  setFrame(frame);
  updateStatus();
}

std::string MainWindow::cacheKey(embed::Method method) const {
  // Appends only: g++ 12 warns (-Wrestrict, a false positive) on "literal" + std::string&&.
  std::string key(embed::method_name(method));
  key.append("|k=").append(std::to_string(m_parameters.k));
  key.append("|heat=").append(
      m_parameters.heat ? QString::number(*m_parameters.heat, 'g', 17).toStdString() : "auto");
  key.append("|").append(features::feature_kind_name(m_parameters.features));
  key.append("|").append(features::distance_kind_name(m_parameters.distance));
  key.append("|exclude=").append(m_parameters.exclude);
  // The blender is part of a cached map.
  const synth::BlendOptions& blend = m_synthParameters.blend;
  key.append("|blend=").append(synth::blend_mode_name(blend.mode));
  key.append(",").append(std::to_string(blend.neighbors));
  key.append(",").append(QString::number(blend.reach, 'g', 17).toStdString());
  return key;
}

void MainWindow::setMethod(embed::Method method) {
  m_method = method;
  for (QAction* a : m_methodGroup->actions()) a->setChecked(a->data().toInt() == int(method));
  QSettings().setValue("method", QString::fromUtf8(embed::method_name(method).data()));
  if (!m_clips) return;
  if (m_maps.count(cacheKey(method))) {
    if (isComputing()) stopWorker();
    saveParameters();
    showMap();
    emit mapReady(method);
    return;
  }
  startComputation(method);
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
  const std::string before = cacheKey(m_method);
  m_synthParameters = parameters;
  if (cacheKey(m_method) != before) {
    setMethod(m_method);  // a blender with the new options: computed, or from the cache
  } else {
    saveParameters();
  }
  return true;
}

const MapResult* MainWindow::currentMap() const {
  if (isComputing()) return nullptr;
  const auto it = m_maps.find(cacheKey(m_method));
  return it == m_maps.end() ? nullptr : it->second.get();
}

void MainWindow::startComputation(embed::Method method) {
  stopWorker();
  m_mapView->clearMap(tr("Computing the %1 map…").arg(methodLabel(method)));
  m_progress->setValue(0);
  m_progress->show();
  m_cancelButton->show();
  m_exportMapAction->setEnabled(false);
  updateStatus();
  std::shared_ptr<const std::vector<Clip>> clips = m_clips;
  const pipeline::ClipMapOptions base = m_parameters.options(method);
  synth::BlendOptions blend = m_synthParameters.blend;
  blend.up = base.features.up;
  const std::string key = cacheKey(method);
  std::shared_ptr<pipeline::FeatureCache> cache = m_featureCache;
  m_mapJob.start([this, clips, cache, method, base, blend,
                  key](const BackgroundJob::Ticket& ticket) {
    const int generation = ticket.generation;
    auto result = std::make_shared<MapResult>();
    QString error;
    bool cancelled = false;
    try {
      pipeline::ClipMapOptions options = base;
      int frames = 0;
      for (const Clip& c : *clips) frames += c.motion.num_frames;
      options.metrics = frames <= kMaxMetricsFrames;
      // Callbacks run on this thread: hand progress to the GUI thread, read cancel atomically.
      const Control control(
          [this, generation](double fraction, std::string_view stage) {
            const QString text = QString::fromUtf8(stage.data(), qsizetype(stage.size()));
            QMetaObject::invokeMethod(
                this,
                [this, generation, fraction, text] {
                  if (!m_mapJob.current(generation)) return;
                  m_progress->setValue(int(fraction * 1000));
                  m_progress->setFormat(text + " %p%");
                  emit progressChanged(fraction);
                },
                Qt::QueuedConnection);
          },
          [ticket] { return ticket.cancelled(); });
      QElapsedTimer clock;
      clock.start();
      result->map = pipeline::map_clips(*clips, options, control, cache.get());
      if (ticket.cancelled()) throw Cancelled();
      result->parameters = pipeline::describe_parameters(result->map.embedding, options);
      // The blender's set-up stays off the GUI thread too. Kriging factors an (N+1)² system at
      // once (about half a minute at 10 000 points) and cannot poll: a cancel leaves it behind.
      const std::shared_ptr<const MapResult> computed = result;
      result->blender =
          runUninterruptible<std::unique_ptr<synth::MapBlender>>(ticket, [clips, computed, blend] {
            return std::make_unique<synth::MapBlender>(*clips, *computed->map.features,
                                                       computed->map.embedding.coordinates, blend);
          });
      result->seconds = double(clock.nsecsElapsed()) * 1e-9;
      result->options = options;
      // Frames left out of the map (a bind pose) show the row of the nearest earlier frame of
      // their clip (or its first row).
      const features::FeatureSet& set = *result->map.features;
      result->rowOfFrame.resize(clips->size());
      for (std::size_t c = 0; c < clips->size(); ++c) {
        const int first = set.segment_starts[c];
        const int end =
            c + 1 < set.segment_starts.size() ? set.segment_starts[c + 1] : set.num_samples();
        std::vector<int>& rows = result->rowOfFrame[c];
        rows.assign(std::size_t(std::max(0, (*clips)[c].motion.num_frames)), first);
        int row = first;
        for (int f = 0; f < int(rows.size()); ++f) {
          while (row + 1 < end && set.frame_of[std::size_t(row + 1)] <= f) ++row;
          rows[std::size_t(f)] = row;
        }
      }
    } catch (const Cancelled&) {
      cancelled = true;
    } catch (const std::exception& e) {
      error = QString::fromStdString(e.what());
    }
    QMetaObject::invokeMethod(
        this,
        [this, generation, method, key, result, error, cancelled] {
          onComputed(generation, method, key, result, error, cancelled);
        },
        Qt::QueuedConnection);
  });
}

void MainWindow::stopWorker() {
  if (!m_mapJob.stop()) return;  // results still queued from it are ignored from now on
  m_progress->hide();
  m_cancelButton->hide();
}

void MainWindow::cancelComputation() {
  if (!isComputing()) return;
  stopWorker();
  m_mapView->clearMap(tr("Cancelled. Choose a method in the Motion menu to compute the map."));
  m_status->setText(tr("Computation cancelled"));
  emit computationFinished(false);
}

void MainWindow::onComputed(int generation, embed::Method method, std::string key,
                            std::shared_ptr<MapResult> result, QString error, bool cancelled) {
  if (!m_mapJob.current(generation)) return;
  m_mapJob.finish();
  m_progress->hide();
  m_cancelButton->hide();
  if (cancelled || !error.isEmpty()) {
    m_mapView->clearMap(cancelled ? tr("Cancelled") : tr("The map could not be computed"));
    if (!error.isEmpty()) showError(error);
    updateStatus();
    emit computationFinished(false);
    return;
  }
  m_maps[key] = std::move(result);
  if (key == cacheKey(m_method)) saveParameters();
  if (method == m_method) showMap();
  emit computationFinished(true);
  emit mapReady(method);
}

render::MapPlotOptions MainWindow::plotOptions(const MapResult& map) const {
  render::MapPlotOptions options;
  options.title = methodLabel(map.map.embedding.method);
  options.time_legend = true;
  if (m_clips && m_clips->size() > 1) {  // several clips: colour by clip, named in the legend
    for (const Clip& clip : *m_clips)
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
  if (!m_clips) return;
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
  if (m_playingSynth && m_synth) {
    parts << tr("synthesized: %1 frames, %2 outside the data")
                 .arg(m_synth->motion.num_frames)
                 .arg(m_synth->clamped_frames);
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
                 .arg(m_synth->motion.num_frames)) == QMessageBox::Yes;
}

const Motion* MainWindow::playingMotion() const {
  if (m_playingSynth && m_synth) return &m_synth->motion;
  return m_clips ? &clip()->motion : nullptr;
}

void MainWindow::showFrame(int frame) {
  const Motion* motion = playingMotion();
  if (!motion || motion->num_frames <= 0) return;
  m_frame = std::clamp(frame, 0, motion->num_frames - 1);
  m_skeletonView->setPose(*motion, m_frame);
  if (m_slider->value() != m_frame) {
    const QSignalBlocker block(m_slider);
    m_slider->setValue(m_frame);
  }
  updatePointer();
  emit frameChanged(m_frame);
}

void MainWindow::setFrame(int frame) {
  showFrame(frame);
  // A jump while playing goes on from there.
  m_playStartFrame = m_frame;
  m_playClock.start();
}

void MainWindow::updatePointer() {
  const MapResult* map = currentMap();
  if (!map) return m_mapView->setPointer(std::nullopt);
  if (m_playingSynth && m_synth) {
    // Its map points belong to the map it was sketched on.
    const bool sameMap = m_synthMap.get() == map && m_frame < int(m_synth->validity.size());
    m_mapView->setPointer(sameMap ? std::optional(m_synth->validity[std::size_t(m_frame)].point)
                                  : std::nullopt);
    return;
  }
  if (m_clipIndex < int(map->rowOfFrame.size()) &&
      m_frame < int(map->rowOfFrame[std::size_t(m_clipIndex)].size())) {
    m_mapView->setPointer(map->blender->sample_point(
        map->rowOfFrame[std::size_t(m_clipIndex)][std::size_t(m_frame)]));
  }
}

void MainWindow::play() {
  const Motion* motion = playingMotion();
  if (!motion || motion->num_frames < 2) return;
  if (!m_loop && m_frame >= motion->num_frames - 1) showFrame(0);  // play again from the start
  m_playStartFrame = m_frame;
  m_playClock.start();
  m_timer.setInterval(
      std::clamp(int(std::lround(motion->frame_time * 1000.0 / m_speed)), 1, kMaxTickMs));
  m_timer.start();
  m_playButton->setText(tr("Pause"));
}

void MainWindow::pause() {
  m_timer.stop();
  m_playButton->setText(tr("Play"));
}

void MainWindow::setPlaybackSpeed(double speed) {
  m_speed = std::clamp(std::isfinite(speed) ? speed : 1.0, 0.05, 8.0);
  for (int i = 0; i < m_speedBox->count(); ++i) {
    if (m_speedBox->itemData(i).toDouble() == m_speed && m_speedBox->currentIndex() != i) {
      const QSignalBlocker block(m_speedBox);
      m_speedBox->setCurrentIndex(i);
    }
  }
  if (isPlaying()) play();  // re-anchors the clock at the current frame
}

void MainWindow::setLoop(bool loop) {
  m_loop = loop;
  if (m_loopBox->isChecked() != loop) {
    const QSignalBlocker block(m_loopBox);
    m_loopBox->setChecked(loop);
  }
}

void MainWindow::onTick() {
  const Motion* motion = playingMotion();
  if (!motion || motion->num_frames == 0) return pause();
  // The frame is the clock's, so playback keeps the clip's rate whatever the tick rate.
  const double elapsed = double(m_playClock.nsecsElapsed()) * 1e-9;
  const long long target =
      m_playStartFrame + (long long)std::floor(elapsed * m_speed / motion->frame_time);
  if (target < motion->num_frames) {
    if (target != m_frame) showFrame(int(target));
  } else if (m_loop) {
    showFrame(int(target % motion->num_frames));
  } else {
    showFrame(motion->num_frames - 1);
    pause();
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
  const auto it = m_maps.find(cacheKey(m_method));
  if (isComputing() || it == m_maps.end() || !confirmDiscard()) return false;
  stopSynthWorker();  // a newer sketch replaces one still being synthesized
  std::shared_ptr<const MapResult> map = it->second;
  m_synthProgress->setValue(0);
  m_synthProgress->show();
  m_synthCancelButton->show();
  const synth::SynthOptions options = m_synthParameters.motion;
  synth::MapPath followed = path;
  if (!m_synthParameters.timedAsDrawn) followed.times.clear();
  m_synthJob.start(
      [this, map, path = std::move(followed), options](const BackgroundJob::Ticket& ticket) {
        const int generation = ticket.generation;
        auto result = std::make_shared<synth::SynthResult>();
        QString error;
        bool cancelled = false;
        try {
          const Control control(
              [this, generation](double fraction, std::string_view) {
                QMetaObject::invokeMethod(
                    this,
                    [this, generation, fraction] {
                      if (!m_synthJob.current(generation)) return;
                      m_synthProgress->setValue(int(fraction * 1000));
                      emit synthesisProgress(fraction);
                    },
                    Qt::QueuedConnection);
              },
              [ticket] { return ticket.cancelled(); });
          *result = synth::synthesize(*map->blender, path, options, control);
          if (ticket.cancelled()) throw Cancelled();
        } catch (const Cancelled&) {
          cancelled = true;
        } catch (const std::exception& e) {
          error = QString::fromStdString(e.what());
        }
        QMetaObject::invokeMethod(
            this,
            [this, generation, map, result, error, cancelled] {
              onSynthesized(generation, map, result, error, cancelled);
            },
            Qt::QueuedConnection);
      });
  updateStatus();
  return true;
}

void MainWindow::stopSynthWorker() {
  if (!m_synthJob.stop()) return;  // a result still queued from it is ignored from now on
  m_synthProgress->hide();
  m_synthCancelButton->hide();
}

void MainWindow::cancelSynthesis() {
  if (!isSynthesizing()) return;
  stopSynthWorker();
  updateStatus();
  m_status->setText(tr("Synthesis cancelled"));
  emit synthesisFinished(false);
}

void MainWindow::onSynthesized(int generation, std::shared_ptr<const MapResult> map,
                               std::shared_ptr<synth::SynthResult> result, QString error,
                               bool cancelled) {
  if (!m_synthJob.current(generation)) return;
  m_synthJob.finish();
  m_synthProgress->hide();
  m_synthCancelButton->hide();
  if (cancelled || !error.isEmpty()) {
    updateStatus();
    if (!error.isEmpty()) showError(error);
    emit synthesisFinished(false);
    return;
  }
  // The user agreed to replace an unexported motion when the sketch ended (synthesizeAlong).
  pause();
  m_synth = std::move(*result);
  m_synthMap = std::move(map);
  m_unsaved = true;
  m_playingSynth = true;
  m_exportAction->setEnabled(true);
  m_slider->setRange(0, std::max(0, m_synth->motion.num_frames - 1));
  setFrame(0);
  updateStatus();
  emit motionSynthesized();
  emit synthesisFinished(true);
  play();
}

bool MainWindow::exportMotion(const QString& path) {
  if (!m_synth || !m_synthMap) return false;
  try {
    io::write_bvh(io::from_motion(m_synthMap->blender->skeleton(), m_synth->motion),
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
  if (!map || !m_clips) return false;
  try {
    if (QFileInfo(path).suffix().compare("csv", Qt::CaseInsensitive) == 0) {
      std::ofstream out(path.toStdString());
      if (!out) throw Error("cannot write " + path.toStdString());
      std::vector<std::string> files;
      for (const Clip& c : *m_clips)
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
  QDialog dialog(this);
  dialog.setWindowTitle(tr("Map parameters"));
  auto* form = new QFormLayout(&dialog);
  auto* k = new QSpinBox;
  k->setRange(1, 1000);
  k->setValue(m_parameters.k);
  form->addRow(tr("Neighbours k (Isomap, LE, LLE)"), k);
  auto* heat =
      new QLineEdit(m_parameters.heat ? QString::number(*m_parameters.heat, 'g', 17) : QString());
  heat->setPlaceholderText(tr("auto"));
  form->addRow(tr("Heat t (LE; ≤ 0: unit weights)"), heat);
  auto* featureBox = new QComboBox;
  for (auto f : {features::FeatureKind::Quaternions, features::FeatureKind::Positions}) {
    featureBox->addItem(QString::fromUtf8(features::feature_kind_name(f).data()), int(f));
  }
  featureBox->setCurrentIndex(featureBox->findData(int(m_parameters.features)));
  form->addRow(tr("Features (PCA, SVD, LLE)"), featureBox);
  auto* distanceBox = new QComboBox;
  for (auto d : {features::DistanceKind::PointCloud, features::DistanceKind::Geodesic,
                 features::DistanceKind::Features}) {
    distanceBox->addItem(QString::fromUtf8(features::distance_kind_name(d).data()), int(d));
  }
  distanceBox->setCurrentIndex(distanceBox->findData(int(m_parameters.distance)));
  form->addRow(tr("Distance (MDS, Isomap, LE)"), distanceBox);
  auto* exclude = new QLineEdit(QString::fromStdString(m_parameters.exclude));
  exclude->setPlaceholderText(tr("e.g. .*(Thumb|Finger).*"));
  form->addRow(tr("Excluded joints (regex)"), exclude);
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel);
  form->addRow(buttons);
  connect(buttons, &QDialogButtonBox::accepted, &dialog, &QDialog::accept);
  connect(buttons, &QDialogButtonBox::rejected, &dialog, &QDialog::reject);
  if (dialog.exec() != QDialog::Accepted) return;
  MapParameters p;
  p.k = k->value();
  const QString heatText = heat->text().trimmed();
  if (!heatText.isEmpty() && heatText.compare("auto", Qt::CaseInsensitive) != 0) {
    bool ok = false;
    const double value = heatText.toDouble(&ok);
    if (!ok || !std::isfinite(value))
      return showError(tr("heat: '%1' is not a number (leave it empty for auto)").arg(heatText));
    p.heat = value;
  }
  p.features = features::FeatureKind(featureBox->currentData().toInt());
  p.distance = features::DistanceKind(distanceBox->currentData().toInt());
  p.exclude = exclude->text().toStdString();
  setParameters(p);  // the library validates: a bad value comes back as its error message
}

void MainWindow::synthesisDialog() {
  QDialog dialog(this);
  dialog.setWindowTitle(tr("Synthesis"));
  auto* form = new QFormLayout(&dialog);
  const SynthParameters& now = m_synthParameters;
  auto* mode = new QComboBox;
  for (auto m : {synth::BlendMode::Local, synth::BlendMode::Kriging, synth::BlendMode::Idw}) {
    mode->addItem(QString::fromUtf8(synth::blend_mode_name(m).data()), int(m));
  }
  mode->setCurrentIndex(mode->findData(int(now.blend.mode)));
  mode->setToolTip(
      tr("local: kriging on the K map-nearest samples (default); kriging: the reference system's "
         "rule over all samples (its set-up grows as N³: seconds at a few thousand frames, about "
         "half a minute at 10 000); idw: inverse-distance weights on the K nearest"));
  form->addRow(tr("Blend"), mode);
  auto* neighbors = new QSpinBox;
  neighbors->setRange(1, 10000);
  neighbors->setValue(now.blend.neighbors);
  form->addRow(tr("Neighbours K (local, idw)"), neighbors);
  auto* reach = new QDoubleSpinBox;
  reach->setRange(0.01, 1000.0);
  reach->setDecimals(2);
  reach->setValue(now.blend.reach);
  reach->setToolTip(
      tr("A point farther from every sample than reach × the median step between "
         "consecutive samples is moved to the data's edge"));
  form->addRow(tr("Reach (× median step)"), reach);
  auto* timing = new QComboBox;
  timing->addItem(tr("as drawn"), true);
  timing->addItem(tr("at a steady speed"), false);
  timing->setCurrentIndex(timing->findData(now.timedAsDrawn));
  form->addRow(tr("Sketch timing"), timing);
  auto* speed = new QDoubleSpinBox;
  speed->setRange(0.0, 1e9);
  speed->setDecimals(4);
  speed->setSpecialValueText(tr("the clip's"));
  speed->setValue(now.motion.speed);
  speed->setToolTip(
      tr("Map units per second along a sketch at a steady speed; the clip's own "
         "median speed at 0"));
  form->addRow(tr("Steady speed"), speed);
  const auto enableSpeed = [timing, speed] { speed->setEnabled(!timing->currentData().toBool()); };
  enableSpeed();
  connect(timing, &QComboBox::currentIndexChanged, speed, enableSpeed);
  auto* fps = new QDoubleSpinBox;
  fps->setRange(0.0, 1000.0);
  fps->setDecimals(2);
  fps->setSpecialValueText(tr("the clip's"));
  fps->setValue(now.motion.fps);
  form->addRow(tr("Frames per second of the motion"), fps);
  auto* smooth = new QDoubleSpinBox;
  smooth->setRange(0.0, synth::kMaxSmoothSeconds);
  smooth->setDecimals(3);
  smooth->setSuffix(tr(" s"));
  smooth->setSpecialValueText(tr("none"));
  smooth->setValue(now.motion.smooth);
  smooth->setToolTip(tr("σ of a Gaussian smoothing of the blend weights over time"));
  form->addRow(tr("Smoothing"), smooth);
  auto* buttons = new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel);
  form->addRow(buttons);
  connect(buttons, &QDialogButtonBox::accepted, &dialog, &QDialog::accept);
  connect(buttons, &QDialogButtonBox::rejected, &dialog, &QDialog::reject);
  if (dialog.exec() != QDialog::Accepted) return;
  SynthParameters p = now;
  p.blend.mode = synth::BlendMode(mode->currentData().toInt());
  p.blend.neighbors = neighbors->value();
  p.blend.reach = reach->value();
  p.timedAsDrawn = timing->currentData().toBool();
  p.motion.speed = speed->value();
  p.motion.fps = fps->value();
  p.motion.smooth = smooth->value();
  setSynthParameters(p);
}

void MainWindow::loadParameters() {
  // A value from an older version or edited by hand that the library would reject is dropped
  // (its default stays) rather than breaking every map of the session.
  const QSettings settings;
  const auto number = [&](const char* key, auto& value, auto valid) {
    bool ok = false;
    const double v = settings.value(key).toDouble(&ok);
    if (ok && std::isfinite(v) && valid(v))
      value = static_cast<std::remove_reference_t<decltype(value)>>(v);
  };
  const auto count = [](double v) { return v >= 1 && v <= 1e6 && v == std::floor(v); };
  MapParameters& m = m_parameters;
  number("map/k", m.k, count);
  const QString heat = settings.value("map/heat").toString();
  bool heatOk = false;
  const double heatValue = heat.toDouble(&heatOk);
  if (heatOk && std::isfinite(heatValue)) m.heat = heatValue;
  const auto name = [&](const char* key) { return settings.value(key).toString().toStdString(); };
  for (auto f : {features::FeatureKind::Quaternions, features::FeatureKind::Positions}) {
    if (name("map/features") == features::feature_kind_name(f)) m.features = f;
  }
  for (auto d : {features::DistanceKind::PointCloud, features::DistanceKind::Geodesic,
                 features::DistanceKind::Features}) {
    if (name("map/distance") == features::distance_kind_name(d)) m.distance = d;
  }
  m.exclude = name("map/exclude");
  SynthParameters& s = m_synthParameters;
  if (const auto b = synth::parse_blend_mode(name("synth/blend"))) s.blend.mode = *b;
  number("synth/neighbors", s.blend.neighbors, count);
  number("synth/reach", s.blend.reach, [](double v) { return v > 0; });
  synth::SynthOptions motion = s.motion;
  s.timedAsDrawn = settings.value("synth/timedAsDrawn", true).toBool();
  number("synth/speed", motion.speed, [](double v) { return v >= 0; });
  number("synth/fps", motion.fps, [](double v) { return v >= 0; });
  number("synth/smooth", motion.smooth, [](double v) { return v >= 0; });
  try {
    motion.validate();
    s.motion = motion;
  } catch (const std::exception&) {
  }
}

void MainWindow::saveParameters() const {
  QSettings settings;
  const MapParameters& m = m_parameters;
  settings.setValue("map/k", m.k);
  settings.setValue("map/heat",
                    m.heat ? QString::number(*m.heat, 'g', 17) : QStringLiteral("auto"));
  settings.setValue("map/features",
                    QString::fromUtf8(features::feature_kind_name(m.features).data()));
  settings.setValue("map/distance",
                    QString::fromUtf8(features::distance_kind_name(m.distance).data()));
  settings.setValue("map/exclude", QString::fromStdString(m.exclude));
  const SynthParameters& s = m_synthParameters;
  settings.setValue("synth/blend", QString::fromUtf8(synth::blend_mode_name(s.blend.mode).data()));
  settings.setValue("synth/neighbors", s.blend.neighbors);
  settings.setValue("synth/reach", s.blend.reach);
  settings.setValue("synth/timedAsDrawn", s.timedAsDrawn);
  settings.setValue("synth/speed", s.motion.speed);
  settings.setValue("synth/fps", s.motion.fps);
  settings.setValue("synth/smooth", s.motion.smooth);
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
  stopSynthWorker();
  stopWorker();
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
  bool add = m_clips && (event->modifiers() & Qt::ControlModifier);
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
      pause();
      setFrame(m_frame - 1);
      break;
    case Qt::Key_Right:
      pause();
      setFrame(m_frame + 1);
      break;
    default:
      QMainWindow::keyPressEvent(event);
  }
}

}  // namespace motionmap::studio
