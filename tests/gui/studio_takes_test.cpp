// Sketch takes and undo/redo (offscreen): a sketch becomes a take whose path stays drawn, its
// control points drag and re-synthesize its motion, the takes are renamed, deleted and exported
// from their list, every step — and method and parameter changes — undoes and redoes, and no
// unexported take is lost without asking.
#include <gtest/gtest.h>

#include <QAbstractButton>
#include <QAction>
#include <QApplication>
#include <QFileInfo>
#include <QImage>
#include <QListView>
#include <QMenuBar>
#include <QMessageBox>
#include <QTemporaryDir>
#include <QTest>
#include <QTimer>
#include <QUndoStack>
#include <cmath>
#include <cstring>
#include <limits>

#include "app/file_menu.h"
#include "app/main_window.h"
#include "export/export_names.h"
#include "map/map_view.h"
#include "motionmap/io/bvh.h"
#include "motionmap/io/load.h"
#include "motionmap/sample/sample_clip.h"
#include "studio_test_util.h"
#include "takes/takes_controller.h"
#include "takes/takes_panel.h"

namespace motionmap::studio {
namespace {

using testing::kTimeoutMs;
using testing::pathAlong;
using testing::windowWithMap;

/// Sketches along the trajectory rows from..to with the mouse (sketch mode), as a user would.
void sketchWithMouse(MapView* view, const MapResult& map, int from, int to, int step) {
  view->setSketchMode(true);
  QTest::mousePress(view, Qt::LeftButton, Qt::NoModifier,
                    view->toWidget(map.blender->sample_point(from)).toPoint());
  for (int row = from + step; row <= to; row += step) {
    QTest::qWait(10);
    QTest::mouseMove(view, view->toWidget(map.blender->sample_point(row)).toPoint());
  }
  QTest::qWait(10);
  QTest::mouseRelease(view, Qt::LeftButton, Qt::NoModifier,
                      view->toWidget(map.blender->sample_point(to)).toPoint());
  view->setSketchMode(false);
}

/// Synthesizes along rows from..to (seconds long) and waits for the take.
void sketch(MainWindow& w, int from, int to, double seconds) {
  const int before = w.takes()->list().count();
  ASSERT_TRUE(w.synthesizeAlong(pathAlong(*w.currentMap(), from, to, seconds)));
  ASSERT_TRUE(QTest::qWaitFor([&] { return !w.isSynthesizing(); }, kTimeoutMs));
  ASSERT_EQ(w.takes()->list().count(), before + 1) << w.lastError().toStdString();
  w.pause();
}

/// Whether `image` has a pixel of the take colour within `radius` pixels of `at`.
bool takeColourNear(const QImage& image, QPointF at, int radius = 2) {
  const QColor want = MapView::takeColor();
  const QPoint c = at.toPoint();
  for (int dy = -radius; dy <= radius; ++dy) {
    for (int dx = -radius; dx <= radius; ++dx) {
      const QPoint p = c + QPoint(dx, dy);
      if (!image.rect().contains(p)) continue;
      const QColor got = image.pixelColor(p);
      if (std::abs(got.red() - want.red()) < 30 && std::abs(got.green() - want.green()) < 40 &&
          std::abs(got.blue() - want.blue()) < 40)
        return true;
    }
  }
  return false;
}

/// The fewest pixels between `pixel` and a frame's map point of `result`.
double closestPixels(const MapView& view, const synth::SynthResult& result, QPointF pixel) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& v : result.validity)
    best = std::min(best, QLineF(view.toWidget(v.point), pixel).length());
  return best;
}

/// Whether two motions have the same frames (rotations within 1e-9).
bool sameMotion(const Motion& a, const Motion& b) {
  if (a.num_frames != b.num_frames || a.rotations.size() != b.rotations.size()) return false;
  for (std::size_t i = 0; i < a.rotations.size(); ++i)
    if (!a.rotations[i].isApprox(b.rotations[i], 1e-9)) return false;
  return true;
}

