// MotionMap Studio driven like a user would (offscreen): open a clip, wait for the map, switch
// methods, drag and sketch on the map, play, cancel. Checks compare with the library's answers.
#include <gtest/gtest.h>

#include <QApplication>
#include <QFileInfo>
#include <QMimeData>
#include <QProcess>
#include <QSettings>
#include <QSignalSpy>
#include <QTemporaryDir>
#include <QTest>
#include <QUrl>
#include <fstream>

#include "app/main_window.h"
#include "map/map_view.h"
#include "motionmap/io/bvh.h"
#include "motionmap/sample/sample_clip.h"
#include "scene/scene.h"
#include "scene/skeleton_view.h"
#include "studio_test_util.h"
#include "support/test_data.h"

namespace motionmap::studio {
namespace {

using testing::kTimeoutMs;
using testing::swing;
using testing::windowWithMap;

bool sameRotations(const Motion& a, const Motion& b) {
  if (a.num_joints != b.num_joints || a.num_frames < 1 || b.num_frames < 1) return false;
  for (int j = 0; j < a.num_joints; ++j) {
    if (std::abs(a.rotation(0, j).dot(b.rotation(0, j))) < 1.0 - 1e-12) return false;
  }
  return true;
}

TEST(StudioScene, BonesOfTheSampleSkeletonJoinEveryJointToItsParent) {
  const Clip clip = swing(0.5);
  const WorldPose pose = forward_kinematics(clip.skeleton, clip.motion, 0);
  const auto bones = bone_segments(clip.skeleton, pose);
  int expected = 0;
  for (const Joint& j : clip.skeleton.joints) {
    expected += int(j.end_sites.size());
    if (j.parent >= 0 && (pose.positions[std::size_t(&j - clip.skeleton.joints.data())] -
                          pose.positions[std::size_t(j.parent)])
                                 .squaredNorm() > 0) {
      ++expected;
    }
  }
  EXPECT_EQ(int(bones.size()), expected);
  EXPECT_GT(bones.size(), 20u);
  // About the subject's height (1.72 m in cm) plus arms: the extent is of the order of metres.
  EXPECT_GT(pose_extent(pose), 100.0);
  EXPECT_LT(pose_extent(pose), 400.0);
}

TEST(StudioScene, BoxHas36VerticesWithUnitNormalsAroundTheBone) {
  std::vector<MeshVertex> mesh;
  appendBox(mesh, {0, 0, 0}, {0, 10, 0}, 1.0, {1, 0, 0});
  ASSERT_EQ(mesh.size(), 36u);
  for (const auto& v : mesh) {
    EXPECT_NEAR(Eigen::Vector3f(v.normal[0], v.normal[1], v.normal[2]).norm(), 1.0f, 1e-5f);
    EXPECT_NEAR(std::hypot(v.position[0], v.position[2]), std::sqrt(2.0), 1e-5);  // corners
    EXPECT_TRUE(v.position[1] == 0.0f || v.position[1] == 10.0f);
  }
  EXPECT_EQ(gridLines({3, 0, 3}, 10.0).size(), 84u);
  EXPECT_TRUE(gridLines({0, 0, 0}, 0.0).empty());
}

TEST(StudioScene, CameraProjectsItsTargetToTheCentreAndZoomsIn) {
  OrbitCamera camera;
  camera.target = {10, 90, -5};
  const QSize size(640, 480);
  const QPointF c = projectToPixels(camera, size, camera.target);
  EXPECT_NEAR(c.x(), 320.0, 1e-3);
  EXPECT_NEAR(c.y(), 240.0, 1e-3);
  // A point above the target is drawn above the centre (pixel y grows downwards).
  EXPECT_LT(projectToPixels(camera, size, camera.target + Eigen::Vector3d(0, 50, 0)).y(), 240.0);
  const double d = camera.distance;
  camera.zoom(1);
  EXPECT_NEAR(camera.distance, d * 0.85, 1e-9);
  camera.panBy(100, 0, size);
  EXPECT_GT(camera.pan.norm(), 0.0);
  EXPECT_NEAR(camera.pan.y(), 0.0, 1e-9);  // horizontal drag, horizontal pan
}

TEST(Studio, ComputesTheMapOnAWorkerAndReportsItInTheStatusBar) {
  auto w = windowWithMap();
  const MapResult* map = w->currentMap();
  ASSERT_NE(map, nullptr);
  EXPECT_EQ(map->map.embedding.method, embed::Method::Isomap);
  EXPECT_EQ(map->map.embedding.coordinates.rows(), map->map.features->num_samples());
  EXPECT_TRUE(w->mapView()->hasMap());
  const QString status = w->statusText();
  EXPECT_TRUE(status.contains("240 frames")) << status.toStdString();
  EXPECT_TRUE(status.contains("120 fps")) << status.toStdString();
  EXPECT_TRUE(status.contains("method=isomap")) << status.toStdString();
  EXPECT_TRUE(status.contains("trustworthiness 0.")) << status.toStdString();
  // The pointer sits on frame 0's map point.
  ASSERT_TRUE(w->mapView()->pointer().has_value());
  EXPECT_EQ(*w->mapView()->pointer(), map->blender->sample_point(map->rowOfFrame[0][0]));
}

TEST(Studio, SwitchingBackToAComputedMethodIsInstant) {
  auto w = windowWithMap();
  const MapResult* isomap = w->currentMap();
  w->setMethod(embed::Method::Pca);
  EXPECT_EQ(w->currentMap(), nullptr);  // computing
  ASSERT_TRUE(QTest::qWaitFor([&] { return w->currentMap() != nullptr; }, kTimeoutMs));
  EXPECT_EQ(w->currentMap()->map.embedding.method, embed::Method::Pca);
  EXPECT_TRUE(w->statusText().contains("method=pca"));
  QSignalSpy ready(w.get(), &MainWindow::mapReady);
  w->setMethod(embed::Method::Isomap);
  EXPECT_FALSE(w->isComputing());
  EXPECT_EQ(w->currentMap(), isomap);  // the cached result itself, no event loop needed
  EXPECT_EQ(ready.count(), 1);
}

TEST(Studio, DraggingOnTheMapShowsTheBlendedPoseUnderTheMouse) {
  auto w = windowWithMap();
  const MapResult* map = w->currentMap();
  ASSERT_NE(map, nullptr);
  w->pause();
  MapView* view = w->mapView();
  // From frame 40's map point towards frame 80's.
  const QPoint a = view->toWidget(map->blender->sample_point(40)).toPoint();
  const QPoint b = view->toWidget(map->blender->sample_point(80)).toPoint();
  const QPoint mid = (a + b) / 2 + QPoint(3, 2);
  // The blends stand where the frame shown before the drag stood (its heading and floor position).
  const synth::RootPlacement placement =
      synth::root_placement(w->clip()->motion, w->currentFrame(), map->blender->motion_root());
  const auto placedAt = [&](const QPoint& pixel) {
    return map->blender->pose(map->blender->locate(view->toMap(QPointF(pixel))), placement);
  };
  QTest::mousePress(view, Qt::LeftButton, Qt::NoModifier, a);
  QTest::mouseMove(view, mid);
  const Motion expected = placedAt(mid);
  EXPECT_TRUE(sameRotations(w->skeletonView()->currentPose(), expected));
  // The text says whether the library moved the point into the data's reach.
  EXPECT_EQ(view->hoverText().contains("outside"),
            map->blender->locate(view->toMap(QPointF(mid))).validity.clamped);
  const QPoint onSample = view->toWidget(map->blender->sample_point(60)).toPoint();
  QTest::mouseMove(view, onSample);
  EXPECT_EQ(view->hoverText(), "blend");  // within half a pixel of a sample: inside the data
  EXPECT_TRUE(sameRotations(w->skeletonView()->currentPose(), placedAt(onSample)));
  QTest::mouseMove(view, b);
  QTest::mouseRelease(view, Qt::LeftButton, Qt::NoModifier, b);
  EXPECT_TRUE(sameRotations(w->skeletonView()->currentPose(), placedAt(b)));
}

TEST(Studio, HoveringTheTrajectoryShowsTheFrameNumber) {
  auto w = windowWithMap();
  const MapResult* map = w->currentMap();
  ASSERT_NE(map, nullptr);
  MapView* view = w->mapView();
  const int row = map->map.features->num_samples() - 1;  // the last frame: nothing drawn over it
  QTest::mouseMove(view, view->toWidget(map->blender->sample_point(row)).toPoint());
  const QString text = view->hoverText();
  ASSERT_TRUE(text.startsWith("frame ")) << text.toStdString();
  // The frame named is one whose map point is under the mouse (within a pixel).
  const int frame = text.mid(6).toInt();
  EXPECT_LE((view->toWidget(map->blender->sample_point(map->rowOfFrame[0][std::size_t(frame)])) -
             view->toWidget(map->blender->sample_point(row)))
                .manhattanLength(),
            2.0);
  QTest::mouseMove(view, QPoint(2, 2));
  EXPECT_TRUE(view->hoverText().isEmpty());
}

TEST(Studio, ClickNearTheTrajectoryJumpsToThatFrame) {
  auto w = windowWithMap();
  const MapResult* map = w->currentMap();
  ASSERT_NE(map, nullptr);
  const int row = 150;
  const QPoint p = w->mapView()->toWidget(map->blender->sample_point(row)).toPoint();
  QTest::mouseClick(w->mapView(), Qt::LeftButton, Qt::NoModifier, p);
  // The nearest sample to the click is `row` or one drawn within a pixel of it.
  const int frame = w->currentFrame();
  EXPECT_LE(
      (w->mapView()->toWidget(map->blender->sample_point(map->rowOfFrame[0][std::size_t(frame)])) -
       QPointF(p))
          .manhattanLength(),
      2.0);
  EXPECT_TRUE(sameRotations(w->skeletonView()->currentPose(), [&] {
    Motion m;
    m.resize(1, w->clip()->motion.num_joints);
    for (int j = 0; j < m.num_joints; ++j) m.rotation(0, j) = w->clip()->motion.rotation(frame, j);
    return m;
  }()));
  // Far from the trajectory (a corner of the widget) nothing happens.
  QTest::mouseClick(w->mapView(), Qt::LeftButton, Qt::NoModifier, QPoint(2, 2));
  EXPECT_EQ(w->currentFrame(), frame);
}

TEST(Studio, SketchSynthesizesAMotionAsLongAsTheGestureAndExportsIt) {
  auto w = windowWithMap();
  const MapResult* map = w->currentMap();
  ASSERT_NE(map, nullptr);
  MapView* view = w->mapView();
  synth::MapPath sketched;
  QObject::connect(view, &MapView::sketchFinished, [&](const synth::MapPath& p) { sketched = p; });
  QTest::mousePress(view, Qt::LeftButton, Qt::ShiftModifier,
                    view->toWidget(map->blender->sample_point(20)).toPoint());
  for (int row = 30; row <= 200; row += 10) {
    QTest::qWait(15);
    QTest::mouseMove(view, view->toWidget(map->blender->sample_point(row)).toPoint());
  }
  QTest::qWait(15);
  QTest::mouseRelease(view, Qt::LeftButton, Qt::NoModifier,
                      view->toWidget(map->blender->sample_point(200)).toPoint());
  ASSERT_GE(sketched.points.size(), 2u);
  // The release only starts the synthesis: the worker's result comes back through the event loop.
  EXPECT_TRUE(w->isSynthesizing());
  EXPECT_EQ(w->synthesized(), nullptr);
  ASSERT_TRUE(QTest::qWaitFor([&] { return !w->isSynthesizing(); }, kTimeoutMs));
  ASSERT_NE(w->synthesized(), nullptr) << w->lastError().toStdString();
  const double duration = sketched.times.back() - sketched.times.front();
  EXPECT_GT(duration, 0.2);
  const double frameTime = w->clip()->motion.frame_time;
  EXPECT_EQ(w->synthesized()->motion.num_frames, int(std::floor(duration / frameTime + 1e-9)) + 1);
  EXPECT_NEAR(w->synthesized()->motion.frame_time, frameTime, 1e-12);
  EXPECT_TRUE(w->isPlaying());
  EXPECT_EQ(w->playingMotion(), &w->synthesized()->motion);
  // While it plays, the pointer shows where each synthesized frame was blended.
  w->pause();
  w->setFrame(5);
  EXPECT_EQ(*view->pointer(), w->synthesized()->validity[5].point);
  const Motion* synthesized = &w->synthesized()->motion;
  EXPECT_EQ(w->playingMotion(), synthesized);
  EXPECT_TRUE(w->hasUnsavedMotion());
  EXPECT_TRUE(w->statusText().contains(
      QString("synthesized: %1 frames").arg(w->synthesized()->motion.num_frames)))
      << w->statusText().toStdString();

  QTemporaryDir dir;
  const QString path = dir.filePath("sketch.bvh");
  ASSERT_TRUE(w->exportMotion(path));
  EXPECT_FALSE(w->hasUnsavedMotion());
  EXPECT_EQ(io::read_bvh(path.toStdString()).num_frames, w->synthesized()->motion.num_frames);
}

TEST(Studio, PlaybackAdvancesTheFrameAndMovesThePointer) {
  auto w = windowWithMap();
  const MapResult* map = w->currentMap();
  ASSERT_NE(map, nullptr);
  w->setFrame(0);
  const Eigen::Vector2d start = *w->mapView()->pointer();
  w->play();
  ASSERT_TRUE(QTest::qWaitFor([&] { return w->currentFrame() >= 20; }, kTimeoutMs));
  w->pause();
  const int frame = w->currentFrame();
  EXPECT_EQ(*w->mapView()->pointer(),
            map->blender->sample_point(map->rowOfFrame[0][std::size_t(frame)]));
  EXPECT_NE(*w->mapView()->pointer(), start);
  // → steps one frame, ← back, Space toggles play.
  QTest::keyClick(w.get(), Qt::Key_Right);
  EXPECT_EQ(w->currentFrame(), frame + 1);
  QTest::keyClick(w.get(), Qt::Key_Left);
  EXPECT_EQ(w->currentFrame(), frame);
  QTest::keyClick(w.get(), Qt::Key_Space);
  EXPECT_TRUE(w->isPlaying());
  QTest::keyClick(w.get(), Qt::Key_Space);
  EXPECT_FALSE(w->isPlaying());
  // Playback loops: from the last frame it goes on at frame 0.
  const int last = w->clip()->motion.num_frames - 1;
  w->setFrame(last);
  w->play();
  ASSERT_TRUE(QTest::qWaitFor([&] { return w->currentFrame() < last; }, kTimeoutMs));
  EXPECT_LT(w->currentFrame(), 20);
  w->pause();
}

TEST(Studio, CancellingALongComputationStopsIt) {
  MainWindow w;
  w.setInteractive(false);
  w.setMethod(embed::Method::Isomap);
  QSignalSpy progress(&w, &MainWindow::progressChanged);
  QSignalSpy finished(&w, &MainWindow::computationFinished);
  w.openClip(swing(50.0));  // 6000 frames: the distance matrix alone takes seconds
  ASSERT_EQ(w.clip()->motion.num_frames, 6000);
  ASSERT_TRUE(w.isComputing());
  ASSERT_TRUE(QTest::qWaitFor([&] { return progress.count() > 0; }, kTimeoutMs));
  w.cancelComputation();
  EXPECT_FALSE(w.isComputing());
  EXPECT_EQ(w.currentMap(), nullptr);
  ASSERT_EQ(finished.count(), 1);
  EXPECT_FALSE(finished.front().front().toBool());
  EXPECT_TRUE(w.statusText().contains("cancelled")) << w.statusText().toStdString();
}

TEST(Studio, ChangingMethodOrClosingDuringAComputationIsSafe) {
  {
    MainWindow w;
    w.setInteractive(false);
    w.setMethod(embed::Method::Mds);
    w.openClip(swing(50.0));
    ASSERT_TRUE(w.isComputing());
    w.setMethod(embed::Method::Pca);  // cancels the 6000-frame MDS, starts PCA
    EXPECT_EQ(w.method(), embed::Method::Pca);
    w.openClip(swing());
    ASSERT_TRUE(QTest::qWaitFor([&] { return w.currentMap() != nullptr; }, kTimeoutMs));
    EXPECT_EQ(w.currentMap()->map.embedding.method, embed::Method::Pca);
    EXPECT_EQ(w.currentMap()->map.embedding.coordinates.rows(),
              w.currentMap()->map.features->num_samples());
  }
  {
    MainWindow w;  // destroyed while computing: the destructor cancels and joins the worker
    w.setInteractive(false);
    w.setMethod(embed::Method::Isomap);
    w.openClip(swing(50.0));
    EXPECT_TRUE(w.isComputing());
  }
}

TEST(Studio, LibraryErrorsAreReportedNotFatal) {
  MainWindow w;
  w.setInteractive(false);
  EXPECT_FALSE(w.openFile("/nonexistent/take.bvh"));
  EXPECT_TRUE(w.lastError().contains("/nonexistent/take.bvh")) << w.lastError().toStdString();
  std::printf("errors shown: %s\n", qPrintable(w.lastError()));
  QTemporaryDir dir;
  const QString bad = dir.filePath("bad.bvh");
  std::ofstream(bad.toStdString()) << "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0\n";
  EXPECT_FALSE(w.openFile(bad));
  EXPECT_TRUE(w.lastError().contains("bad.bvh:5:1: error: file ends early"))
      << w.lastError().toStdString();
  std::printf("errors shown: %s\n", qPrintable(w.lastError()));
  EXPECT_TRUE(w.statusText().startsWith("Error: ")) << w.statusText().toStdString();
  EXPECT_EQ(w.clip(), nullptr);
  // A map the method cannot make (k = 20 neighbours of a 10-frame clip) is an error, not a crash.
  sample::SampleOptions tiny;
  tiny.seconds = 0.1;
  QSignalSpy finished(&w, &MainWindow::computationFinished);
  w.openClip(sample::make_sample_clip(sample::SampleKind::Walk, tiny));
  ASSERT_TRUE(QTest::qWaitFor([&] { return finished.count() > 0; }, kTimeoutMs));
  EXPECT_FALSE(finished.front().front().toBool());
  std::printf("errors shown: %s\n", qPrintable(w.lastError()));
  EXPECT_FALSE(w.lastError().isEmpty());
  EXPECT_EQ(w.currentMap(), nullptr);
}

TEST(Studio, DroppingAFileOpensIt) {
  QTemporaryDir dir;
  const QString path = dir.filePath("walk.bvh");
  sample::SampleOptions options;
  options.seconds = 1.0;
  const Clip walk = sample::make_sample_clip(sample::SampleKind::Walk, options);
  io::write_bvh(io::from_motion(walk.skeleton, walk.motion), path.toStdString());
  MainWindow w;
  w.setInteractive(false);
  w.setMethod(embed::Method::Pca);
  QMimeData mime;
  mime.setUrls({QUrl::fromLocalFile(path)});
  QDragEnterEvent enter(QPoint(10, 10), Qt::CopyAction, &mime, Qt::LeftButton, Qt::NoModifier);
  QApplication::sendEvent(&w, &enter);
  EXPECT_TRUE(enter.isAccepted());
  QDropEvent drop(QPointF(10, 10), Qt::CopyAction, &mime, Qt::LeftButton, Qt::NoModifier);
  QApplication::sendEvent(&w, &drop);
  ASSERT_NE(w.clip(), nullptr) << w.lastError().toStdString();
  EXPECT_EQ(w.clip()->path, path.toStdString());
  EXPECT_EQ(w.clip()->motion.num_frames, 120);
  ASSERT_TRUE(QTest::qWaitFor([&] { return w.currentMap() != nullptr; }, kTimeoutMs));
  EXPECT_TRUE(w.statusText().contains("method=pca")) << w.statusText().toStdString();
  // Remembered for File → Open recent (settings are the test's own, see gui_test_main.cpp).
  const QStringList recent = QSettings().value("recentFiles").toStringList();
  ASSERT_FALSE(recent.isEmpty());
  EXPECT_EQ(recent.front(), QFileInfo(path).absoluteFilePath());
}

TEST(Studio, OpensARealClip) {
  MOTIONMAP_REQUIRE_SHARED("cmu/64_08.bvh");
  MainWindow w;
  w.setInteractive(false);
  w.setMethod(embed::Method::Pca);
  ASSERT_TRUE(w.openFile(QString::fromStdString(test::shared_file("cmu/64_08.bvh"))));
  ASSERT_TRUE(QTest::qWaitFor([&] { return w.currentMap() != nullptr; }, kTimeoutMs))
      << w.lastError().toStdString();
  EXPECT_TRUE(w.statusText().contains("365 frames")) << w.statusText().toStdString();
  EXPECT_EQ(w.currentMap()->rowOfFrame[0].size(), 365u);
  EXPECT_EQ(w.skeletonView()->currentPose().num_joints, w.clip()->skeleton.num_joints());
}

// Runs with either renderer: QPainter offscreen, OpenGL under a display (e.g. xvfb-run -a with
// QT_QPA_PLATFORM=xcb).
TEST(Studio, ViewDrawsTheSkeletonWhereTheCameraProjectsItsJoints) {
  auto w = windowWithMap(embed::Method::Pca);
  QTest::qWait(50);
  std::printf("3-D view renderer: %s\n", w->skeletonView()->glReady() ? "OpenGL" : "QPainter");
  const QImage image = w->skeletonView()->renderImage();
  ASSERT_FALSE(image.isNull());
  const QColor background = image.pixelColor(2, 2);
  int differing = 0;
  for (const QPointF& p : w->skeletonView()->jointPixels()) {
    const QPoint q = (p * image.width() / double(w->skeletonView()->width())).toPoint();
    if (image.rect().contains(q) && image.pixelColor(q) != background) ++differing;
  }
  EXPECT_GT(differing, int(w->skeletonView()->jointPixels().size()) / 2);
}

TEST(StudioExecutable, ScreenshotModeWritesAPngAndFailsCleanly) {
  QTemporaryDir dir;
  const QString clip = dir.filePath("swing.bvh");
  const Clip sample = swing(1.0);
  io::write_bvh(io::from_motion(sample.skeleton, sample.motion), clip.toStdString());
  const QString png = dir.filePath("shot.png");
  QProcess studio;
  QProcessEnvironment env = QProcessEnvironment::systemEnvironment();
  env.insert("XDG_CONFIG_HOME", dir.filePath("config"));  // keep the user's settings untouched
  studio.setProcessEnvironment(env);
  studio.start(MOTIONMAP_STUDIO_EXE,
               {clip, "--method", "pca", "--frame", "60", "--screenshot", png});
  ASSERT_TRUE(studio.waitForFinished(kTimeoutMs));
  EXPECT_EQ(studio.exitCode(), 0) << studio.readAllStandardError().toStdString();
  const QImage image(png);
  ASSERT_FALSE(image.isNull());
  EXPECT_GT(image.width(), 400);

  studio.start(MOTIONMAP_STUDIO_EXE, {dir.filePath("missing.bvh"), "--screenshot", png});
  ASSERT_TRUE(studio.waitForFinished(kTimeoutMs));
  EXPECT_EQ(studio.exitCode(), 1);
  EXPECT_TRUE(studio.readAllStandardError().contains("missing.bvh"));

  studio.start(MOTIONMAP_STUDIO_EXE, {clip, "--method", "tsne", "--screenshot", png});
  ASSERT_TRUE(studio.waitForFinished(kTimeoutMs));
  EXPECT_EQ(studio.exitCode(), 1);
  EXPECT_TRUE(studio.readAllStandardError().contains("unknown method 'tsne'"));

  studio.start(MOTIONMAP_STUDIO_EXE, {clip, "--frame", "1000", "--screenshot", png});
  ASSERT_TRUE(studio.waitForFinished(kTimeoutMs));
  EXPECT_EQ(studio.exitCode(), 1);
  EXPECT_TRUE(studio.readAllStandardError().contains("--frame 1000: the clip has 120 frames"));
}

}  // namespace
}  // namespace motionmap::studio
