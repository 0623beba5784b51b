// MotionMap Studio's per-frame costs, measured on the app's own widgets (offscreen: the 3-D view
// draws with QPainter; under a display, e.g. `QT_QPA_PLATFORM=xcb xvfb-run -a`, with OpenGL):
//  - MapViewFrame: a frame of the map view (the pointer moves, the cached trajectory is blitted);
//    it must not grow with the trajectory's length.
//  - MapViewFullRepaint: the same panel painted from scratch (render::paint_map), the cost the
//    cache saves on every frame; linear in the trajectory's length.
//  - DragUpdate: one mouse move of a drag on the map (MapBlender locate + blend, forward
//    kinematics, pointer) and both views drawn; DragUpdateLogic: the same without drawing.
//  - PlaybackFrame: one playback step (setFrame) and both views drawn: well under 16.7 ms means
//    60 fps playback.
// On a saved map (MOTIONMAP_STUDIO_BENCH_MAP=lib.mmap.h5, e.g. the 10⁶-frame library of
// docs/studio.md; skipped with a message without it):
//  - SavedMapOpen: File → Open map end to end (read_map_file, the 2-D index, the first clip
//    loaded and hash-checked, the density image binned and the view painted once);
//    SavedMapRead, SavedMapIndex, SavedMapDensity: its parts.
//  - SavedMapHover: one mouse move over the map (index lookup, hover text) and the view drawn.
//  - SavedMapClickCached: a click on a sample of a clip in the cache, the jump, both views drawn.
//  - SavedMapClickLoad: a click on a sample of a clip not in the cache: the event asks the
//    loader's thread for the clip and returns; SavedMapClipLoad: what that load takes (SHA-256
//    and parse of one clip file), the wait before the jump.
//  - SavedMapDrag: one mouse move of a drag (k-nearest lookup, the samples' clips asked for when
//    not cached, the blend when they are) and both views drawn; "loads" counts clips loaded.
// Zoom and pan on 10⁶ points (no file needed: clustered random points in a 640 × 640 map view, a
// 6 000-frame clip's trajectory over them):
//  - ZoomFrame1M: one wheel notch (in, then out, alternately) around a point and the view drawn:
//    the density image binned again at the zoomed view (so it stays sharp), the trajectory
//    repainted (a smooth 6 000-frame loop through the blobs), the frame; must stay under 16 ms.
//    PanFrame1M: one move of a pan drag, the same. Argument 1: coloured by a label of 7 values
//    (one per blob; View → Colour by), one of them hidden: the density binned by category
//    (render::category_density_image) — the same 16 ms. Argument 2: with View → Shade
//    trustworthy blends on (reach 5 % of the map's size, the least synth::reach_radius gives):
//    the shading decided again at every pixel of the view (render::reach_image) — the same 16 ms;
//    argument 3: the same zoomed on the shading's edge, where the exact k-d lookups are.
//  - ReachField1M: what turning the shading on first costs on 10⁶ points (once per map and
//    reach): render::ReachField's grid and distance transform; the view's k-d tree over the
//    points is SavedMapIndex's (a saved map's own, not built again).
//  - LegendToggle1M: a legend click on 10⁶ coloured points: a value hidden or shown again (every
//    sample's category set, MapView::setSampleCategories) and the view drawn.
// Data (argument 0/1): CMU 64_08 (365 frames), and a 10 000-frame concatenation of 64_08 and
// 64_09 (same subject, same skeleton) as one clip; the built-in swing sample stands in (said on
// stderr) when ../shared/data is absent. Maps are PCA (the drawing costs do not depend on the
// method; PCA keeps the 10 000-frame set-up short).
#include <benchmark/benchmark.h>

#include <QApplication>
#include <QImage>
#include <QMouseEvent>
#include <QPainter>
#include <QStandardPaths>
#include <QThread>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <vector>

#include "app/main_window.h"
#include "map/map_view.h"
#include "motionmap/io/load.h"
#include "motionmap/mapfile/saved_map.h"
#include "motionmap/sample/sample_clip.h"
#include "scene/skeleton_view.h"