QAction* editAction(MainWindow& w, const QString& prefix) {
  for (QAction* menu : w.menuBar()->actions()) {
    if (menu->text() != "&Edit") continue;
    for (QAction* a : menu->menu()->actions())
      if (a->text().startsWith(prefix)) return a;
  }
  return nullptr;
}

TEST(StudioTakes, ControlPointsSimplifyTheSketchAndEditsMoveOnlyTheirStretch) {
  synth::MapPath line;
  for (int i = 0; i <= 100; ++i) {
    // A right angle at i = 50: the simplification keeps both ends and the corner.
    line.points.emplace_back(i <= 50 ? i : 50, i <= 50 ? 0 : i - 50);
    line.times.push_back(i * 0.01);
  }
  const std::vector<int> controls = controlPoints(line);
  EXPECT_EQ(controls, (std::vector<int>{0, 50, 100}));
  const synth::MapPath moved = deformPath(line, controls, 1, Eigen::Vector2d(60, -10));
  EXPECT_EQ(moved.points[50], Eigen::Vector2d(60, -10));
  EXPECT_EQ(moved.points[0], line.points[0]);  // the neighbouring control points stay
  EXPECT_EQ(moved.points[100], line.points[100]);
  EXPECT_TRUE(moved.points[25].isApprox(line.points[25] + 0.5 * Eigen::Vector2d(10, -10)));
  EXPECT_EQ(moved.times, line.times);
  // A long wiggly sketch gets at most kMaxControlPoints.
  synth::MapPath wiggle;
  for (int i = 0; i < 2000; ++i) wiggle.points.emplace_back(i, (i % 7) * 40.0);
  const auto many = controlPoints(wiggle);
  EXPECT_LE(int(many.size()), kMaxControlPoints);
  EXPECT_GE(many.size(), 2u);
  EXPECT_EQ(many.front(), 0);
  EXPECT_EQ(many.back(), 1999);
}

TEST(StudioTakes, ASketchBecomesATakeWhosePathStaysDrawn) {
  auto w = windowWithMap();
  const MapResult* map = w->currentMap();
  ASSERT_NE(map, nullptr);
  MapView* view = w->mapView();
  sketchWithMouse(view, *map, 20, 200, 10);
  ASSERT_TRUE(w->isSynthesizing());
  ASSERT_TRUE(QTest::qWaitFor([&] { return !w->isSynthesizing(); }, kTimeoutMs));
  w->pause();
  const TakeList& takes = w->takes()->list();
  ASSERT_EQ(takes.count(), 1) << w->lastError().toStdString();
  EXPECT_EQ(takes.at(0).name, "Take 1");
  EXPECT_EQ(takes.current(), 0);
  EXPECT_EQ(w->synthesized(), takes.at(0).result.get());
  EXPECT_EQ(w->playingMotion(), &takes.at(0).result->motion);
  EXPECT_TRUE(w->takesPanel()->isVisible());
  // After the release the sketch is gone, and the take's path is drawn with its control points.
  EXPECT_TRUE(view->sketch().points.empty());
  ASSERT_EQ(view->takePaths().size(), 1u);
  const MapView::TakePath& drawn = view->takePaths().front();
  EXPECT_TRUE(drawn.current);
  EXPECT_EQ(drawn.points, takes.at(0).path.points);
  EXPECT_GE(drawn.controls.size(), 2u);
  EXPECT_LE(int(drawn.controls.size()), kMaxControlPoints);
  const QImage image = view->grab().toImage();
  // Path-coloured pixels along the path (between two control points) and on each control point's
  // square outline.
  const auto& points = drawn.points;
  // (Midpoints of its segments, except under a control point's square or the frame pointer.)
  int onPath = 0, looked = 0;
  for (std::size_t i = 1; i < points.size(); ++i) {
    const QPointF m = (view->toWidget(points[i - 1]) + view->toWidget(points[i])) / 2;
    bool covered = view->pointer() && QLineF(view->toWidget(*view->pointer()), m).length() < 10;
    for (const int c : drawn.controls)
      covered = covered || QLineF(view->toWidget(points[std::size_t(c)]), m).length() < 8;
    if (covered) continue;
    ++looked;
    onPath += takeColourNear(image, m) ? 1 : 0;
  }
  EXPECT_GE(looked, 5);
  EXPECT_EQ(onPath, looked);
  const QPointF firstControl = view->toWidget(points[std::size_t(drawn.controls.front())]);
  EXPECT_EQ(image.pixelColor(firstControl.toPoint()), QColor(Qt::white));  // the square's inside
  // A second sketch is another take: the first stays, and both are drawn.
  sketch(*w, 100, 180, 1.0);
  EXPECT_EQ(takes.count(), 2);
  EXPECT_EQ(takes.current(), 1);
  ASSERT_EQ(view->takePaths().size(), 2u);
  EXPECT_FALSE(view->takePaths()[0].current);
  EXPECT_TRUE(view->takePaths()[0].controls.empty());  // only the current take's are shown
}

