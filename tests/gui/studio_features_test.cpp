// MotionMap Studio beyond the basic gestures (offscreen): synthesis on a worker (progress, cancel,
// the GUI thread stays free), never losing an unexported motion, playback speed and loop, map
// parameters and their cache, synthesis parameters, parameters kept across sessions, map export,
// sketch mode, the magnifier and the camera's follow mode.
#include <gtest/gtest.h>

#include <QAbstractButton>
#include <QApplication>
#include <QComboBox>
#include <QDialog>
#include <QDialogButtonBox>
#include <QDoubleSpinBox>
#include <QDragEnterEvent>
#include <QElapsedTimer>
#include <QFileDialog>
#include <QFileInfo>
#include <QImage>
#include <QMessageBox>
#include <QMimeData>
#include <QPushButton>
#include <QSettings>
#include <QSignalSpy>
#include <QSpinBox>
#include <QTemporaryDir>
#include <QTest>
#include <QTimer>
#include <QUrl>
#include <cmath>

#include "app/main_window.h"
#include "map/map_view.h"
#include "motionmap/io/bvh.h"
#include "motionmap/pipeline/map_csv.h"
#include "motionmap/sample/sample_clip.h"
#include "scene/skeleton_view.h"
#include "studio_test_util.h"

namespace motionmap::studio {
namespace {

using testing::kTimeoutMs;
using testing::pathAlong;
using testing::swing;
using testing::windowWithMap;

/// Answers the next modal message box with `button` (as a user would), recording its text.
struct QuestionAnswerer {
  QMessageBox::StandardButton button;
  int asked = 0;
  QString lastText;
  QTimer timer;
  explicit QuestionAnswerer(QMessageBox::StandardButton b) : button(b) {
    timer.setInterval(5);
    QObject::connect(&timer, &QTimer::timeout, [this] {
      if (auto* box = qobject_cast<QMessageBox*>(QApplication::activeModalWidget())) {
        ++asked;
        lastText = box->text();
        box->button(button)->click();
      }
    });
    timer.start();
  }
};

TEST(StudioSynthesis, RunsOnAWorkerWithProgressAndTheGuiThreadStaysFree) {
  auto w = windowWithMap();
  const MapResult* map = w->currentMap();
  ASSERT_NE(map, nullptr);
  QSignalSpy progress(w.get(), &MainWindow::synthesisProgress);
  QSignalSpy finished(w.get(), &MainWindow::synthesisFinished);
  // 60 s of motion at 120 fps: 7200 blended frames, long enough for several progress reports.
  int ticks = 0;
  QTimer ticker;
  QObject::connect(&ticker, &QTimer::timeout, [&] { ++ticks; });
  ticker.start(1);
  QElapsedTimer clock;
  clock.start();
  ASSERT_TRUE(w->synthesizeAlong(pathAlong(*map, 10, 200, 60.0)));
  const double startSeconds = double(clock.nsecsElapsed()) * 1e-9;
  EXPECT_TRUE(w->isSynthesizing());
  EXPECT_TRUE(w->statusText().contains("synthesizing")) << w->statusText().toStdString();
  ASSERT_TRUE(QTest::qWaitFor([&] { return finished.count() > 0; }, kTimeoutMs));
  const double totalSeconds = double(clock.nsecsElapsed()) * 1e-9;
  std::printf(
      "synthesizeAlong returned after %.4f s; the synthesis took %.3f s; %d timer ticks and %d "
      "progress "
      "reports ran on the GUI thread meanwhile\n",
      startSeconds, totalSeconds, ticks, int(progress.count()));
  EXPECT_TRUE(finished.front().front().toBool()) << w->lastError().toStdString();
  EXPECT_GE(progress.count(), 2);  // queued from the worker, delivered by the free GUI event loop
  EXPECT_GT(ticks, 0);
  ASSERT_NE(w->synthesized(), nullptr);
  EXPECT_EQ(w->synthesized()->motion.num_frames, 7201);
  EXPECT_TRUE(w->isPlaying());
  EXPECT_TRUE(w->hasUnsavedMotion());
  // The worker's motion is the library's answer for the same path.
  const synth::SynthResult direct =
      synth::synthesize(*map->blender, pathAlong(*map, 10, 200, 60.0));
  ASSERT_EQ(direct.motion.num_frames, w->synthesized()->motion.num_frames);
  for (int f : {0, 3600, 7200}) {
    EXPECT_TRUE(
        direct.motion.rotation(f, 3).isApprox(w->synthesized()->motion.rotation(f, 3), 1e-12));
  }
  w->pause();
}

TEST(StudioSynthesis, CancellingKeepsThePreviousMotion) {
  auto w = windowWithMap();
  const MapResult* map = w->currentMap();
  ASSERT_NE(map, nullptr);
  ASSERT_TRUE(w->synthesizeAlong(pathAlong(*map, 20, 60, 1.0)));
  ASSERT_TRUE(QTest::qWaitFor([&] { return !w->isSynthesizing(); }, kTimeoutMs));
  ASSERT_NE(w->synthesized(), nullptr);
  const synth::SynthResult* first = w->synthesized();
  const int firstFrames = first->motion.num_frames;
  EXPECT_EQ(firstFrames, 121);

  QSignalSpy progress(w.get(), &MainWindow::synthesisProgress);
  QSignalSpy finished(w.get(), &MainWindow::synthesisFinished);
  // Ten minutes of motion (72 000 frames): cancelled after its first progress report.
  ASSERT_TRUE(w->synthesizeAlong(pathAlong(*map, 10, 220, 600.0)));
  ASSERT_TRUE(
      QTest::qWaitFor([&] { return progress.count() > 0 || !w->isSynthesizing(); }, kTimeoutMs));
  ASSERT_TRUE(w->isSynthesizing()) << "the synthesis ended before it could be cancelled";
  EXPECT_LT(progress.back().front().toDouble(), 1.0);
  w->cancelSynthesis();
  EXPECT_FALSE(w->isSynthesizing());
  ASSERT_EQ(finished.count(), 1);
  EXPECT_FALSE(finished.front().front().toBool());
  EXPECT_TRUE(w->statusText().contains("cancelled")) << w->statusText().toStdString();
  QTest::qWait(50);  // nothing still queued from the cancelled worker replaces the motion
  ASSERT_NE(w->synthesized(), nullptr);
  EXPECT_EQ(w->synthesized()->motion.num_frames, firstFrames);
  EXPECT_TRUE(w->hasUnsavedMotion());
  w->pause();
}

TEST(StudioSynthesis, AsksBeforeDiscardingAnUnexportedMotion) {
  auto w = windowWithMap();
  const MapResult* map = w->currentMap();
  ASSERT_NE(map, nullptr);
  ASSERT_TRUE(w->synthesizeAlong(pathAlong(*map, 20, 60, 1.0)));
  ASSERT_TRUE(QTest::qWaitFor([&] { return !w->isSynthesizing(); }, kTimeoutMs));
  ASSERT_TRUE(w->hasUnsavedMotion());
  const int frames = w->synthesized()->motion.num_frames;
  w->pause();
  w->setInteractive(true);  // from here on the window asks, and the answerer replies

  {
    QuestionAnswerer no(QMessageBox::Cancel);
    // A new sketch: not asked, it is another take (the first is kept).
    EXPECT_TRUE(w->synthesizeAlong(pathAlong(*map, 100, 180, 2.0)));
    ASSERT_TRUE(QTest::qWaitFor([&] { return !w->isSynthesizing(); }, kTimeoutMs));
    w->pause();
    EXPECT_EQ(no.asked, 0);
    ASSERT_EQ(w->takes()->list().count(), 2);
    EXPECT_EQ(w->takes()->list().at(0).result->motion.num_frames, frames);
    EXPECT_EQ(w->synthesized()->motion.num_frames, 241);
    // Another clip (File → Open, recent, drop all go through openFile): asked, refused.
    QTemporaryDir dir;
    const QString other = dir.filePath("walk.bvh");
    const Clip walk = sample::make_sample_clip(sample::SampleKind::Walk);
    io::write_bvh(io::from_motion(walk.skeleton, walk.motion), other.toStdString());
    EXPECT_FALSE(w->openFile(other));
    EXPECT_EQ(no.asked, 1);
    EXPECT_TRUE(no.lastText.contains("not been exported")) << no.lastText.toStdString();
    EXPECT_EQ(w->clip()->motion.num_frames, 240);
    // Closing the window: asked, refused, still open.
    EXPECT_FALSE(w->close());
    EXPECT_EQ(no.asked, 2);
    EXPECT_TRUE(w->isVisible());
    EXPECT_EQ(w->takes()->list().count(), 2);
  }
  {
    // Export…: every unexported take written into the folder chosen, named after it; then the
    // window may go on.
    QTemporaryDir dir;
    QuestionAnswerer save(QMessageBox::Save);
    QTimer chooser;
    chooser.setInterval(5);
    QObject::connect(&chooser, &QTimer::timeout, [&] {
      if (auto* files = qobject_cast<QFileDialog*>(QApplication::activeModalWidget())) {
        files->setDirectory(dir.path());
        files->selectFile(dir.path());
        static_cast<QDialog*>(files)->accept();  // QFileDialog::accept is protected
      }
    });
    chooser.start();
    EXPECT_TRUE(w->confirmDiscard()) << w->lastError().toStdString();
    EXPECT_EQ(save.asked, 1);
    EXPECT_TRUE(QFileInfo::exists(dir.filePath("Take 1.bvh")));
    EXPECT_TRUE(QFileInfo::exists(dir.filePath("Take 2.bvh")));
    EXPECT_FALSE(w->hasUnsavedMotion());
    EXPECT_TRUE(w->takes()->list().unexportedNames().isEmpty());
  }
  {
    // Every take exported: nothing to lose, nothing asked.
    QTemporaryDir dir;
    ASSERT_TRUE(w->exportMotion(dir.filePath("kept.bvh")));
    ASSERT_TRUE(w->exportTake(0, dir.filePath("first.bvh")));
    QuestionAnswerer none(QMessageBox::Cancel);
    EXPECT_TRUE(w->confirmDiscard());
    EXPECT_EQ(none.asked, 0);
  }
  w->pause();
  w->setInteractive(false);
}

TEST(StudioSynthesis, ItsParametersReachTheLibrary) {
  auto w = windowWithMap();
  const MapResult* local = w->currentMap();
  ASSERT_NE(local, nullptr);
  EXPECT_EQ(local->blender->options().mode, synth::BlendMode::Local);
  // Motion options: no new map, the next sketch uses them.
  SynthParameters p = w->synthParameters();
  p.motion.fps = 30.0;  // the swing is 120 fps
  p.motion.smooth = 0.05;
  ASSERT_TRUE(w->setSynthParameters(p)) << w->lastError().toStdString();
  EXPECT_FALSE(w->isComputing());
  EXPECT_EQ(w->currentMap(), local);
  QSignalSpy finished(w.get(), &MainWindow::synthesisFinished);
  const synth::MapPath path = pathAlong(*local, 10, 100, 2.0);
  ASSERT_TRUE(w->synthesizeAlong(path));
  ASSERT_TRUE(QTest::qWaitFor([&] { return finished.count() > 0; }, kTimeoutMs));
  ASSERT_NE(w->synthesized(), nullptr) << w->lastError().toStdString();
  EXPECT_EQ(w->synthesized()->motion.num_frames, 61);  // 2 s at 30 fps
  const synth::SynthResult direct = synth::synthesize(*local->blender, path, p.motion);
  ASSERT_EQ(direct.motion.num_frames, 61);
  for (int f : {0, 30, 60}) {
    EXPECT_TRUE(
        direct.motion.rotation(f, 3).isApprox(w->synthesized()->motion.rotation(f, 3), 1e-12));
  }
  w->pause();
  // Not timed as drawn: the same gesture followed at a steady speed of the clip's own pace.
  p.timedAsDrawn = false;
  ASSERT_TRUE(w->setSynthParameters(p));
  ASSERT_TRUE(w->synthesizeAlong(path));
  ASSERT_TRUE(QTest::qWaitFor([&] { return finished.count() > 1; }, kTimeoutMs));
  synth::MapPath untimed = path;
  untimed.times.clear();
  const synth::SynthResult steady = synth::synthesize(*local->blender, untimed, p.motion);
  EXPECT_EQ(w->synthesized()->motion.num_frames, steady.motion.num_frames);
  EXPECT_NE(steady.motion.num_frames, 61);
  w->pause();

  // Blend options: a map whose blender has them (the embedding's cache key includes them).
  p.blend.mode = synth::BlendMode::Kriging;
  ASSERT_TRUE(w->setSynthParameters(p));
  ASSERT_TRUE(
      QTest::qWaitFor([&] { return w->currentMap() != nullptr || !w->isComputing(); }, kTimeoutMs));
  const MapResult* kriging = w->currentMap();
  ASSERT_NE(kriging, nullptr) << w->lastError().toStdString();
  EXPECT_NE(kriging, local);
  EXPECT_EQ(kriging->blender->options().mode, synth::BlendMode::Kriging);
  const Eigen::Vector2d between =
      0.5 * (kriging->blender->sample_point(40) + kriging->blender->sample_point(41));
  EXPECT_EQ(int(kriging->blender->locate(between).samples.size()), kriging->blender->num_points());
  p.blend.mode = synth::BlendMode::Local;
  ASSERT_TRUE(w->setSynthParameters(p));
  EXPECT_FALSE(w->isComputing());
  EXPECT_EQ(w->currentMap(), local);  // cached: back at once

  // Values the library rejects: its message, and the parameters stay.
  SynthParameters bad = p;
  bad.motion.fps = -1.0;
  EXPECT_FALSE(w->setSynthParameters(bad));
  EXPECT_TRUE(w->lastError().contains("fps")) << w->lastError().toStdString();
  bad = p;
  bad.blend.neighbors = local->blender->num_samples() + 1;
  EXPECT_FALSE(w->setSynthParameters(bad));
  EXPECT_TRUE(w->lastError().contains("neighbors")) << w->lastError().toStdString();
  EXPECT_EQ(w->synthParameters().motion.fps, 30.0);
  EXPECT_EQ(w->synthParameters().blend.neighbors, 12);
  EXPECT_EQ(w->currentMap(), local);
}

TEST(StudioSynthesis, TheDialogEditsEveryParameter) {
  auto w = windowWithMap();
  QAction* action = nullptr;
  for (QAction* a : w->findChildren<QAction*>()) {
    if (a->text() == "S&ynthesis…") action = a;
  }
  ASSERT_NE(action, nullptr);
  // Fill the modal dialog as a user would, then press OK.
  bool filled = false;
  QTimer::singleShot(50, [&] {
    auto* dialog = qobject_cast<QDialog*>(QApplication::activeModalWidget());
    if (!dialog) return;
    const auto combos = dialog->findChildren<QComboBox*>();
    const auto ints = dialog->findChildren<QSpinBox*>();
    const auto reals = dialog->findChildren<QDoubleSpinBox*>();
    if (combos.size() != 3 || ints.size() != 1 || reals.size() != 4) return dialog->reject();
    combos[0]->setCurrentText("idw");
    combos[1]->setCurrentText("at a steady speed");
    combos[2]->setCurrentText("free after the first key");
    ints[0]->setValue(5);
    reals[0]->setValue(2.5);   // reach
    reals[1]->setValue(0.75);  // speed
    reals[2]->setValue(60.0);  // fps
    reals[3]->setValue(0.02);  // smoothing
    filled = true;
    dialog->findChild<QDialogButtonBox*>()->button(QDialogButtonBox::Ok)->click();
  });
  action->trigger();
  ASSERT_TRUE(filled);
  const SynthParameters& p = w->synthParameters();
  EXPECT_EQ(p.blend.mode, synth::BlendMode::Idw);
  EXPECT_EQ(p.blend.neighbors, 5);
  EXPECT_EQ(p.blend.reach, 2.5);
  EXPECT_FALSE(p.timedAsDrawn);
  EXPECT_EQ(p.motion.speed, 0.75);
  EXPECT_EQ(p.motion.fps, 60.0);
  EXPECT_EQ(p.motion.smooth, 0.02);
  EXPECT_TRUE(p.freeRoots);
  ASSERT_TRUE(
      QTest::qWaitFor([&] { return w->currentMap() != nullptr || !w->isComputing(); }, kTimeoutMs));
  ASSERT_NE(w->currentMap(), nullptr) << w->lastError().toStdString();
  EXPECT_EQ(w->currentMap()->blender->options().mode, synth::BlendMode::Idw);
  EXPECT_EQ(w->currentMap()->blender->options().neighbors, 5);
}

TEST(StudioSettings, TheLastGoodParametersComeBackNextSession) {
  {
    auto w = windowWithMap();
    MapParameters m = w->parameters();
    m.k = 8;
    m.heat = 2.5;
    m.distance = features::DistanceKind::Geodesic;
    m.exclude = ".*Thumb.*";
    SynthParameters s = w->synthParameters();
    s.blend.mode = synth::BlendMode::Idw;
    s.blend.neighbors = 6;
    s.motion.fps = 30.0;
    s.motion.smooth = 0.1;
    s.timedAsDrawn = false;
    s.freeRoots = true;
    ASSERT_TRUE(w->setSynthParameters(s));
    w->setParameters(m);
    ASSERT_TRUE(QTest::qWaitFor([&] { return w->currentMap() != nullptr || !w->isComputing(); },
                                kTimeoutMs));
    ASSERT_NE(w->currentMap(), nullptr) << w->lastError().toStdString();
    // A map that fails (a bad regular expression) is not remembered.
    m.exclude = "(";
    QSignalSpy finished(w.get(), &MainWindow::computationFinished);
    w->setParameters(m);
    ASSERT_TRUE(QTest::qWaitFor([&] { return finished.count() > 0; }, kTimeoutMs));
    EXPECT_FALSE(finished.front().front().toBool());
  }
  MainWindow next;
  EXPECT_EQ(next.parameters().k, 8);
  EXPECT_EQ(next.parameters().heat, 2.5);
  EXPECT_EQ(next.parameters().distance, features::DistanceKind::Geodesic);
  EXPECT_EQ(next.parameters().features, features::FeatureKind::Quaternions);
  EXPECT_EQ(next.parameters().exclude, ".*Thumb.*");
  EXPECT_EQ(next.synthParameters().blend.mode, synth::BlendMode::Idw);
  EXPECT_EQ(next.synthParameters().blend.neighbors, 6);
  EXPECT_EQ(next.synthParameters().motion.fps, 30.0);
  EXPECT_EQ(next.synthParameters().motion.smooth, 0.1);
  EXPECT_FALSE(next.synthParameters().timedAsDrawn);
  EXPECT_TRUE(next.synthParameters().freeRoots);

  // Values edited by hand that the library would reject fall back to the defaults.
  QSettings settings;
  settings.setValue("map/k", "many");
  settings.setValue("map/heat", "auto");
  settings.setValue("map/distance", "manhattan");
  settings.setValue("synth/blend", "spline");
  settings.setValue("synth/neighbors", 0);
  settings.setValue("synth/fps", -5);
  settings.sync();
  MainWindow reset;
  EXPECT_EQ(reset.parameters().k, 20);
  EXPECT_FALSE(reset.parameters().heat.has_value());
  EXPECT_EQ(reset.parameters().distance, features::DistanceKind::PointCloud);
  EXPECT_EQ(reset.synthParameters().blend.mode, synth::BlendMode::Local);
  EXPECT_EQ(reset.synthParameters().blend.neighbors, 12);
  EXPECT_EQ(reset.synthParameters().motion.fps, 0.0);
  EXPECT_EQ(reset.synthParameters().motion.smooth, 0.1);  // valid, kept
}

TEST(StudioPlayback, SpeedScalesTheClockAndLoopOffStopsAtTheEnd) {
  auto w = windowWithMap(embed::Method::Pca);
  const double frameTime = w->clip()->motion.frame_time;
  w->setFrame(0);
  w->setPlaybackSpeed(2.0);
  EXPECT_EQ(w->playbackSpeed(), 2.0);
  QElapsedTimer clock;
  clock.start();
  w->play();
  ASSERT_TRUE(QTest::qWaitFor([&] { return w->currentFrame() >= 100; }, kTimeoutMs));
  const double elapsed = double(clock.nsecsElapsed()) * 1e-9;
  const int frame = w->currentFrame();
  w->pause();
  std::printf("2x playback: frame %d after %.3f s (%.1f frames/s; the clip has %.0f fps)\n", frame,
              elapsed, frame / elapsed, 1.0 / frameTime);
  // The frame follows the clock: never ahead of 2x, and faster than 1x.
  EXPECT_LE(frame, int(std::floor(2.0 * elapsed / frameTime)) + 1);
  EXPECT_GT(frame, int(elapsed / frameTime));

  w->setPlaybackSpeed(1.0);
  w->setLoop(false);
  const int last = w->clip()->motion.num_frames - 1;
  w->setFrame(last - 6);
  w->play();
  ASSERT_TRUE(QTest::qWaitFor([&] { return !w->isPlaying(); }, kTimeoutMs));
  EXPECT_EQ(w->currentFrame(), last);
  w->play();  // from the end without loop: starts over
  EXPECT_LT(w->currentFrame(), 5);
  w->pause();
  w->setLoop(true);
}

TEST(StudioMap, ParametersGiveANewMapAndTheOldOneStaysCached) {
  auto w = windowWithMap(embed::Method::Isomap);
  const MapResult* k20 = w->currentMap();
  ASSERT_NE(k20, nullptr);
  MapParameters p = w->parameters();
  p.k = 8;
  p.exclude = ".*Thumb.*";
  w->setParameters(p);
  EXPECT_TRUE(w->isComputing());
  ASSERT_TRUE(
      QTest::qWaitFor([&] { return w->currentMap() != nullptr || !w->isComputing(); }, kTimeoutMs));
  ASSERT_NE(w->currentMap(), nullptr) << w->lastError().toStdString();
  EXPECT_NE(w->currentMap(), k20);
  EXPECT_TRUE(w->statusText().contains("k=8")) << w->statusText().toStdString();
  // Back to the defaults: the first map, at once.
  w->setParameters(MapParameters{});
  EXPECT_FALSE(w->isComputing());
  EXPECT_EQ(w->currentMap(), k20);
  // A value the library rejects is its error message, not a crash.
  p.exclude = "(";
  QSignalSpy finished(w.get(), &MainWindow::computationFinished);
  w->setParameters(p);
  ASSERT_TRUE(QTest::qWaitFor([&] { return finished.count() > 0; }, kTimeoutMs));
  EXPECT_FALSE(finished.front().front().toBool());
  EXPECT_FALSE(w->lastError().isEmpty());
  std::printf("error shown: %s\n", qPrintable(w->lastError()));
}

TEST(StudioMap, FilesDroppedTogetherShareOneMap) {
  QTemporaryDir dir;
  sample::SampleOptions options;
  options.seconds = 1.0;
  QList<QUrl> urls;
  for (auto kind : {sample::SampleKind::Swing, sample::SampleKind::Walk}) {
    const Clip clip = sample::make_sample_clip(kind, options);
    const QString path = dir.filePath(kind == sample::SampleKind::Swing ? "swing.bvh" : "walk.bvh");
    io::write_bvh(io::from_motion(clip.skeleton, clip.motion), path.toStdString());
    urls << QUrl::fromLocalFile(path);
  }
  MainWindow w;
  w.setInteractive(false);
  w.setMethod(embed::Method::Pca);
  QMimeData mime;
  mime.setUrls(urls);
  QDragEnterEvent enter(QPoint(10, 10), Qt::CopyAction, &mime, Qt::LeftButton, Qt::NoModifier);
  QApplication::sendEvent(&w, &enter);
  QDropEvent drop(QPointF(10, 10), Qt::CopyAction, &mime, Qt::LeftButton, Qt::NoModifier);
  QApplication::sendEvent(&w, &drop);
  ASSERT_EQ(w.clipCount(), 2) << w.lastError().toStdString();
  ASSERT_TRUE(
      QTest::qWaitFor([&] { return w.currentMap() != nullptr || !w.isComputing(); }, kTimeoutMs));
  ASSERT_NE(w.currentMap(), nullptr) << w.lastError().toStdString();
  EXPECT_EQ(w.currentMap()->map.features->segment_starts, (std::vector<int>{0, 120}));
  // Ctrl-drop adds to the open map.
  QMimeData one;
  one.setUrls({urls.front()});
  QDragEnterEvent enterAgain(QPoint(10, 10), Qt::CopyAction, &one, Qt::LeftButton,
                             Qt::ControlModifier);
  QApplication::sendEvent(&w, &enterAgain);
  QDropEvent add(QPointF(10, 10), Qt::CopyAction, &one, Qt::LeftButton, Qt::ControlModifier);
  QApplication::sendEvent(&w, &add);
  EXPECT_EQ(w.clipCount(), 3);
}

TEST(StudioMap, ExportsTheMapAsCsvPngAndSvg) {
  auto w = windowWithMap(embed::Method::Pca);
  const MapResult* map = w->currentMap();
  ASSERT_NE(map, nullptr);
  QTemporaryDir dir;
  ASSERT_TRUE(w->exportMap(dir.filePath("map.csv"))) << w->lastError().toStdString();
  const pipeline::MapTable table = pipeline::read_map_csv(dir.filePath("map.csv").toStdString());
  ASSERT_EQ(table.num_rows(), map->map.features->num_samples());
  EXPECT_NO_THROW(table.check_matches(*map->map.features));
  EXPECT_EQ(table.coords.row(7), map->map.embedding.coordinates.row(7).leftCols(2));
  ASSERT_TRUE(w->exportMap(dir.filePath("map.png")));
  EXPECT_EQ(QImage(dir.filePath("map.png")).width(), 800);
  ASSERT_TRUE(w->exportMap(dir.filePath("map.svg")));
  EXPECT_GT(QFileInfo(dir.filePath("map.svg")).size(), 1000);
  EXPECT_FALSE(w->exportMap(dir.filePath("map.xyz")));
  EXPECT_TRUE(w->lastError().contains("map.xyz")) << w->lastError().toStdString();
}

TEST(StudioMap, SketchModeTurnsAPlainDragIntoASketch) {
  auto w = windowWithMap(embed::Method::Pca);
  const MapResult* map = w->currentMap();
  ASSERT_NE(map, nullptr);
  MapView* view = w->mapView();
  QSignalSpy sketches(view, &MapView::sketchFinished);
  QSignalSpy drags(view, &MapView::dragged);
  view->setSketchMode(true);
  QTest::mousePress(view, Qt::LeftButton, Qt::NoModifier,
                    view->toWidget(map->blender->sample_point(20)).toPoint());
  for (int row = 40; row <= 120; row += 20) {
    QTest::qWait(10);
    QTest::mouseMove(view, view->toWidget(map->blender->sample_point(row)).toPoint());
  }
  QTest::mouseRelease(view, Qt::LeftButton, Qt::NoModifier,
                      view->toWidget(map->blender->sample_point(120)).toPoint());
  EXPECT_EQ(sketches.count(), 1);
  EXPECT_EQ(drags.count(), 0);
  ASSERT_TRUE(QTest::qWaitFor([&] { return !w->isSynthesizing(); }, kTimeoutMs));
  EXPECT_NE(w->synthesized(), nullptr);
  w->pause();
  view->setSketchMode(false);
}

TEST(StudioMap, MagnifierSpreadsFramesUnderItAndGesturesStillHitTheRightPoint) {
  auto w = windowWithMap(embed::Method::Isomap);
  const MapResult* map = w->currentMap();
  ASSERT_NE(map, nullptr);
  w->pause();
  MapView* view = w->mapView();
  const Eigen::Vector2d a = map->blender->sample_point(100), b = map->blender->sample_point(101);
  const double plain = QLineF(view->toWidget(a), view->toWidget(b)).length();
  const QPointF at = view->toWidget(a);
  view->setLensEnabled(true);
  view->setLensPower(4.0);
  view->setLensCenter(at);
  const double lensed = QLineF(view->toWidget(a), view->toWidget(b)).length();
  std::printf("frames 100-101: %.2f px apart without the lens, %.2f px under it (power 4)\n", plain,
              lensed);
  EXPECT_GT(lensed, 3.0 * plain);  // magnification d + 1 = 5 at the centre, less away from it
  // Conversions are inverse to each other inside and outside the lens.
  for (const QPointF pixel : {view->lensCenter() + QPointF(10, -7),
                              view->lensCenter() + QPointF(view->lensRadius() * 0.8, 0),
                              view->lensCenter() + QPointF(view->lensRadius() * 1.5, 3)}) {
    EXPECT_LT(QLineF(view->toWidget(view->toMap(pixel)), pixel).length(), 1e-6);
  }
  // A drag inside the lens (it stays put while the button is down) blends at the lensed point.
  const QPointF centre = view->lensCenter();
  const QPoint press = centre.toPoint();
  QTest::mousePress(view, Qt::LeftButton, Qt::NoModifier, press);
  const QPoint inside = press + QPoint(15, 9);
  QTest::mouseMove(view, inside);
  EXPECT_EQ(view->lensCenter(), centre);
  // Placed where the frame shown before the drag stood (MapGestures).
  const Motion expected = map->blender->pose(
      map->blender->locate(view->toMap(QPointF(inside))),
      synth::root_placement(w->clip()->motion, w->currentFrame(), map->blender->motion_root()));
  const Motion& shown = w->skeletonView()->currentPose();
  for (int j = 0; j < shown.num_joints; ++j) {
    EXPECT_GT(std::abs(shown.rotation(0, j).dot(expected.rotation(0, j))), 1.0 - 1e-12)
        << "joint " << j;
  }
  QTest::mouseRelease(view, Qt::LeftButton, Qt::NoModifier, inside);
  // The wheel changes the power; off, the lens leaves the conversions alone.
  QWheelEvent wheel(QPointF(press), view->mapToGlobal(QPointF(press)), QPoint(), QPoint(0, 120),
                    Qt::NoButton, Qt::NoModifier, Qt::NoScrollPhase, false);
  QApplication::sendEvent(view, &wheel);
  EXPECT_NEAR(view->lensPower(), 5.0, 1e-9);
  view->setLensEnabled(false);
  EXPECT_NEAR(QLineF(view->toWidget(a), view->toWidget(b)).length(), plain, 1e-9);
}

TEST(StudioMap, ClipsOfTheSameSkeletonShareOneMap) {
  auto w = windowWithMap(embed::Method::Pca);
  sample::SampleOptions options;
  options.seconds = 1.0;
  Clip walk = sample::make_sample_clip(sample::SampleKind::Walk, options);
  walk.path = "walk.bvh";
  ASSERT_TRUE(w->addClip(walk)) << w->lastError().toStdString();
  EXPECT_EQ(w->clipCount(), 2);
  ASSERT_TRUE(
      QTest::qWaitFor([&] { return w->currentMap() != nullptr || !w->isComputing(); }, kTimeoutMs));
  const MapResult* map = w->currentMap();
  ASSERT_NE(map, nullptr) << w->lastError().toStdString();
  // Coloured by clip, the clips named in the legend.
  EXPECT_EQ(w->mapView()->plotOptions().clip_names,
            QStringList({"clip 1: sample:swing", "clip 2: walk.bvh"}));
  // One map of both clips, each its own trajectory.
  EXPECT_EQ(map->map.features->segment_starts, (std::vector<int>{0, 240}));
  EXPECT_EQ(map->map.features->num_samples(), 240 + 120);
  ASSERT_EQ(map->rowOfFrame.size(), 2u);
  EXPECT_EQ(map->rowOfFrame[1][30], 270);
  EXPECT_TRUE(w->windowTitle().contains("+ 1 more")) << w->windowTitle().toStdString();
  // Clicking the second clip's trajectory (where it is farthest from the first's) plays that
  // clip from that frame.
  int target = 240;
  double farthest = -1.0;
  for (int r = 240; r < 360; ++r) {
    double nearest = 1e300;
    for (int q = 0; q < 240; ++q)
      nearest =
          std::min(nearest, (map->blender->sample_point(q) - map->blender->sample_point(r)).norm());
    if (nearest > farthest) farthest = nearest, target = r;
  }
  const QPoint p = w->mapView()->toWidget(map->blender->sample_point(target)).toPoint();
  QTest::mouseClick(w->mapView(), Qt::LeftButton, Qt::NoModifier, p);
  const int row = map->rowOfFrame[std::size_t(w->currentClip())][std::size_t(w->currentFrame())];
  EXPECT_LE(
      (w->mapView()->toWidget(map->blender->sample_point(row)) - QPointF(p)).manhattanLength(),
      2.0);
  EXPECT_EQ(w->currentClip(), map->map.features->clip_of[std::size_t(row)]);
  ASSERT_EQ(w->currentClip(), 1);
  EXPECT_EQ(w->currentFrame(), map->map.features->frame_of[std::size_t(row)]);
  EXPECT_EQ(w->clip()->path, "walk.bvh");
  EXPECT_TRUE(w->statusText().contains("clip 2 of 2 · 120 frames"))
      << w->statusText().toStdString();
  EXPECT_EQ(*w->mapView()->pointer(), map->blender->sample_point(row));
  // A sketch across both clips blends from both.
  synth::MapPath path;
  path.points = {map->blender->sample_point(100), map->blender->sample_point(300)};
  path.times = {0.0, 1.0};
  ASSERT_TRUE(w->synthesizeAlong(path));
  ASSERT_TRUE(QTest::qWaitFor([&] { return !w->isSynthesizing(); }, kTimeoutMs));
  ASSERT_NE(w->synthesized(), nullptr) << w->lastError().toStdString();
  EXPECT_EQ(w->synthesized()->motion.num_frames, 121);
  w->pause();
  QTemporaryDir dir;
  ASSERT_TRUE(w->exportMap(dir.filePath("both.csv")));
  const pipeline::MapTable table = pipeline::read_map_csv(dir.filePath("both.csv").toStdString());
  EXPECT_EQ(table.num_rows(), 360);
  EXPECT_EQ(table.clip_of.back(), 1);
  // Another skeleton cannot join: the library's hierarchy check, as a message.
  Clip other;
  other.path = "other.bvh";
  other.skeleton.joints.resize(1);
  other.skeleton.joints[0].name = "Root";
  other.motion.resize(10, 1);
  EXPECT_FALSE(w->addClip(other));
  EXPECT_TRUE(w->lastError().contains("other.bvh")) << w->lastError().toStdString();
  EXPECT_EQ(w->clipCount(), 2);
}

TEST(StudioView, CameraFollowsTheRootUnlessToldNotTo) {
  sample::SampleOptions options;
  options.seconds = 2.0;
  const Clip walk = sample::make_sample_clip(sample::SampleKind::Walk, options);
  SkeletonView view;
  view.resize(400, 300);
  view.setSkeleton(walk.skeleton);
  view.setPose(walk.motion, 0);
  const Eigen::Vector3d start = view.camera().target;
  view.setPose(walk.motion, 200);
  const Eigen::Vector3d followed = view.camera().target;
  EXPECT_GT((followed - start).norm(), 10.0);  // the walk moves the root (cm)
  view.setFollowRoot(false);
  view.setPose(walk.motion, 0);
  EXPECT_EQ(view.camera().target, followed);
}

}  // namespace
}  // namespace motionmap::studio
