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
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>

#include "main_window.h"
#include "map_view.h"
#include "motionmap/io/load.h"
#include "motionmap/sample/sample_clip.h"
#include "skeleton_view.h"

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