TEST(StudioTakes, DraggingAControlPointResynthesizesAndUndoRedoAreInstant) {
  auto w = windowWithMap();
  w->activateWindow();
  ASSERT_TRUE(QTest::qWaitForWindowActive(w.get()));
  const MapResult* map = w->currentMap();
  ASSERT_NE(map, nullptr);
  sketch(*w, 20, 120, 1.5);
  const TakeList& takes = w->takes()->list();
  const Take before = takes.at(0);
  MapView* view = w->mapView();
  ASSERT_GE(before.controls.size(), 3u);
  const int control = int(before.controls.size()) / 2;
  const QPointF from = view->toWidget(before.path.points[std::size_t(before.controls[control])]);
  // Drag it onto another stretch of the trajectory (inside the data, far from the path).
  QPointF to;
  for (int row = 150; row < 240; row += 5) {
    to = view->toWidget(map->blender->sample_point(row));
    if (closestPixels(*view, *before.result, to) > 40) break;
  }
  ASSERT_GT(closestPixels(*view, *before.result, to), 40);
  ASSERT_EQ(view->controlPointAt(from), control);
  QTest::mousePress(view, Qt::LeftButton, Qt::NoModifier, from.toPoint());
  QTest::mouseMove(view, ((from + to) / 2).toPoint());
  EXPECT_EQ(view->draggedControlPoint(), control);
  QTest::mouseMove(view, to.toPoint());
  QTest::mouseRelease(view, Qt::LeftButton, Qt::NoModifier, to.toPoint());
  EXPECT_TRUE(w->isSynthesizing());
  EXPECT_EQ(w->takes()->pendingTake(), before.id);
  // While it is synthesized the map shows the new path; the take keeps its motion.
  EXPECT_LT(
      QLineF(view->toWidget(view->takePaths()[0].points[std::size_t(before.controls[control])]), to)
          .length(),
      2.0);
  EXPECT_EQ(takes.at(0).result, before.result);
  ASSERT_TRUE(QTest::qWaitFor([&] { return !w->isSynthesizing(); }, kTimeoutMs));
  w->pause();
  const Take edited = takes.at(0);
  EXPECT_EQ(edited.name, before.name);
  EXPECT_EQ(edited.id, before.id);
  ASSERT_NE(edited.result, before.result);
  EXPECT_FALSE(sameMotion(edited.result->motion, before.result->motion));
  // The new motion passes through the moved point (within a pixel or two).
  EXPECT_LT(closestPixels(*view, *edited.result, to), 3.0);
  EXPECT_EQ(w->synthesized(), edited.result.get());
  EXPECT_EQ(w->takes()->undoStack().count(), 2);  // the sketch, the edit

  // Undo (Ctrl+Z): the previous path and motion at once, no synthesis.
  QAction* undo = editAction(*w, "&Undo");
  ASSERT_NE(undo, nullptr);
  EXPECT_EQ(undo->text(), "&Undo edit Take 1");
  QTest::keyClick(w.get(), Qt::Key_Z, Qt::ControlModifier);
  EXPECT_FALSE(w->isSynthesizing());
  EXPECT_EQ(takes.at(0).result, before.result);
  EXPECT_EQ(takes.at(0).path.points, before.path.points);
  EXPECT_EQ(w->synthesized(), before.result.get());
  EXPECT_EQ(view->takePaths()[0].points, before.path.points);
  // Redo (Ctrl+Shift+Z, and Ctrl+Y after another undo): edited again.
  QTest::keyClick(w.get(), Qt::Key_Z, Qt::ControlModifier | Qt::ShiftModifier);
  EXPECT_EQ(takes.at(0).result, edited.result);
  EXPECT_EQ(takes.at(0).path.points, edited.path.points);
  w->takes()->undo();
  EXPECT_EQ(takes.at(0).result, before.result);
  QTest::keyClick(w.get(), Qt::Key_Y, Qt::ControlModifier);
  EXPECT_EQ(takes.at(0).result, edited.result);
  w->pause();
}

