#include "main_window.h"

#include <QAction>
#include <QActionGroup>
#include <QApplication>
#include <QCloseEvent>
#include <QDragEnterEvent>
#include <QElapsedTimer>
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
#include "motionmap/sample/sample_clip.h"
#include "skeleton_view.h"

namespace motionmap::studio {

namespace {
constexpr int kMaxRecent = 8;
constexpr double kNearPixels = 12.0;
/// Metrics are O(#frames²) on top of the map; beyond this the status bar shows none.
constexpr int kMaxMetricsFrames = 5000;
}  // namespace

QString methodLabel(embed::Method method) {
  switch (method) {
    case embed::Method::Pca: return QStringLiteral("PCA");
    case embed::Method::Svd: return QStringLiteral("SVD");
    case embed::Method::Mds: return QStringLiteral("MDS");
    case embed::Method::Isomap: return QStringLiteral("Isomap");
    case embed::Method::LaplacianEigenmap: return QStringLiteral("LE");
    case embed::Method::Lle: return QStringLiteral("LLE");
  }
  return {};
}

MainWindow::MainWindow(QWidget* parent) : QMainWindow(parent) {
  if (qEnvironmentVariableIntValue("MOTIONMAP_STUDIO_NO_CONFIRM") != 0) m_interactive = false;
  QSettings settings;
  m_lastDir = settings.value("lastDir").toString();
  if (const auto m = embed::parse_method(settings.value("method", "isomap").toString().toStdString())) m_method = *m;
  buildUi();
  restoreGeometry(settings.value("geometry").toByteArray());
  setAcceptDrops(true);
  connect(&m_timer, &QTimer::timeout, this, &MainWindow::onTick);
}

MainWindow::~MainWindow() { stopWorker(); }

void MainWindow::buildUi() {
  setWindowTitle(tr("MotionMap Studio"));
  resize(1280, 720);
  m_skeletonView = new SkeletonView;
  m_mapView = new MapView;
  auto* splitter = new QSplitter(Qt::Horizontal);
  splitter->addWidget(m_skeletonView);
  splitter->addWidget(m_mapView);
  splitter->setSizes({640, 640});

  m_playButton = new QPushButton(tr("Play"));
  m_playButton->setFocusPolicy(Qt::NoFocus);
  m_slider = new QSlider(Qt::Horizontal);
  m_slider->setEnabled(false);
  m_slider->setFocusPolicy(Qt::NoFocus);
  auto* transport = new QHBoxLayout;
  transport->addWidget(m_playButton);
  transport->addWidget(m_slider, 1);
  auto* central = new QWidget;
  auto* layout = new QVBoxLayout(central);
  layout->setContentsMargins(4, 4, 4, 4);
  layout->addWidget(splitter, 1);
  layout->addLayout(transport);
  setCentralWidget(central);
  connect(m_playButton, &QPushButton::clicked, this, [this] { isPlaying() ? pause() : play(); });
  connect(m_slider, &QSlider::valueChanged, this, [this](int v) {
    if (v != m_frame) setFrame(v);
  });

  QMenu* file = menuBar()->addMenu(tr("&File"));
  file->addAction(tr("&Open…"), QKeySequence::Open, this, &MainWindow::openDialog);
  file->addAction(tr("Open &sample golf swing"), this, [this] {
    if (confirmDiscard()) openClip(sample::make_sample_clip(sample::SampleKind::Swing));
  });
  m_recentMenu = file->addMenu(tr("Open &recent"));
  m_exportAction = file->addAction(tr("&Export motion…"), QKeySequence(tr("Ctrl+E")), this, &MainWindow::exportDialog);
  m_exportAction->setEnabled(false);
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
  motion->addAction(tr("Show &clip"), this, &MainWindow::showClipMotion);

  m_status = new QLabel(tr("No clip"));
  m_progress = new QProgressBar;
  m_progress->setRange(0, 1000);
  m_progress->setMaximumWidth(200);
  m_progress->hide();
  m_cancelButton = new QPushButton(tr("Cancel"));
  m_cancelButton->hide();
  connect(m_cancelButton, &QPushButton::clicked, this, &MainWindow::cancelComputation);
  statusBar()->addWidget(m_status, 1);
  statusBar()->addPermanentWidget(m_progress);
  statusBar()->addPermanentWidget(m_cancelButton);

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
  stopWorker();
  pause();
  m_maps.clear();
  m_synth.reset();
  m_unsaved = false;
  m_playingSynth = false;
  m_exportAction->setEnabled(false);
  m_clip = std::make_shared<const Clip>(std::move(clip));
  setWindowTitle(tr("MotionMap Studio — %1").arg(QFileInfo(QString::fromStdString(m_clip->path)).fileName()));
  m_skeletonView->setSkeleton(m_clip->skeleton);
  m_frame = 0;
  m_slider->setRange(0, std::max(0, m_clip->motion.num_frames - 1));
  m_slider->setEnabled(m_clip->motion.num_frames > 0);
  m_timer.setInterval(std::max(1, int(std::lround(m_clip->motion.frame_time * 1000.0))));
  if (m_clip->motion.num_frames > 0) m_skeletonView->setPose(m_clip->motion, 0);
  m_mapView->clearMap(tr("Computing the map…"));
  setMethod(m_method);
}

void MainWindow::setMethod(embed::Method method) {
  m_method = method;
  for (QAction* a : m_methodGroup->actions()) a->setChecked(a->data().toInt() == int(method));
  QSettings().setValue("method", QString::fromUtf8(embed::method_name(method).data()));
  if (!m_clip) return;
  if (m_maps.count(method)) {
    if (isComputing()) stopWorker();
    showMap();
    emit mapReady(method);
    return;
  }
  startComputation(method);
}

const MapResult* MainWindow::currentMap() const {
  const auto it = m_maps.find(m_method);
  return it == m_maps.end() || isComputing() ? nullptr : it->second.get();
}

void MainWindow::startComputation(embed::Method method) {
  stopWorker();
  m_mapView->clearMap(tr("Computing the %1 map…").arg(methodLabel(method)));
  auto cancel = std::make_shared<std::atomic<bool>>(false);
  m_cancel = cancel;
  const int generation = ++m_generation;
  m_progress->setValue(0);
  m_progress->show();
  m_cancelButton->show();
  updateStatus();
  std::shared_ptr<const Clip> clip = m_clip;
  m_worker = std::thread([this, clip, cancel, method, generation] {
    auto result = std::make_shared<MapResult>();
    QString error;
    bool cancelled = false;
    try {
      embed::ClipMapOptions options;
      options.embed.method = method;
      options.metrics = clip->motion.num_frames <= kMaxMetricsFrames;
      // Callbacks run on this thread: hand progress to the GUI thread, read cancel atomically.
      options.progress = [this, generation](double fraction, std::string_view stage) {
        const QString text = QString::fromUtf8(stage.data(), qsizetype(stage.size()));
        QMetaObject::invokeMethod(
            this,
            [this, generation, fraction, text] {
              if (generation != m_generation) return;
              m_progress->setValue(int(fraction * 1000));
              m_progress->setFormat(text + " %p%");
              emit progressChanged(fraction);
            },
            Qt::QueuedConnection);
      };
      options.cancel = [cancel] { return cancel->load(); };
      QElapsedTimer clock;
      clock.start();
      result->map = embed::map_clips(std::span<const Clip>(clip.get(), 1), options);
      result->seconds = double(clock.nsecsElapsed()) * 1e-9;
      if (cancel->load()) throw Cancelled();
      result->parameters = embed::describe_parameters(result->map.embedding, options);
      result->blender = std::make_unique<synth::MapBlender>(std::span<const Clip>(clip.get(), 1),
                                                            result->map.features, result->map.embedding.coordinates);
      // Frames left out of the map (a bind pose) show the row of the nearest earlier frame.
      const auto& frames = result->map.features.frame_of;
      result->rowOfFrame.assign(std::size_t(std::max(0, clip->motion.num_frames)), 0);
      std::size_t row = 0;
      for (int f = 0; f < clip->motion.num_frames; ++f) {
        while (row + 1 < frames.size() && frames[row + 1] <= f) ++row;
        result->rowOfFrame[std::size_t(f)] = int(row);
      }
    } catch (const Cancelled&) {
      cancelled = true;
    } catch (const std::exception& e) {
      error = QString::fromStdString(e.what());
    }
    QMetaObject::invokeMethod(
        this, [this, generation, method, result, error, cancelled] { onComputed(generation, method, result, error, cancelled); },
        Qt::QueuedConnection);
  });
}

void MainWindow::stopWorker() {
  if (!m_worker.joinable()) return;
  if (m_cancel) m_cancel->store(true);
  m_worker.join();
  ++m_generation;  // results still queued from that worker are ignored
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

void MainWindow::onComputed(int generation, embed::Method method, std::shared_ptr<MapResult> result,
                            QString error, bool cancelled) {
  if (generation != m_generation) return;
  if (m_worker.joinable()) m_worker.join();
  m_progress->hide();
  m_cancelButton->hide();
  if (cancelled || !error.isEmpty()) {
    m_mapView->clearMap(cancelled ? tr("Cancelled") : tr("The map could not be computed"));
    if (!error.isEmpty()) showError(error);
    updateStatus();
    emit computationFinished(false);
    return;
  }
  m_maps[method] = std::move(result);
  if (method == m_method) showMap();
  emit computationFinished(true);
  emit mapReady(method);
}

void MainWindow::showMap() {
  const MapResult* map = currentMap();
  if (!map) return;
  render::MapPlotOptions options;
  options.title = methodLabel(m_method);
  options.time_legend = true;
  // What the library wants the user to know (a bind pose left out, a joined graph) under the map.
  for (const auto& note : map->map.features.notes) options.notes << QString::fromStdString(note);
  for (const auto& warning : map->map.embedding.warnings) options.notes << QString::fromStdString(warning);
  m_mapView->setMap(map->map.embedding.coordinates, map->map.features.segment_starts, options);
  updatePointer();
  updateStatus();
}

void MainWindow::updateStatus() {
  if (!m_clip) return;
  QStringList parts;
  parts << tr("%1 frames").arg(m_clip->motion.num_frames) << tr("%1 fps").arg(m_clip->motion.fps(), 0, 'g', 4);
  if (const MapResult* map = currentMap()) {
    parts << QString::fromStdString(map->parameters) << tr("%1 s").arg(map->seconds, 0, 'f', 2);
    if (map->map.metrics) {
      parts << tr("trustworthiness %1").arg(map->map.metrics->neighborhood.trustworthiness, 0, 'f', 3);
    }
  } else if (isComputing()) {
    parts << tr("computing %1…").arg(methodLabel(m_method));
  }
  if (m_playingSynth && m_synth) {
    parts << tr("synthesized: %1 frames, %2 outside the data").arg(m_synth->motion.num_frames).arg(m_synth->clamped_frames);
  }
  m_status->setText(parts.join(QStringLiteral(" · ")));
}

QString MainWindow::statusText() const { return m_status->text(); }

void MainWindow::showError(const QString& message) {
  m_lastError = message;
  m_status->setText(tr("Error: %1").arg(message));
  if (m_interactive) QMessageBox::warning(this, tr("MotionMap Studio"), message);
}

bool MainWindow::confirmDiscard() {
  if (!hasUnsavedMotion() || !m_interactive) return true;
  return QMessageBox::question(this, tr("MotionMap Studio"),
                               tr("The synthesized motion has not been exported. Discard it?")) ==
         QMessageBox::Yes;
}

const Motion* MainWindow::playingMotion() const {
  if (m_playingSynth && m_synth) return &m_synth->motion;
  return m_clip ? &m_clip->motion : nullptr;
}

void MainWindow::setFrame(int frame) {
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

void MainWindow::updatePointer() {
  const MapResult* map = currentMap();
  if (!map) return m_mapView->setPointer(std::nullopt);
  if (m_playingSynth && m_synth) {
    // Its map points belong to the map it was sketched on.
    const bool sameMap = m_synthMethod == m_method && m_frame < int(m_synth->validity.size());
    m_mapView->setPointer(sameMap ? std::optional(m_synth->validity[std::size_t(m_frame)].point) : std::nullopt);
    return;
  }
  if (m_frame < int(map->rowOfFrame.size())) {
    m_mapView->setPointer(map->blender->sample_point(map->rowOfFrame[std::size_t(m_frame)]));
  }
}

void MainWindow::play() {
  const Motion* motion = playingMotion();
  if (!motion || motion->num_frames < 2) return;
  m_timer.setInterval(std::max(1, int(std::lround(motion->frame_time * 1000.0))));
  m_timer.start();
  m_playButton->setText(tr("Pause"));
}

void MainWindow::pause() {
  m_timer.stop();
  m_playButton->setText(tr("Play"));
}

void MainWindow::onTick() {
  const Motion* motion = playingMotion();
  if (!motion || motion->num_frames == 0) return pause();
  setFrame(m_frame + 1 >= motion->num_frames ? 0 : m_frame + 1);  // loop
}

void MainWindow::showClipMotion() {
  if (!m_playingSynth) return;
  m_playingSynth = false;
  m_slider->setRange(0, std::max(0, m_clip->motion.num_frames - 1));
  setFrame(0);
  updateStatus();
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
  m_mapView->setHoverText(sample < 0 ? QString() : tr("frame %1").arg(map->map.features.frame_of[std::size_t(sample)]));
}

void MainWindow::onClick(const Eigen::Vector2d& point, const QPointF& pixel) {
  const int sample = sampleNear(point, pixel);
  if (sample < 0) return;
  if (m_playingSynth) showClipMotion();
  setFrame(currentMap()->map.features.frame_of[std::size_t(sample)]);
}

void MainWindow::onDrag(const Eigen::Vector2d& point) {
  const MapResult* map = currentMap();
  if (!map || isPlaying() || !point.allFinite()) return;
  try {
    const Motion pose = map->blender->pose_at(point);
    m_skeletonView->setPose(pose, 0);
    const synth::PointValidity validity = map->blender->locate(point).validity;
    m_mapView->setPointer(validity.point);
    m_mapView->setHoverText(validity.clamped ? tr("blend (outside the data: moved to its edge)") : tr("blend"));
  } catch (const std::exception& e) {
    showError(QString::fromStdString(e.what()));
  }
}

void MainWindow::synthesizeAlong(const synth::MapPath& path) {
  const MapResult* map = currentMap();
  if (!map || !confirmDiscard()) return;
  try {
    synth::SynthResult result = synth::synthesize(*map->blender, path);
    pause();
    m_synth = std::move(result);
    m_synthMethod = m_method;
    m_unsaved = true;
    m_playingSynth = true;
    m_exportAction->setEnabled(true);
    m_slider->setRange(0, std::max(0, m_synth->motion.num_frames - 1));
    setFrame(0);
    updateStatus();
    emit motionSynthesized();
    play();
  } catch (const std::exception& e) {
    showError(QString::fromStdString(e.what()));
  }
}

bool MainWindow::exportMotion(const QString& path) {
  if (!m_synth || !m_clip) return false;
  try {
    io::write_bvh(io::from_motion(m_clip->skeleton, m_synth->motion), path.toStdString());
    m_unsaved = false;
    return true;
  } catch (const std::exception& e) {
    showError(QString::fromStdString(e.what()));
    return false;
  }
}

void MainWindow::openDialog() {
  const QString path = QFileDialog::getOpenFileName(this, tr("Open clip"), m_lastDir,
                                                    tr("Motion capture (*.bvh *.amc);;All files (*)"));
  if (!path.isEmpty()) openFile(path);
}

void MainWindow::exportDialog() {
  const QString path = QFileDialog::getSaveFileName(this, tr("Export motion"), m_lastDir, tr("BVH (*.bvh)"));
  if (!path.isEmpty()) exportMotion(path);
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
    m_recentMenu->addAction(QFileInfo(path).fileName(), this, [this, path] { openFile(path); })->setToolTip(path);
  }
  m_recentMenu->setEnabled(!recent.isEmpty());
}

QImage MainWindow::screenshot() {
  QImage image = grab().toImage();
  // Paint the 3-D view's own rendering over its place: a window grab may leave a GL child blank.
  const QImage view = m_skeletonView->renderImage();
  if (!view.isNull()) {
    QPainter painter(&image);
    painter.drawImage(QRect(m_skeletonView->mapTo(this, QPoint(0, 0)), m_skeletonView->size()), view);
  }
  return image;
}

void MainWindow::closeEvent(QCloseEvent* event) {
  if (!confirmDiscard()) return event->ignore();
  stopWorker();
  QSettings settings;
  settings.setValue("geometry", saveGeometry());
  settings.setValue("lastDir", m_lastDir);
  event->accept();
}

void MainWindow::dragEnterEvent(QDragEnterEvent* event) {
  if (event->mimeData()->hasUrls()) event->acceptProposedAction();
}

void MainWindow::dropEvent(QDropEvent* event) {
  const auto urls = event->mimeData()->urls();
  if (!urls.isEmpty() && urls.front().isLocalFile()) openFile(urls.front().toLocalFile());
}

void MainWindow::keyPressEvent(QKeyEvent* event) {
  switch (event->key()) {
    case Qt::Key_Space: isPlaying() ? pause() : play(); break;
    case Qt::Key_Left: pause(); setFrame(m_frame - 1); break;
    case Qt::Key_Right: pause(); setFrame(m_frame + 1); break;
    default: QMainWindow::keyPressEvent(event);
  }
}

}  // namespace motionmap::studio
