// The scripted session, as a user drives MotionMap Studio on a real X server (Xvfb, the
// 3-D view through OpenGL): start on the sample clip; press Space without clicking anywhere and
// see the frame advance; drag off the trajectory and see the body keep its heading; sketch a
// path with the mouse, drag one of its control points, undo, export the take; export a picture
// and an image sequence. Every step goes through the window's own input (keys to the window,
// mouse events to the map view) except where a file name would come from a dialog.
//
// Part of motionmap_gui_gl_tests, run by ctest as `studio_gl_render` under xvfb-run.
#include <gtest/gtest.h>

#include <QDir>
#include <QFileInfo>
#include <QImage>
#include <QTemporaryDir>
#include <QTest>
#include <cmath>

#include "app/main_window.h"
#include "export/animation_export.h"
#include "export/picture_export.h"
#include "map/map_view.h"
#include "motionmap/io/load.h"
#include "motionmap/sample/sample_clip.h"
#include "motionmap/skeleton/skeleton.h"
#include "motionmap/synth/blender.h"
#include "scene/skeleton_view.h"
#include "takes/takes_controller.h"

namespace motionmap::studio {
namespace {

constexpr int kWaitMs = 120000;

double angleBetween(double a, double b) {
  return std::abs(std::remainder(a - b, 2.0 * M_PI));
}

TEST(StudioSession, AScriptedSessionOnTheSampleClip) {
  MainWindow w;
  w.setInteractive(false);
  w.resize(1280, 720);
  w.show();
  // A bare Xvfb has no window manager to activate the window, as a desktop would.
  w.activateWindow();
  ASSERT_TRUE(QTest::qWaitForWindowActive(&w));
  w.setMethod(embed::Method::Isomap);
  w.openClip(sample::make_sample_clip(sample::SampleKind::Swing));
  ASSERT_TRUE(QTest::qWaitFor([&] { return w.currentMap() != nullptr; }, kWaitMs))
      << w.lastError().toStdString();
  ASSERT_TRUE(w.skeletonView()->glReady()) << "no OpenGL context under Xvfb";

  // 1. Space, with no click into a view: playback starts and the frame advances.
  w.setFrame(0);
  QTest::keyClick(w.windowHandle(), Qt::Key_Space);
  EXPECT_TRUE(w.isPlaying());
  EXPECT_TRUE(QTest::qWaitFor([&] { return w.currentFrame() > 10; }, 10000));
  QTest::keyClick(w.windowHandle(), Qt::Key_Space);
  EXPECT_FALSE(w.isPlaying());
  QTest::keyClick(w.windowHandle(), Qt::Key_Home);
  EXPECT_EQ(w.currentFrame(), 0);
  QTest::keyClick(w.windowHandle(), Qt::Key_Right, Qt::ShiftModifier);
  EXPECT_EQ(w.currentFrame(), 10);

  // 2. Drag from the frame shown to the plot's corner, far off the trajectory: the body keeps
  // the heading and floor position it had.
  const MapResult& map = *w.currentMap();
  const Skeleton& skeleton = map.blender->skeleton();
  const int frame = 120;
  w.setFrame(frame);
  const int root = motion_root(skeleton, w.clip()->motion);
  const synth::RootPlacement before = synth::root_placement(w.clip()->motion, frame, root);
  MapView* view = w.mapView();
  const QPointF start = view->toWidget(map.blender->sample_point(map.rowOfFrame[0][frame]));
  const QPointF corner = view->plotRect().topLeft() + QPointF(6, 6);
  QTest::mousePress(view, Qt::LeftButton, Qt::NoModifier, start.toPoint());
  bool clamped = false;
  for (int i = 1; i <= 30; ++i) {
    QTest::mouseMove(view, (start + (corner - start) * (i / 30.0)).toPoint());
    clamped = clamped || view->hoverText().contains("edge");
    const synth::RootPlacement now =
        synth::root_placement(w.skeletonView()->currentPose(), 0, root);
    EXPECT_LT(angleBetween(now.heading, before.heading), 1e-6) << "move " << i;
    EXPECT_NEAR(now.floor.x(), before.floor.x(), 1e-6) << "move " << i;
    EXPECT_NEAR(now.floor.z(), before.floor.z(), 1e-6) << "move " << i;
  }
  QTest::mouseRelease(view, Qt::LeftButton, Qt::NoModifier, corner.toPoint());
  EXPECT_TRUE(clamped) << "the drag never left the data";

  // 3. Sketch with Shift held along the trajectory; a take follows.
  const int from = map.rowOfFrame[0][40], to = map.rowOfFrame[0][200];
  QTest::mousePress(view, Qt::LeftButton, Qt::ShiftModifier,
                    view->toWidget(map.blender->sample_point(from)).toPoint());
  for (int row = from + 8; row <= to; row += 8) {
    QTest::qWait(10);
    QTest::mouseMove(view, view->toWidget(map.blender->sample_point(row)).toPoint());
  }
  QTest::mouseRelease(view, Qt::LeftButton, Qt::ShiftModifier,
                      view->toWidget(map.blender->sample_point(to)).toPoint());
  ASSERT_TRUE(QTest::qWaitFor([&] { return !w.isSynthesizing() && w.takes()->list().count() == 1; },
                              kWaitMs))
      << w.lastError().toStdString();
  w.pause();
  const Take sketched = w.takes()->list().at(0);
  ASSERT_FALSE(view->takePaths().empty());
  const MapView::TakePath& path = view->takePaths().front();
  ASSERT_GE(path.controls.size(), 3u);

  // Drag a middle control point onto a far sample of the trajectory; the take re-synthesizes.
  const int control = int(path.controls.size()) / 2;
  const QPointF grab =
      view->toWidget(path.points[std::size_t(path.controls[std::size_t(control)])]);
  ASSERT_EQ(view->controlPointAt(grab), control);
  const QPointF target = view->toWidget(map.blender->sample_point(map.rowOfFrame[0][300]));
  QTest::mousePress(view, Qt::LeftButton, Qt::NoModifier, grab.toPoint());
  for (int i = 1; i <= 10; ++i) {
    QTest::qWait(10);
    QTest::mouseMove(view, (grab + (target - grab) * (i / 10.0)).toPoint());
  }
  QTest::mouseRelease(view, Qt::LeftButton, Qt::NoModifier, target.toPoint());
  ASSERT_TRUE(QTest::qWaitFor(
      [&] { return !w.isSynthesizing() && w.takes()->list().at(0).result != sketched.result; },
      kWaitMs))
      << w.lastError().toStdString();
  w.pause();

  // Undo (Ctrl+Z to the window): the motion sketched first is back, as it was.
  QTest::keyClick(w.windowHandle(), Qt::Key_Z, Qt::ControlModifier);
  EXPECT_EQ(w.takes()->list().at(0).result, sketched.result);

  // Export the take as BVH and read it back.
  QTemporaryDir dir;
  const QString bvh = dir.filePath("take1.bvh");
  ASSERT_TRUE(w.exportTake(0, bvh)) << w.lastError().toStdString();
  const Clip back = io::load_clip(bvh.toStdString());
  EXPECT_EQ(back.motion.num_frames, sketched.result->motion.num_frames);

  // The window as the session left it (a test artefact, and docs/studio.md's picture of takes).
  w.setFrame(60);
  QTest::qWait(100);
  w.screenshot().save(QString(MOTIONMAP_TEST_ARTIFACT_DIR) + "/studio-session.png");

  // 4. A picture of both views (the GL view drawn, not blank) and an image sequence.
  const QString png = dir.filePath("both.png");
  ASSERT_TRUE(w.exportPicture(png, PictureKind::Both)) << w.lastError().toStdString();
  const QImage picture(png);
  EXPECT_EQ(picture.width(), w.skeletonView()->width() + w.mapView()->width());
  AnimationSettings s;
  s.folder = dir.filePath("frames");
  s.name = "session";
  s.images = true;
  s.video = false;
  s.first = 0;
  s.last = 11;
  ASSERT_TRUE(w.exportAnimation(s)) << w.lastError().toStdString();
  const QStringList frames = QDir(s.folder).entryList({"session_*.png"}, QDir::Files);
  EXPECT_EQ(frames.size(), 12);
  EXPECT_NE(QImage(QDir(s.folder).filePath(frames.front())),
            QImage(QDir(s.folder).filePath(frames.back())));
}

}  // namespace
}  // namespace motionmap::studio