TEST(StudioTakes, ADraggedControlPointRemakesOnlyItsStretch) {
  auto w = windowWithMap();
  sketch(*w, 10, 230, 6.0);
  const Take before = w->takes()->list().at(0);
  ASSERT_GE(before.controls.size(), 5u);
  const int control = int(before.controls.size()) / 2;
  const Eigen::Vector2d at = before.path.points[std::size_t(before.controls[std::size_t(control)])];
  // A small move, towards a neighbouring sample of the trajectory.
  const Eigen::Vector2d to = at + 0.5 * (w->currentMap()->blender->sample_point(120) - at);
  ASSERT_TRUE(w->moveControlPoint(control, to));
  ASSERT_TRUE(QTest::qWaitFor([&] { return !w->isSynthesizing(); }, kTimeoutMs));
  w->pause();
  const Take edited = w->takes()->list().at(0);
  ASSERT_NE(edited.result, before.result);
  ASSERT_TRUE(w->takes()->lastEditWindow().has_value());
  const auto [first, end] = *w->takes()->lastEditWindow();
  const Motion& m = edited.result->motion;
  const Motion& b = before.result->motion;
  ASSERT_EQ(m.num_frames, b.num_frames);
  EXPECT_GT(first, 0);
  EXPECT_LT(end, m.num_frames);
  EXPECT_FALSE(sameMotion(m, b));
  // The frames before and after the window: the take's motion before the edit, bit for bit.
  const std::size_t J = std::size_t(m.num_joints);
  for (int f = 0; f < m.num_frames; ++f) {
    if (f >= first && f < end) continue;
    const std::size_t i = std::size_t(f) * J;
    ASSERT_EQ(std::memcmp(&m.rotations[i], &b.rotations[i], J * sizeof(Eigen::Quaterniond)), 0)
        << "frame " << f;
    ASSERT_EQ(std::memcmp(&m.translations[i], &b.translations[i], J * sizeof(Eigen::Vector3d)), 0)
        << "frame " << f;
  }
  // One undo step, which brings the motion before back.
  EXPECT_EQ(w->takes()->undoStack().count(), 2);
  w->takes()->undo();
  EXPECT_EQ(w->takes()->list().at(0).result, before.result);
  // Other motion options: the whole take is re-made.
  w->takes()->redo();
  SynthParameters other;
  other.motion.smooth = 0.0;  // the default smooths
  ASSERT_TRUE(w->takes()->editControlPoint(control, at, other));
  ASSERT_TRUE(QTest::qWaitFor([&] { return w->takes()->pendingTake() < 0; }, kTimeoutMs));
  EXPECT_FALSE(w->takes()->lastEditWindow().has_value());
  w->pause();
}

