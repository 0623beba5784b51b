// Zoom and pan on the map (MapView): the wheel zooms around the cursor, a middle drag or Space+drag
// pans, a double-click, Home (map focused) or View → Whole map resets; every gesture (click,
// sketch, Ctrl-click keys, hover) maps the mouse through the zoomed view, and a saved map's
// density image is binned again at the zoomed view so it stays sharp.
#include <QApplication>
#include <QCursor>
#include <QDir>
#include <QImage>
#include <QSignalSpy>
#include <QTest>
#include <QWheelEvent>
#include <random>

#include "map/map_view.h"
#include "scene/skeleton_view.h"
#include "studio_test_util.h"

namespace motionmap::studio {
namespace {

using testing::kTimeoutMs;
using testing::windowWithMap;

void wheel(QWidget* view, QPointF at, int delta) {
  QWheelEvent event(at, view->mapToGlobal(at), QPoint(), QPoint(0, delta), Qt::NoButton,
                    Qt::NoModifier, Qt::NoScrollPhase, false);
  QApplication::sendEvent(view, &event);
}

double pixels(const MapView* view, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return QLineF(view->toWidget(a), view->toWidget(b)).length();
}

TEST(StudioZoom, TheWheelZoomsAroundTheCursorAndTheConversionsFollow) {
  auto w = windowWithMap(embed::Method::Pca);
  const MapResult* map = w->currentMap();
  ASSERT_NE(map, nullptr);
  w->pause();
  MapView* view = w->mapView();
  QSignalSpy changes(view, &MapView::viewChanged);
  const Eigen::Vector2d a = map->blender->sample_point(60), b = map->blender->sample_point(61);
  const double before = pixels(view, a, b);
  const QPointF at = view->toWidget(a);
  wheel(view, at, 120 * 4);  // four notches: 1.25⁴
  EXPECT_TRUE(view->isZoomed());
  EXPECT_NEAR(view->zoom(), std::pow(1.25, 4), 1e-9);
  EXPECT_EQ(changes.count(), 1);
  // The point under the cursor stays there; distances grow by the zoom.
  EXPECT_LT(QLineF(view->toWidget(a), at).length(), 1e-6);
  EXPECT_NEAR(pixels(view, a, b), before * view->zoom(), 1e-6 * before * view->zoom());
  // toMap inverts toWidget in the zoomed view.
  for (const QPointF p : {QPointF(100, 120), QPointF(333, 250), at}) {
    EXPECT_LT(QLineF(view->toWidget(view->toMap(p)), p).length(), 1e-6);
  }
  // What leaves the view is clipped to the plot's frame: nothing left of it.
  const QImage shot = view->grab().toImage();
  const QRect frame = view->plotRect().toRect();
  for (int y = frame.top(); y <= frame.bottom(); y += 3)
    EXPECT_EQ(shot.pixelColor(frame.left() - 4, y), QColor(Qt::white)) << y;
  // The extent shown shrank by the zoom, around a.
  const QRectF extent = view->viewExtent();
  view->resetView();
  EXPECT_FALSE(view->isZoomed());
  EXPECT_NEAR(view->viewExtent().width() / extent.width(), std::pow(1.25, 4), 1e-9);
  EXPECT_NEAR(pixels(view, a, b), before, 1e-9);
  // Zooming out never goes past the whole map.
  wheel(view, at, -120 * 3);
  EXPECT_DOUBLE_EQ(view->zoom(), 1.0);
}

TEST(StudioZoom, ASketchDrawnWhileZoomedLandsAtTheRightMapPoints) {
  auto w = windowWithMap(embed::Method::Pca);
  const MapResult* map = w->currentMap();
  ASSERT_NE(map, nullptr);
  w->pause();
  MapView* view = w->mapView();
  view->zoomAt(view->toWidget(map->blender->sample_point(80)), 6.0);
  view->panBy(QPointF(-20, 15));
  QSignalSpy sketches(view, &MapView::sketchFinished);
  // The samples near 80 that lie in the zoomed plot: the sketch passes their pixels.
  std::vector<Eigen::Vector2d> targets;
  for (int row = 60; row <= 100; row += 2) {
    const Eigen::Vector2d p = map->blender->sample_point(row);
    if (view->plotRect().adjusted(5, 5, -5, -5).contains(view->toWidget(p))) targets.push_back(p);
  }
  ASSERT_GE(targets.size(), 3u);
  QTest::mousePress(view, Qt::LeftButton, Qt::ShiftModifier,
                    view->toWidget(targets.front()).toPoint());
  for (std::size_t i = 1; i < targets.size(); ++i) {
    QTest::qWait(5);
    QTest::mouseMove(view, view->toWidget(targets[i]).toPoint());
  }
  QTest::mouseRelease(view, Qt::LeftButton, Qt::ShiftModifier,
                      view->toWidget(targets.back()).toPoint());
  ASSERT_EQ(sketches.count(), 1);
  const auto path = sketches.at(0).at(0).value<synth::MapPath>();
  ASSERT_GE(path.points.size(), 2u);
  // A pixel of rounding in the zoomed view is a sixth of a pixel of the whole map.
  const double pixel = view->viewExtent().width() / view->plotRect().width();
  EXPECT_LT((path.points.front() - targets.front()).norm(), 1.5 * pixel);
  EXPECT_LT((path.points.back() - targets.back()).norm(), 1.5 * pixel);
  ASSERT_TRUE(QTest::qWaitFor([&] { return !w->isSynthesizing(); }, kTimeoutMs));
  w->pause();
}

TEST(StudioZoom, ClicksKeysAndHoverGoThroughThePannedView) {
  auto w = windowWithMap(embed::Method::Pca);
  const MapResult* map = w->currentMap();
  ASSERT_NE(map, nullptr);
  w->pause();
  MapView* view = w->mapView();
  const Eigen::Vector2d target = map->blender->sample_point(150);
  view->zoomAt(view->toWidget(target), 4.0);
  // A middle drag pans: the map follows the mouse.
  const QPointF before = view->toWidget(target);
  QTest::mousePress(view, Qt::MiddleButton, Qt::NoModifier, QPoint(200, 200));
  QTest::mouseMove(view, QPoint(230, 220));
  QTest::mouseRelease(view, Qt::MiddleButton, Qt::NoModifier, QPoint(230, 220));
  EXPECT_LT(QLineF(view->toWidget(target), before + QPointF(30, 20)).length(), 1e-6);
  ASSERT_TRUE(view->plotRect().contains(view->toWidget(target)));
  // A click on the sample's pixel jumps to its frame.
  w->setFrame(0);
  QTest::mouseClick(view, Qt::LeftButton, Qt::NoModifier, view->toWidget(target).toPoint());
  EXPECT_EQ(w->currentFrame(), 150);
  // Hover names it.
  QTest::mouseMove(view, view->toWidget(target).toPoint() + QPoint(1, 0));
  EXPECT_TRUE(view->hoverText().contains("150")) << view->hoverText().toStdString();
  // A Ctrl-click reports the map point under the mouse.
  QSignalSpy keys(view, &MapView::keyClicked);
  const QPoint keyPixel = view->toWidget(target).toPoint() + QPoint(40, -25);
  QTest::mouseClick(view, Qt::LeftButton, Qt::ControlModifier, keyPixel);
  ASSERT_EQ(keys.count(), 1);
  const Eigen::Vector2d keyPoint = keys.at(0).at(0).value<Eigen::Vector2d>();
  EXPECT_LT((keyPoint - view->toMap(QPointF(keyPixel))).norm(), 1e-9);
  EXPECT_LT(QLineF(view->toWidget(keyPoint), QPointF(keyPixel)).length(), 1e-6);
  ASSERT_TRUE(QTest::qWaitFor([&] { return !w->isSynthesizing(); }, kTimeoutMs));
}

TEST(StudioZoom, DoubleClickHomeAndTheMenuShowTheWholeMapAgain) {
  auto w = windowWithMap(embed::Method::Pca);
  ASSERT_NE(w->currentMap(), nullptr);
  w->pause();
  MapView* view = w->mapView();
  const QPoint centre = view->plotRect().center().toPoint();
  view->zoomAt(centre, 3.0);
  QTest::mouseDClick(view, Qt::LeftButton, Qt::NoModifier, centre);
  EXPECT_FALSE(view->isZoomed());
  // Home with the map focused resets the view, and leaves the frame alone.
  view->zoomAt(centre, 3.0);
  w->setFrame(40);
  view->setFocus();
  QTest::keyClick(view, Qt::Key_Home);
  EXPECT_FALSE(view->isZoomed());
  EXPECT_EQ(w->currentFrame(), 40);
  // Not zoomed, Home is the timeline's (first frame) again.
  QTest::keyClick(view, Qt::Key_Home);
  EXPECT_EQ(w->currentFrame(), 0);
  // View → Whole map (Ctrl+0).
  view->zoomAt(centre, 3.0);
  QAction* whole = nullptr;
  for (QAction* a : w->findChildren<QAction*>())
    if (a->shortcut() == QKeySequence(Qt::CTRL | Qt::Key_0)) whole = a;
  ASSERT_NE(whole, nullptr);
  whole->trigger();
  EXPECT_FALSE(view->isZoomed());
}

TEST(StudioZoom, SpaceDragPansAndASpaceTapStillPlays) {
  auto w = windowWithMap(embed::Method::Pca);
  const MapResult* map = w->currentMap();
  ASSERT_NE(map, nullptr);
  w->pause();
  w->activateWindow();
  ASSERT_TRUE(QTest::qWaitForWindowActive(w.get()));
  MapView* view = w->mapView();
  const QPoint over = view->plotRect().center().toPoint();
  QCursor::setPos(view->mapToGlobal(over));
  const Eigen::Vector2d target = map->blender->sample_point(100);
  const QPointF before = view->toWidget(target);
  QTest::keyPress(w.get(), Qt::Key_Space);
  EXPECT_FALSE(w->isPlaying());  // held back while Space is down
  QTest::mousePress(view, Qt::LeftButton, Qt::NoModifier, over);
  QTest::mouseMove(view, over + QPoint(-25, 40));
  QTest::mouseRelease(view, Qt::LeftButton, Qt::NoModifier, over + QPoint(-25, 40));
  QTest::keyRelease(w.get(), Qt::Key_Space);
  EXPECT_LT(QLineF(view->toWidget(target), before + QPointF(-25, 40)).length(), 1e-6);
  EXPECT_FALSE(w->isPlaying());  // a pan is no play
  // Space alone plays and pauses as before.
  QTest::keyClick(w.get(), Qt::Key_Space);
  EXPECT_TRUE(w->isPlaying());
  QTest::keyClick(w.get(), Qt::Key_Space);
  EXPECT_FALSE(w->isPlaying());
  // With the mouse away from the map, Space is the window's shortcut as always.
  QCursor::setPos(w->skeletonView()->mapToGlobal(QPoint(20, 20)));
  QTest::keyClick(w.get(), Qt::Key_Space);
  EXPECT_TRUE(w->isPlaying());
  w->pause();
}

/// Clustered points: a library's map in miniature.
std::shared_ptr<Eigen::MatrixXd> clusters(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  auto xy = std::make_shared<Eigen::MatrixXd>(n, 2);
  for (int i = 0; i < n; ++i) {
    const int c = i % 7;
    const double cx = std::cos(c * 0.9) * 3, cy = std::sin(c * 1.7) * 2;
    (*xy)(i, 0) = cx + 0.3 * normal(rng);
    (*xy)(i, 1) = cy + 0.2 * normal(rng) + 0.1 * (*xy)(i, 0);
  }
  return xy;
}

int inkedPixels(const QImage& image, const QRect& area) {
  int inked = 0;
  for (int y = area.top(); y <= area.bottom(); ++y)
    for (int x = area.left(); x <= area.right(); ++x) inked += qAlpha(image.pixel(x, y)) > 0;
  return inked;
}

TEST(StudioZoom, TheDensityImageIsBinnedAgainAtTheZoomedViewAndStaysSharp) {
  MapView view;
  view.resize(600, 600);
  const auto points = clusters(200000, 3);
  const Eigen::MatrixXd trajectory = points->topRows(300);
  view.setDensityMap(points, trajectory, {});
  const QRect plot = view.plotRect().toRect().adjusted(2, 2, -2, -2);
  const int inkedWhole = inkedPixels(view.densityImage(), plot);
  // Zoom far into the middle of one cluster: the image is binned at the zoomed transform, so the
  // cluster fills the plot with single points, not a few blown-up pixels or nothing.
  const Eigen::Vector2d cluster(std::cos(0.0) * 3, 0.3);
  view.zoomAt(view.toWidget(cluster), 12.0);
  const QImage zoomed = view.densityImage();
  const int inkedZoomed = inkedPixels(zoomed, plot);
  std::printf("inked pixels in the plot: %d whole, %d zoomed ×12\n", inkedWhole, inkedZoomed);
  EXPECT_GT(inkedZoomed, plot.width() * plot.height() / 20);
  // Every point inside the view is inked where toWidget puts it.
  int checked = 0;
  for (Eigen::Index i = 0; i < points->rows() && checked < 200; ++i) {
    const QPointF p = view.toWidget(points->row(i).transpose());
    if (!QRectF(plot).contains(p)) continue;
    EXPECT_GT(qAlpha(zoomed.pixel(int(p.x()), int(p.y()))), 0) << "point " << i;
    ++checked;
  }
  EXPECT_EQ(checked, 200);
  // Nothing is drawn outside the plot's frame (title, legend, notes stay clear).
  const QImage shown = view.grab().toImage();
  const QString dir = QDir::temp().filePath("motionmap-studio-zoom");
  QDir().mkpath(dir);
  shown.save(dir + "/density-zoomed.png");
  const QRect frame = view.plotRect().toRect();
  const QColor outside = shown.pixelColor(frame.left() - 3, frame.center().y());
  EXPECT_EQ(outside, QColor(Qt::white));
  // The magnifier shows the density under it (binned again at its magnification), not a blank
  // disc: about as many inked pixels in the lens as without it.
  auto inkedIn = [](const QImage& image, QPointF centre, double radius) {
    int inked = 0;
    for (int y = int(centre.y() - radius); y <= int(centre.y() + radius); ++y)
      for (int x = int(centre.x() - radius); x <= int(centre.x() + radius); ++x)
        if (QLineF(centre, QPointF(x, y)).length() < radius - 3 &&
            image.pixelColor(x, y).lightness() < 200)
          ++inked;
    return inked;
  };
  const QPointF centre = view.plotRect().center();
  const int plain = inkedIn(shown, centre, 60);
  view.setLensEnabled(true);
  view.setLensCenter(centre);
  const QImage lensed = view.grab().toImage();
  lensed.save(dir + "/density-lens.png");
  const int magnified = inkedIn(lensed, centre, 0.9 * view.lensRadius());
  std::printf("inked pixels near the centre: %d plain, %d under the lens\n", plain, magnified);
  EXPECT_GT(magnified, plain / 4);
}

}  // namespace
}  // namespace motionmap::studio
