// Studio's map keeps its place while the user draws on it: the Takes panel does not take room
// from the map when its first take arrives, and a sketch outside the plot stays on its edge.
#include <QLabel>
#include <QSignalSpy>
#include <QTest>
#include <vector>

#include "map/map_view.h"
#include "studio_test_util.h"
#include "takes/takes_panel.h"

namespace motionmap::studio::testing {

TEST(StudioMapPlace, TheFirstTakeLeavesTheMapWhereTheUserIsDrawing) {
  auto w = windowWithMap(embed::Method::Pca);
  const MapResult* map = w->currentMap();
  ASSERT_NE(map, nullptr);
  MapView* view = w->mapView();
  // The panel's room is the map's from the start: it is there before any take.
  QTest::qWait(50);
  EXPECT_TRUE(w->takesPanel()->isVisible());
  EXPECT_TRUE(w->takesPanel()->emptyHint()->isVisible());
  const QRectF plot = view->plotRect();
  const QPoint origin = view->mapTo(w.get(), QPoint(0, 0));
  const QSize size = view->size();
  const Eigen::Vector2d probe = map->blender->sample_point(60);
  const QPointF probePixel = view->toWidget(probe);

  QSignalSpy done(w.get(), &MainWindow::synthesisFinished);
  ASSERT_TRUE(w->synthesizeAlong(pathAlong(*map, 10, 90, 1.0)));
  ASSERT_TRUE(done.wait(kTimeoutMs));
  ASSERT_EQ(w->takes()->list().count(), 1);
  QTest::qWait(100);  // the dock and the window lay themselves out again, if anything changed
  w->pause();

  EXPECT_TRUE(w->takesPanel()->isVisible());
  EXPECT_FALSE(w->takesPanel()->emptyHint()->isVisible());
  EXPECT_EQ(view->plotRect(), plot);
  EXPECT_EQ(view->mapTo(w.get(), QPoint(0, 0)), origin);
  EXPECT_EQ(view->size(), size);
  EXPECT_LT(QLineF(view->toWidget(probe), probePixel).length(), 1e-9);
}

TEST(StudioMapPlace, ASketchLeavingThePlotStaysOnItsEdge) {
  auto w = windowWithMap(embed::Method::Pca);
  const MapResult* map = w->currentMap();
  ASSERT_NE(map, nullptr);
  w->pause();
  MapView* view = w->mapView();
  const QRectF plot = view->plotRect();
  std::vector<synth::MapPath> sketches;
  QObject::connect(view, &MapView::sketchFinished, view,
                   [&](const synth::MapPath& path) { sketches.push_back(path); });
  const QPoint start = plot.center().toPoint();
  QTest::mousePress(view, Qt::LeftButton, Qt::ShiftModifier, start);
  QTest::qWait(10);
  QTest::mouseMove(view, start + QPoint(20, 0));
  QTest::qWait(10);
  // Past the plot's right edge and below its bottom (into the colour bar and notes).
  const QPoint outside(int(plot.right()) + 40, int(plot.bottom()) + 30);
  QTest::mouseMove(view, outside);
  QTest::qWait(10);
  QTest::mouseRelease(view, Qt::LeftButton, Qt::ShiftModifier, outside);
  ASSERT_EQ(sketches.size(), 1u);
  const synth::MapPath& path = sketches.front();
  ASSERT_GE(path.points.size(), 2u);
  const QRectF edge = plot.adjusted(-1e-6, -1e-6, 1e-6, 1e-6);
  for (const Eigen::Vector2d& p : path.points) {
    const QPointF pixel = view->toWidget(p);
    EXPECT_TRUE(edge.contains(pixel)) << pixel.x() << ", " << pixel.y();
  }
  // The last point is the plot's bottom-right corner: clamped, not dropped.
  const QPointF last = view->toWidget(path.points.back());
  EXPECT_NEAR(last.x(), plot.right(), 1e-6);
  EXPECT_NEAR(last.y(), plot.bottom(), 1e-6);
  ASSERT_TRUE(QTest::qWaitFor([&] { return !w->isSynthesizing(); }, kTimeoutMs));
  w->pause();
}

}  // namespace motionmap::studio::testing