TEST(StudioTakes, ACancelledEditLeavesTheTakeAsItWas) {
  auto w = windowWithMap();
  sketch(*w, 20, 120, 1.5);
  const Take before = w->takes()->list().at(0);
  ASSERT_TRUE(w->moveControlPoint(1, w->currentMap()->blender->sample_point(200)));
  EXPECT_EQ(w->takes()->pendingTake(), before.id);
  w->cancelSynthesis();
  EXPECT_EQ(w->takes()->pendingTake(), -1);
  QTest::qWait(50);
  EXPECT_EQ(w->takes()->list().at(0).result, before.result);
  EXPECT_EQ(w->mapView()->takePaths()[0].points, before.path.points);
  EXPECT_EQ(w->takes()->undoStack().count(), 1);
  // Out of range: nothing starts.
  EXPECT_FALSE(w->moveControlPoint(int(before.controls.size()), Eigen::Vector2d(0, 0)));
  w->pause();
}

TEST(StudioTakes, RenameAndDeleteFromTheListUndo) {
  auto w = windowWithMap();
  sketch(*w, 20, 80, 1.0);
  sketch(*w, 100, 180, 1.0);
  TakeList& takes = w->takes()->list();
  const auto first = takes.at(0).result;
  // Renaming by editing the list entry: one undoable step.
  ASSERT_TRUE(takes.setData(takes.index(0), "  swing up ", Qt::EditRole));
  EXPECT_EQ(takes.at(0).name, "swing up");
  EXPECT_EQ(takes.data(takes.index(0), Qt::EditRole).toString(), "swing up");
  EXPECT_FALSE(takes.setData(takes.index(0), "   ", Qt::EditRole));  // empty: refused
  EXPECT_EQ(editAction(*w, "&Undo")->text(), "&Undo rename Take 1 to swing up");
  w->takes()->undo();
  EXPECT_EQ(takes.at(0).name, "Take 1");
  w->takes()->redo();
  EXPECT_EQ(takes.at(0).name, "swing up");

  // Delete, with the list focused: the take goes, and comes back where it was on undo.
  QListView* list = w->takesPanel()->listView();
  w->activateWindow();
  ASSERT_TRUE(QTest::qWaitForWindowActive(w.get()));
  list->setFocus();
  list->setCurrentIndex(takes.index(0));
  EXPECT_EQ(takes.current(), 0);  // selecting plays it
  EXPECT_EQ(w->synthesized(), first.get());
  QTest::keyClick(list, Qt::Key_Delete);
  ASSERT_EQ(takes.count(), 1);
  EXPECT_EQ(takes.at(0).name, "Take 2");
  EXPECT_EQ(takes.current(), -1);
  EXPECT_EQ(w->synthesized(), nullptr);
  EXPECT_EQ(w->playingMotion(), &w->clip()->motion);  // its take gone, the clip plays
  ASSERT_EQ(w->mapView()->takePaths().size(), 1u);
  w->takes()->undo();
  ASSERT_EQ(takes.count(), 2);
  EXPECT_EQ(takes.at(0).name, "swing up");
  EXPECT_EQ(takes.at(0).result, first);
  EXPECT_EQ(takes.current(), 0);
  w->takes()->redo();
  EXPECT_EQ(takes.count(), 1);
  // Undoing the sketch itself removes its take.
  w->takes()->undo();  // the delete
  w->takes()->undo();  // the rename
  w->takes()->undo();  // the second sketch
  EXPECT_EQ(takes.count(), 1);
  EXPECT_EQ(takes.at(0).name, "Take 1");
  w->pause();
}