namespace motionmap::studio {
namespace {

constexpr int kConcatFrames = 10000;

std::string shared(const std::string& name) {
  return std::string(MOTIONMAP_SHARED_DATA) + "/" + name;
}

Clip sampleSwing(int frames) {
  sample::SampleOptions options;
  options.seconds = frames / 120.0;
  return sample::make_sample_clip(sample::SampleKind::Swing, options);
}

/// Clips appended frame after frame into one clip of exactly `frames` frames (same skeleton).
Clip concatenate(const std::vector<Clip>& clips, int frames) {
  Clip out;
  out.path = "concat";
  out.skeleton = clips.front().skeleton;
  const int J = out.skeleton.num_joints();
  out.motion.frame_time = clips.front().motion.frame_time;
  out.motion.resize(frames, J);
  int f = 0;
  for (std::size_t c = 0; f < frames; c = (c + 1) % clips.size()) {
    const Motion& m = clips[c].motion;
    const int n = std::min(m.num_frames, frames - f);
    std::copy_n(m.rotations.begin(), std::size_t(n) * std::size_t(J),
                out.motion.rotations.begin() + std::size_t(f) * J);
    std::copy_n(m.translations.begin(), std::size_t(n) * std::size_t(J),
                out.motion.translations.begin() + std::size_t(f) * J);
    f += n;
  }
  return out;
}

Clip dataset(int which) {
  const bool haveData = std::filesystem::exists(shared("cmu/64_08.bvh")) &&
                        std::filesystem::exists(shared("cmu/64_09.bvh"));
  if (!haveData) {
    std::fprintf(stderr, "studio bench: %s missing; using the built-in swing sample instead\n",
                 shared("cmu/64_0{8,9}.bvh").c_str());
    return sampleSwing(which == 0 ? 365 : kConcatFrames);
  }
  Clip a = io::load_clip(shared("cmu/64_08.bvh"));
  if (which == 0) return a;
  Clip b = io::load_clip(shared("cmu/64_09.bvh"));
  if (!a.skeleton.same_hierarchy(b.skeleton)) return concatenate({a}, kConcatFrames);
  return concatenate({a, b}, kConcatFrames);
}

const char* datasetName(int which) {
  return which == 0 ? "64_08" : "concat10k";
}

/// One shown window per data set with its PCA map computed (made on first use, kept).
std::map<int, std::unique_ptr<MainWindow>>& windows() {
  static std::map<int, std::unique_ptr<MainWindow>> w;
  return w;
}

MainWindow& window(int which) {
  auto& w = windows()[which];
  if (!w) {
    w = std::make_unique<MainWindow>();
    w->setInteractive(false);
    w->resize(1280, 720);
    w->show();
    w->setMethod(embed::Method::Pca);
    w->openClip(dataset(which));
    while (w->isComputing()) {
      QCoreApplication::processEvents(QEventLoop::AllEvents, 50);
      QThread::msleep(5);
    }
    QCoreApplication::processEvents();
    if (!w->currentMap()) {
      std::fprintf(stderr, "studio bench: no map: %s\n", qPrintable(w->lastError()));
      std::exit(1);
    }
    w->pause();
    w->setFrame(0);
  }
  return *w;
}

QImage canvas(const QWidget* widget) {
  QImage image(widget->size(), QImage::Format_ARGB32_Premultiplied);
  image.fill(Qt::white);
  return image;
}

void label(benchmark::State& state, MainWindow& w) {
  state.SetLabel(std::string(datasetName(int(state.range(0)))) + ", " +
                 std::to_string(w.currentMap()->map.features->num_samples()) +
                 " samples, 3-D view: " + (w.skeletonView()->glReady() ? "OpenGL" : "QPainter"));
}

void MapViewFrame(benchmark::State& state) {
  MainWindow& w = window(int(state.range(0)));
  const MapResult& map = *w.currentMap();
  MapView* view = w.mapView();
  QImage image = canvas(view);
  view->render(&image);  // fills the trajectory cache
  const int n = map.map.features->num_samples();
  int i = 0;
  for (auto _ : state) {
    view->setPointer(map.blender->sample_point(i));
    i = (i + 7) % n;
    view->render(&image);
    benchmark::DoNotOptimize(image.constBits());
  }
  label(state, w);
}

void MapViewFullRepaint(benchmark::State& state) {
  MainWindow& w = window(int(state.range(0)));
  const MapResult& map = *w.currentMap();
  QImage image = canvas(w.mapView());
  render::MapPlotOptions options;
  options.title = "PCA";
  options.time_legend = true;
  for (auto _ : state) {
    QPainter painter(&image);
    painter.setRenderHint(QPainter::Antialiasing);
    render::paint_map(painter, QRectF(image.rect()), map.map.embedding.coordinates,
                      map.map.features->segment_starts, options);
    painter.end();
    benchmark::DoNotOptimize(image.constBits());
  }
  label(state, w);
}

void sendMouse(QWidget* view, QEvent::Type type, QPointF at) {
  const Qt::MouseButton button = type == QEvent::MouseMove ? Qt::NoButton : Qt::LeftButton;
  const Qt::MouseButtons buttons =
      type == QEvent::MouseButtonRelease ? Qt::NoButton : Qt::LeftButton;
  QMouseEvent event(type, at, view->mapToGlobal(at), button, buttons, Qt::NoModifier);
  QApplication::sendEvent(view, &event);
}

/// Pixels between consecutive samples along the trajectory, a little off it.
std::vector<QPointF> dragPixels(MainWindow& w) {
  const MapResult& map = *w.currentMap();
  std::vector<QPointF> out;
  const int n = map.map.features->num_samples();
  for (int i = 0; i + 1 < n; i += std::max(1, n / 512)) {
    out.push_back((w.mapView()->toWidget(map.blender->sample_point(i)) +
                   w.mapView()->toWidget(map.blender->sample_point(i + 1))) /
                      2 +
                  QPointF(1.5, -1.0));
  }
  return out;
}

void drag(benchmark::State& state, bool draw) {
  MainWindow& w = window(int(state.range(0)));
  MapView* view = w.mapView();
  SkeletonView* skeleton = w.skeletonView();
  const std::vector<QPointF> pixels = dragPixels(w);
  QImage mapImage = canvas(view), skeletonImage = canvas(skeleton);
  sendMouse(view, QEvent::MouseButtonPress, pixels.front() + QPointF(-20, 0));
  sendMouse(view, QEvent::MouseMove, pixels.front());  // past the click threshold: a drag
  std::size_t i = 0;
  for (auto _ : state) {
    sendMouse(view, QEvent::MouseMove, pixels[i]);
    i = (i + 1) % pixels.size();
    if (draw) {
      skeleton->render(&skeletonImage);
      view->render(&mapImage);
      benchmark::DoNotOptimize(skeletonImage.constBits());
    }
    benchmark::DoNotOptimize(skeleton->currentPose().rotations.data());
  }
  sendMouse(view, QEvent::MouseButtonRelease, pixels[i]);
  label(state, w);
}

void DragUpdate(benchmark::State& state) {
  drag(state, true);
}
void DragUpdateLogic(benchmark::State& state) {
  drag(state, false);
}

void PlaybackFrame(benchmark::State& state) {
  MainWindow& w = window(int(state.range(0)));
  QImage mapImage = canvas(w.mapView()), skeletonImage = canvas(w.skeletonView());
  const int n = w.clip()->motion.num_frames;
  int f = 0;
  for (auto _ : state) {
    f = (f + 1) % n;
    w.setFrame(f);
    w.skeletonView()->render(&skeletonImage);
    w.mapView()->render(&mapImage);
    benchmark::DoNotOptimize(skeletonImage.constBits());
  }
  label(state, w);
}

// ---- Saved maps -------------------------------------------------------------------------------

QString savedMapPath() {
  return qEnvironmentVariable("MOTIONMAP_STUDIO_BENCH_MAP");
}

bool needSavedMap(benchmark::State& state) {
  if (!savedMapPath().isEmpty()) return true;
  state.SkipWithError("set MOTIONMAP_STUDIO_BENCH_MAP to a saved map (docs/studio.md)");
  return false;
}

/// One shown window with the saved map open (made on first use, kept).
MainWindow& savedWindow() {
  auto& w = windows()[100];
  if (!w) {
    w = std::make_unique<MainWindow>();
    w->setInteractive(false);
    w->resize(1280, 720);
    w->show();
    if (!w->openMapFile(savedMapPath())) {
      std::fprintf(stderr, "studio bench: %s\n", qPrintable(w->lastError()));
      std::exit(1);
    }
    QCoreApplication::processEvents();
    w->pause();
  }
  return *w;
}

void savedLabel(benchmark::State& state, const mapfile::SavedMap& map) {
  state.SetLabel(std::to_string(map.file().num_samples()) + " points, " +
                 std::to_string(map.num_clips()) + " clips");
}

void SavedMapOpen(benchmark::State& state) {
  if (!needSavedMap(state)) return;
  int points = 0;
  for (auto _ : state) {
    state.PauseTiming();  // a new window is not part of opening
    auto w = std::make_unique<MainWindow>();
    w->setInteractive(false);
    w->resize(1280, 720);
    w->show();
    state.ResumeTiming();
    if (!w->openMapFile(savedMapPath())) {
      state.SkipWithError(qPrintable(w->lastError()));
      return;
    }
    QImage image = canvas(w->mapView());
    w->mapView()->render(&image);  // the density binned and the view painted
    benchmark::DoNotOptimize(image.constBits());
    points = w->savedMap()->file().num_samples();
    state.PauseTiming();  // nor is closing it
    w.reset();
    state.ResumeTiming();
  }
  state.SetLabel(std::to_string(points) + " points");
}

void SavedMapRead(benchmark::State& state) {
  if (!needSavedMap(state)) return;
  for (auto _ : state) {
    const mapfile::MapFile file =
        mapfile::read_map_file(savedMapPath().toStdString(), {.model = false});
    benchmark::DoNotOptimize(file.coordinates.data());
  }
}

void SavedMapIndex(benchmark::State& state) {
  if (!needSavedMap(state)) return;
  const mapfile::SavedMap& map = *savedWindow().savedMap();
  for (auto _ : state) {
    const mapfile::PointIndex index(map.file().coordinates);
    benchmark::DoNotOptimize(index.indexed());
  }
  savedLabel(state, map);
}

void SavedMapDensity(benchmark::State& state) {
  if (!needSavedMap(state)) return;
  MainWindow& w = savedWindow();
  const QSize size = w.mapView()->size();
  const QTransform toPixel =
      render::map_transform(Eigen::MatrixXd(0, 2), QRectF(QPointF(0, 0), QSizeF(size)), [&] {
        render::MapPlotOptions o;
        const auto& idx = w.savedMap()->index();
        o.extent = QRectF(QPointF(idx.lower().x(), idx.lower().y()),
                          QPointF(idx.upper().x(), idx.upper().y()));
        return o;
      }());
  for (auto _ : state) {
    const QImage image = render::density_image(w.savedMap()->file().coordinates, toPixel, size);
    benchmark::DoNotOptimize(image.constBits());
  }
  state.SetLabel(std::to_string(size.width()) + "x" + std::to_string(size.height()) + " px, " +
                 std::to_string(w.savedMap()->file().num_samples()) + " points");
}

/// A map view of 10⁶ clustered points (seven blobs, as a library's actions) with a 6 000-frame
/// trajectory over them, drawn once.
/// The million points of millionView() (set when it is first made).
std::shared_ptr<const Eigen::MatrixXd>& millionPoints() {
  static std::shared_ptr<const Eigen::MatrixXd> points;
  return points;
}

/// The shading's reach over the million points: 5 % of the map's size (the larger side of their
/// box), synth::reach_radius's least reach.
double millionReach() {
  const Eigen::MatrixXd& xy = *millionPoints();
  return 0.05 * (xy.colwise().maxCoeff() - xy.colwise().minCoeff()).maxCoeff();
}

MapView& millionView() {
  static std::unique_ptr<MapView> view;
  if (!view) {
    constexpr int kPoints = 1000000;
    auto xy = std::make_shared<Eigen::MatrixXd>(kPoints, 2);
    millionPoints() = xy;
    std::uint64_t state = 12345;
    auto uniform = [&state] {  // splitmix-style: reproducible, no <random> distributions
      state += 0x9E3779B97F4A7C15ull;
      std::uint64_t z = state;
      z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
      z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
      return double((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
    };
    for (int i = 0; i < kPoints; ++i) {
      const int c = i % 7;
      const double r = std::sqrt(-2.0 * std::log(uniform() + 1e-12)), a = 6.283185 * uniform();
      (*xy)(i, 0) = 3.0 * std::cos(0.9 * c) + 0.4 * r * std::cos(a);
      (*xy)(i, 1) = 2.0 * std::sin(1.7 * c) + 0.25 * r * std::sin(a);
    }
    view = std::make_unique<MapView>();
    view->resize(640, 640);
    render::MapPlotOptions options;
    options.title = "10^6 points";
    // A clip's trajectory: a smooth loop through three of the blobs, 6 000 frames.
    Eigen::MatrixXd clip(6000, 2);
    for (int i = 0; i < 6000; ++i) {
      const double t = 6.283185 * i / 6000.0;
      clip.row(i) << 3.0 * std::cos(t) + 0.3 * std::sin(7 * t),
          2.0 * std::sin(2 * t) + 0.2 * std::cos(5 * t);
    }
    view->setDensityMap(xy, clip, options);
    view->setShadingReach(millionReach());
  }
  return *view;
}

/// Arguments 2 and 3 of the zoom and pan steps: the shading on (else off).
void shadeMillion(MapView& view, int argument) {
  view.setShadingVisible(argument >= 2);
}

/// Where the steps zoom: inside the blobs, or for argument 3 on the shading's edge (the first
/// unshaded pixel right of the plot's centre at the whole map), so the edge crosses the view.
QPointF zoomPoint(const MapView& view, int argument, const QPointF& inside) {
  if (argument != 3) return inside;
  const QImage layer = view.shadingLayer();
  const QPoint c = view.plotRect().center().toPoint();
  for (int x = c.x(); x < int(view.plotRect().right()); ++x)
    if (qAlpha(layer.pixel(x, c.y())) == 0) return QPointF(x, c.y());
  return inside;
}

/// The share of the plot's pixels the shading covers, for the label: what the step decided.
QString shadedShare(const MapView& view) {
  const QImage layer = view.shadingLayer();
  const QRect plot = view.plotRect().toAlignedRect().intersected(layer.rect());
  long long shaded = 0;
  for (int y = plot.top(); y <= plot.bottom(); ++y)
    for (int x = plot.left(); x <= plot.right(); ++x) shaded += qAlpha(layer.pixel(x, y)) != 0;
  return QString(", %1 % of the plot shaded")
      .arg(100.0 * double(shaded) / double(plot.width() * plot.height()), 0, 'f', 0);
}

/// The million points coloured by blob (7 values, blob 3 hidden) for argument 1, else plain.
void colourMillion(MapView& view, bool on, int hidden = 3) {
  std::vector<int> categories;
  if (on) {
    categories.resize(1000000);
    for (std::size_t i = 0; i < categories.size(); ++i)
      categories[i] = int(i % 7) == hidden ? MapView::kHiddenCategory : int(i % 7);
  }
  view.setSampleCategories(std::move(categories));
}

void ZoomFrame1M(benchmark::State& state) {
  MapView& view = millionView();
  view.resetView();
  colourMillion(view, state.range(0) == 1);
  shadeMillion(view, int(state.range(0)));
  QImage image = canvas(&view);
  view.render(&image);
  const QPointF at =
      zoomPoint(view, int(state.range(0)), view.plotRect().center() + QPointF(40, -30));
  view.zoomAt(at, 8.0);  // start well inside, then one notch in and out
  int k = 0;
  for (auto _ : state) {
    view.zoomAt(at, (k++ % 2) ? 1.0 / 1.25 : 1.25);
    view.render(&image);
    benchmark::DoNotOptimize(image.constBits());
  }
  state.SetLabel(state.range(0) == 1 ? "640x640 px, 10^6 points by 7 colours, zoom ~8-10x"
                 : state.range(0) >= 2
                     ? ("640x640 px, 10^6 points, shaded, zoom ~8-10x" +
                        QString(state.range(0) == 3 ? " at the data's edge" : "") +
                        shadedShare(view))
                           .toStdString()
                     : "640x640 px, 10^6 points, zoom ~8-10x");
  shadeMillion(view, 0);
}

void PanFrame1M(benchmark::State& state) {
  MapView& view = millionView();
  view.resetView();
  colourMillion(view, state.range(0) == 1);
  shadeMillion(view, int(state.range(0)));
  QImage image = canvas(&view);
  view.render(&image);
  view.zoomAt(zoomPoint(view, int(state.range(0)), view.plotRect().center()), 4.0);
  view.render(&image);
  int k = 0;
  for (auto _ : state) {
    view.panBy((k++ % 2) ? QPointF(-7, 5) : QPointF(7, -5));
    view.render(&image);
    benchmark::DoNotOptimize(image.constBits());
  }
  state.SetLabel(state.range(0) == 1 ? "640x640 px, 10^6 points by 7 colours, zoom 4x"
                 : state.range(0) >= 2
                     ? ("640x640 px, 10^6 points, shaded, zoom 4x" +
                        QString(state.range(0) == 3 ? " at the data's edge" : "") +
                        shadedShare(view))
                           .toStdString()
                     : "640x640 px, 10^6 points, zoom 4x");
  shadeMillion(view, 0);
}

void ReachField1M(benchmark::State& state) {
  millionView();
  const Eigen::MatrixXd& xy = *millionPoints();
  for (auto _ : state) {
    const render::ReachField field(xy, millionReach());
    benchmark::DoNotOptimize(field.nx());
  }
  state.SetLabel("10^6 points, 2048-cell grid");
}

void LegendToggle1M(benchmark::State& state) {
  MapView& view = millionView();
  view.resetView();
  QImage image = canvas(&view);
  int k = 0;
  for (auto _ : state) {
    colourMillion(view, true, (k++ % 2) ? 3 : -1);  // blob 3 hidden, then shown again
    view.render(&image);
    benchmark::DoNotOptimize(image.constBits());
  }
  state.SetLabel("640x640 px, 10^6 points by 7 colours");
}

/// `count` pixels of samples spread over the map (every n/count-th row), a pixel off.
std::vector<QPointF> samplePixels(MainWindow& w, int count) {
  const mapfile::MapFile& file = w.savedMap()->file();
  std::vector<QPointF> out;
  const int n = file.num_samples();
  for (int i = 0; i < count; ++i) {
    const int r = int((long long)(i)*n / count);
    out.push_back(
        w.mapView()->toWidget(Eigen::Vector2d(file.coordinates(r, 0), file.coordinates(r, 1))) +
        QPointF(0.7, -0.4));
  }
  return out;
}

void SavedMapHover(benchmark::State& state) {
  if (!needSavedMap(state)) return;
  MainWindow& w = savedWindow();
  MapView* view = w.mapView();
  const std::vector<QPointF> pixels = samplePixels(w, 997);
  QImage image = canvas(view);
  view->render(&image);
  std::size_t i = 0;
  for (auto _ : state) {
    sendMouse(view, QEvent::MouseMove, pixels[i]);
    i = (i + 1) % pixels.size();
    view->render(&image);
    benchmark::DoNotOptimize(image.constBits());
  }
  savedLabel(state, *w.savedMap());
}

// Clip loads run on the loader's thread: the events of a benchmark only asked for them. Waits for
// them so the next benchmark starts quiet, then counts the loads per iteration since `before`.
void finishLoads(benchmark::State& state, MainWindow& w, const mapfile::SavedMap& map, int before) {
  while (w.isLoadingClip()) {
    QCoreApplication::processEvents(QEventLoop::AllEvents, 50);
    QThread::msleep(5);
  }
  QCoreApplication::processEvents();
  state.counters["loads"] =
      benchmark::Counter(double(map.loads() - before), benchmark::Counter::kAvgIterations);
  savedLabel(state, map);
}

void click(benchmark::State& state, bool cached) {
  if (!needSavedMap(state)) return;
  MainWindow& w = savedWindow();
  const mapfile::SavedMap& map = *w.savedMap();
  MapView* view = w.mapView();
  QImage mapImage = canvas(view), skeletonImage = canvas(w.skeletonView());
  const mapfile::MapFile& file = map.file();
  // Cached: samples of the current clip and the one before (both stay in the cache). Load: a
  // sample of a different clip every time, cycling through more clips than the cache holds.
  const int current = std::max(0, w.currentClip());
  const int other = (current + 1) % map.num_clips();
  std::vector<QPointF> pixels;
  for (int i = 0; i < 64; ++i) {
    const int c = cached ? (i % 2 ? current : other) : (current + 1 + i) % map.num_clips();
    const mapfile::ClipRecord& r = file.clips[std::size_t(c)];
    const int row = r.first_sample + (i * 97) % std::max(1, r.samples);
    pixels.push_back(
        view->toWidget(Eigen::Vector2d(file.coordinates(row, 0), file.coordinates(row, 1))));
  }
  if (cached) map.clip(other);
  const int before = map.loads();
  std::size_t i = 0;
  for (auto _ : state) {
    sendMouse(view, QEvent::MouseButtonPress, pixels[i]);
    sendMouse(view, QEvent::MouseButtonRelease, pixels[i]);
    i = (i + 1) % pixels.size();
    w.skeletonView()->render(&skeletonImage);
    view->render(&mapImage);
    benchmark::DoNotOptimize(mapImage.constBits());
  }
  finishLoads(state, w, map, before);
}

/// What a click on a clip not in the cache waits for (on the loader's thread): SHA-256 check and
/// parse of one clip file, on a SavedMap of its own (so the cache is cold).
void SavedMapClipLoad(benchmark::State& state) {
  if (!needSavedMap(state)) return;
  const mapfile::SavedMap& shown = *savedWindow().savedMap();
  const mapfile::SavedMap cold(shown.file(), 1);
  int c = 0;
  for (auto _ : state) {
    const auto clip = cold.clip(c);
    benchmark::DoNotOptimize(clip->motion.rotations.data());
    c = (c + 1) % cold.num_clips();
  }
  state.SetLabel(std::to_string(cold.file().clips.front().frames) + "-frame clips");
}

void SavedMapClickCached(benchmark::State& state) {
  click(state, true);
}
void SavedMapClickLoad(benchmark::State& state) {
  click(state, false);
}

void SavedMapDrag(benchmark::State& state) {
  if (!needSavedMap(state)) return;
  MainWindow& w = savedWindow();
  const mapfile::SavedMap& map = *w.savedMap();
  MapView* view = w.mapView();
  SkeletonView* skeleton = w.skeletonView();
  // A slow drag: 256 points 1 px apart along a line through the middle of the map.
  const QPointF centre = view->toWidget(0.5 * (map.index().lower() + map.index().upper()));
  std::vector<QPointF> pixels;
  for (int i = 0; i < 256; ++i) pixels.push_back(centre + QPointF(i - 128, 0.5 * (i - 128)));
  QImage mapImage = canvas(view), skeletonImage = canvas(skeleton);
  sendMouse(view, QEvent::MouseButtonPress, pixels.front() + QPointF(-20, 0));
  sendMouse(view, QEvent::MouseMove, pixels.front());
  const int before = map.loads();
  std::size_t i = 0;
  for (auto _ : state) {
    sendMouse(view, QEvent::MouseMove, pixels[i]);
    i = (i + 1) % pixels.size();
    skeleton->render(&skeletonImage);
    view->render(&mapImage);
    benchmark::DoNotOptimize(skeletonImage.constBits());
  }
  sendMouse(view, QEvent::MouseButtonRelease, pixels[i]);
  finishLoads(state, w, map, before);
}

BENCHMARK(SavedMapOpen)->Iterations(3)->Unit(benchmark::kMillisecond);
BENCHMARK(SavedMapRead)->Iterations(3)->Unit(benchmark::kMillisecond);
BENCHMARK(SavedMapIndex)->Iterations(3)->Unit(benchmark::kMillisecond);
BENCHMARK(SavedMapDensity)->Unit(benchmark::kMillisecond);
BENCHMARK(SavedMapHover)->Unit(benchmark::kMicrosecond);
BENCHMARK(SavedMapClickCached)->Unit(benchmark::kMicrosecond);
BENCHMARK(SavedMapClickLoad)->Iterations(32)->Unit(benchmark::kMicrosecond);
BENCHMARK(SavedMapClipLoad)->Iterations(8)->Unit(benchmark::kMillisecond);
BENCHMARK(SavedMapDrag)->Unit(benchmark::kMicrosecond);

BENCHMARK(ZoomFrame1M)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);
BENCHMARK(PanFrame1M)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);
BENCHMARK(ReachField1M)->Iterations(3)->Unit(benchmark::kMillisecond);
BENCHMARK(LegendToggle1M)->Unit(benchmark::kMillisecond);
BENCHMARK(MapViewFrame)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK(MapViewFullRepaint)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK(DragUpdateLogic)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK(DragUpdate)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK(PlaybackFrame)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace motionmap::studio

int main(int argc, char** argv) {
  if (qEnvironmentVariableIsEmpty("QT_QPA_PLATFORM")) qputenv("QT_QPA_PLATFORM", "offscreen");
  motionmap::studio::SkeletonView::installSurfaceFormat();
  QStandardPaths::setTestModeEnabled(true);  // the app's QSettings stay out of the user's
  QApplication app(argc, argv);
  QApplication::setOrganizationName("MotionMapBench");
  QApplication::setApplicationName("MotionMap Studio Bench");
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  motionmap::studio::windows().clear();
  return 0;
}