TEST(StudioTakes, MethodAndParameterChangesUndoFromTheCache) {
  auto w = windowWithMap(embed::Method::Isomap);
  const MapResult* isomap = w->currentMap();
  ASSERT_NE(isomap, nullptr);
  sketch(*w, 20, 80, 1.0);
  w->setMethod(embed::Method::Pca);
  ASSERT_TRUE(QTest::qWaitFor([&] { return !w->isComputing(); }, kTimeoutMs));
  const MapResult* pca = w->currentMap();
  ASSERT_NE(pca, nullptr);
  // The take belongs to the Isomap map: not drawn on PCA's.
  EXPECT_TRUE(w->mapView()->takePaths().empty());
  EXPECT_EQ(editAction(*w, "&Undo")->text(), "&Undo method PCA");
  w->takes()->undo();
  EXPECT_EQ(w->method(), embed::Method::Isomap);
  EXPECT_FALSE(w->isComputing());
  EXPECT_EQ(w->currentMap(), isomap);  // at once, from the cache
  EXPECT_EQ(w->mapView()->takePaths().size(), 1u);
  w->takes()->redo();
  EXPECT_EQ(w->method(), embed::Method::Pca);
  EXPECT_EQ(w->currentMap(), pca);

  MapParameters p = w->parameters();
  const MapParameters old = p;
  p.k = old.k + 5;
  w->setParameters(p);
  ASSERT_TRUE(QTest::qWaitFor([&] { return !w->isComputing(); }, kTimeoutMs));
  EXPECT_EQ(w->parameters().k, old.k + 5);
  w->takes()->undo();
  EXPECT_EQ(w->parameters(), old);
  EXPECT_EQ(w->currentMap(), pca);
  w->takes()->redo();
  EXPECT_EQ(w->parameters().k, old.k + 5);

  SynthParameters s = w->synthParameters();
  const double fps = s.motion.fps;
  s.motion.fps = 30.0;
  ASSERT_TRUE(w->setSynthParameters(s));
  const int steps = w->takes()->undoStack().count();
  ASSERT_TRUE(w->setSynthParameters(s));  // unchanged: no step
  EXPECT_EQ(w->takes()->undoStack().count(), steps);
  EXPECT_EQ(editAction(*w, "&Undo")->text(), "&Undo synthesis parameters");
  w->takes()->undo();
  EXPECT_EQ(w->synthParameters().motion.fps, fps);
  w->takes()->redo();
  EXPECT_EQ(w->synthParameters().motion.fps, 30.0);
  w->pause();
}

TEST(StudioTakes, AMapThatFailsOrIsCancelledLeavesNoUndoStep) {
  auto w = windowWithMap(embed::Method::Isomap);
  const int steps = w->takes()->undoStack().count();
  // Refused parameters: the map and parameters before stay, and nothing is there to undo.
  MapParameters bad = w->parameters();
  bad.exclude = "Left(Arm";
  w->setParameters(bad);
  ASSERT_TRUE(QTest::qWaitFor([&] { return !w->isComputing(); }, kTimeoutMs));
  EXPECT_NE(w->parameters().exclude, bad.exclude);
  EXPECT_EQ(w->takes()->undoStack().count(), steps);
  // A method change cancelled while its map is computed: the same.
  w->setMethod(embed::Method::Lle);
  ASSERT_TRUE(w->isComputing());
  w->cancelComputation();
  EXPECT_EQ(w->method(), embed::Method::Isomap);
  EXPECT_EQ(w->takes()->undoStack().count(), steps);
  // Two changes while the first map computes make one step, from the map shown to the last.
  w->setMethod(embed::Method::Lle);
  w->setMethod(embed::Method::Mds);
  ASSERT_TRUE(QTest::qWaitFor([&] { return w->currentMap() && !w->isComputing(); }, kTimeoutMs));
  EXPECT_EQ(w->takes()->undoStack().count(), steps + 1);
  EXPECT_EQ(editAction(*w, "&Undo")->text(), "&Undo method MDS");
  w->takes()->undo();
  EXPECT_EQ(w->method(), embed::Method::Isomap);
}

TEST(StudioTakes, ATakeLeftForTheClipPlaysAgainWhenPicked) {
  auto w = windowWithMap();
  sketch(*w, 20, 120, 1.0);
  ASSERT_EQ(w->takes()->list().current(), 0);
  // A click on the clip's trajectory (or Motion → Show clip) shows the clip: no take is current.
  w->setCurrentClip(0, 30);
  EXPECT_EQ(w->takes()->list().current(), -1);
  EXPECT_EQ(w->playingMotion(), &w->clip()->motion);
  // Picking the take again plays it.
  w->takes()->list().setCurrent(0);
  EXPECT_EQ(w->playingMotion(), &w->takes()->list().at(0).result->motion);
  w->pause();
}

TEST(StudioTakes, EachTakeExportsAndTheScriptedSessionWorks) {
  // The scripted session: sketch, edit one control point, undo, export.
  auto w = windowWithMap();
  sketch(*w, 20, 120, 1.5);
  const Take before = w->takes()->list().at(0);
  ASSERT_TRUE(w->moveControlPoint(1, w->currentMap()->blender->sample_point(200)));
  ASSERT_TRUE(QTest::qWaitFor([&] { return !w->isSynthesizing(); }, kTimeoutMs));
  ASSERT_NE(w->takes()->list().at(0).result, before.result);
  w->takes()->undo();
  ASSERT_EQ(w->takes()->list().at(0).result, before.result);
  sketch(*w, 100, 180, 1.0);

  // File → Export motion and the panel's Export… suggest the clip's and the take's name.
  ExportNaming naming;
  naming.clip = "sample-swing";
  naming.take = "Take 1";
  EXPECT_EQ(motionFileName(naming), "sample-swing-Take_1.bvh");
  naming.take = "swing / up!";
  EXPECT_EQ(motionFileName(naming), "sample-swing-swing_up.bvh");
  naming.take = "///";
  EXPECT_EQ(motionFileName(naming), "sample-swing-take.bvh");
  EXPECT_EQ(w->fileMenu()->context().naming.take, w->takes()->list().currentTake()->name);
  QTemporaryDir dir;
  const TakeList& takes = w->takes()->list();
  EXPECT_TRUE(w->hasUnsavedMotion());
  for (int row = 0; row < takes.count(); ++row) {
    naming.take = takes.at(row).name;
    const QString path = dir.filePath(motionFileName(naming));
    ASSERT_TRUE(w->exportTake(row, path)) << w->lastError().toStdString();
    EXPECT_TRUE(takes.at(row).exported);
    const Clip back = io::load_clip(path.toStdString());
    EXPECT_EQ(back.motion.num_frames, takes.at(row).result->motion.num_frames);
    EXPECT_NEAR(back.motion.frame_time, takes.at(row).result->motion.frame_time, 1e-6);
  }
  EXPECT_EQ(takes.at(0).result, before.result);  // the undone edit is not what was written
  EXPECT_FALSE(w->hasUnsavedMotion());
  EXPECT_FALSE(w->exportTake(takes.count(), dir.filePath("none.bvh")));
  w->pause();
}

TEST(StudioTakes, UnexportedTakesAreAskedAboutNotReplaced) {
  auto w = windowWithMap();
  sketch(*w, 20, 80, 1.0);
  sketch(*w, 100, 180, 1.0);  // not asked: a new take
  QTemporaryDir dir;
  ASSERT_TRUE(w->exportTake(1, dir.filePath("second.bvh")));
  w->setInteractive(true);
  int asked = 0;
  QString text;
  QTimer answer;
  QObject::connect(&answer, &QTimer::timeout, [&] {
    if (auto* box = qobject_cast<QMessageBox*>(QApplication::activeModalWidget())) {
      ++asked;
      text = box->text();
      box->button(QMessageBox::Cancel)->click();
    }
  });
  answer.start(5);
  EXPECT_FALSE(w->close());
  EXPECT_EQ(asked, 1);
  EXPECT_EQ(text, "Take 1 has not been exported.");
  EXPECT_EQ(w->takes()->list().count(), 2);
  // After an edit of the exported take, both are unexported.
  ASSERT_TRUE(w->moveControlPoint(0, w->currentMap()->blender->sample_point(90)));
  ASSERT_TRUE(QTest::qWaitFor([&] { return !w->isSynthesizing(); }, kTimeoutMs));
  EXPECT_FALSE(w->confirmDiscard());
  EXPECT_EQ(asked, 2);
  EXPECT_EQ(text, "2 takes have not been exported (Take 1, Take 2).");
  // Undoing the edit brings back the exported motion.
  w->takes()->undo();
  EXPECT_TRUE(w->takes()->list().at(1).exported);
  answer.stop();
  w->setInteractive(false);
  w->pause();
}

}  // namespace
}  // namespace motionmap::studio
