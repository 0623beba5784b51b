// Box and lasso selection on the map (right drag, Shift + right drag): the frames inside listed
// per clip with their ranges in the Selection panel, played one after another, exported as a clip
// list that `motionmap map @list.txt` reads (io::read_clip_list) and as CSV.
#include <QDir>
#include <QFile>
#include <QSignalSpy>
#include <QTemporaryDir>
#include <QTest>
#include <QTreeWidget>
#include <filesystem>
#include <set>

#include "explore/nearest_panel.h"
#include "explore/selection_panel.h"
#include "map/map_view.h"
#include "motionmap/io/clip_inputs.h"
#include "studio_test_util.h"

namespace motionmap::studio {
namespace {

using testing::kTimeoutMs;

const std::string kData = MOTIONMAP_SHARED_DATA;

/// 64_08 and 64_09 (CMU golf swings, one skeleton) mapped together with PCA.
std::unique_ptr<MainWindow> twoSwings() {
  auto w = std::make_unique<MainWindow>();
  w->setInteractive(false);
  w->resize(1100, 650);
  w->show();
  w->setMethod(embed::Method::Pca);
  EXPECT_TRUE(w->openFile(QString::fromStdString(kData + "/cmu/64_08.bvh")));
  EXPECT_TRUE(w->addFile(QString::fromStdString(kData + "/cmu/64_09.bvh")));
  EXPECT_TRUE(
      QTest::qWaitFor([&] { return w->currentMap() != nullptr && !w->isComputing(); }, kTimeoutMs));
  w->pause();
  return w;
}

bool haveSwings() {
  return std::filesystem::exists(kData + "/cmu/64_08.bvh") &&
         std::filesystem::exists(kData + "/cmu/64_09.bvh");
}

void rightDrag(QWidget* view, const std::vector<QPoint>& path, Qt::KeyboardModifiers mods) {
  QTest::mousePress(view, Qt::RightButton, mods, path.front());
  for (std::size_t i = 1; i < path.size(); ++i) QTest::mouseMove(view, path[i]);
  QTest::mouseRelease(view, Qt::RightButton, mods, path.back());
}

/// The rows of the map shown whose pixels `inside` accepts, as (clip, frame).
std::set<std::pair<int, int>> expected(const MainWindow& w,
                                       const std::function<bool(QPointF)>& inside) {
  std::set<std::pair<int, int>> out;
  const MapResult* map = w.currentMap();
  const Eigen::MatrixXd& xy = map->map.embedding.coordinates;
  for (Eigen::Index i = 0; i < xy.rows(); ++i) {
    if (inside(w.mapView()->toWidget(Eigen::Vector2d(xy(i, 0), xy(i, 1)))))
      out.insert({map->map.features->clip_of[std::size_t(i)],
                  map->map.features->frame_of[std::size_t(i)]});
  }
  return out;
}

std::set<std::pair<int, int>> selected(const SelectionPanel& panel) {
  std::set<std::pair<int, int>> out;
  for (const SelectedFrame& f : panel.frames()) out.insert({f.clip, f.frame});
  return out;
}

TEST(StudioSelection, ABoxSelectsTheFramesInsideListedPerClipWithTheirRanges) {
  if (!haveSwings()) GTEST_SKIP() << "no CMU swings in " << kData;
  auto w = twoSwings();
  ASSERT_NE(w->currentMap(), nullptr);
  MapView* view = w->mapView();
  auto* panel = w->findChild<SelectionPanel*>();
  ASSERT_NE(panel, nullptr);
  EXPECT_FALSE(panel->isVisible());
  // A box around frame 150 of the first clip, drawn while zoomed in a little.
  const MapResult* map = w->currentMap();
  view->zoomAt(view->toWidget(map->map.embedding.coordinates.row(150).transpose().head<2>()), 1.5);
  const QPointF centre =
      view->toWidget(map->map.embedding.coordinates.row(150).transpose().head<2>());
  const QPoint a = (centre + QPointF(-70, -50)).toPoint();
  const QPoint b = (centre + QPointF(60, 45)).toPoint();
  const QRectF box = QRectF(a, b).normalized();
  const auto want = expected(*w, [&](QPointF p) { return box.contains(p); });  // before: the
  ASSERT_FALSE(want.empty());  // panel shown may change the view's size
  rightDrag(view, {a, (a + b) / 2, b}, Qt::NoModifier);
  // Points on the box's edge may round either way: compare away from it.
  const auto got = selected(*panel);
  std::size_t differ = 0;
  for (const auto& f : want) differ += !got.count(f);
  for (const auto& f : got) differ += !want.count(f);
  EXPECT_LE(differ, 2u) << want.size() << " expected, " << got.size() << " selected";
  EXPECT_TRUE(panel->isVisible());
  EXPECT_EQ(view->selection().rows(), Eigen::Index(panel->frames().size()));
  EXPECT_EQ(view->selectionOutline().size(), 5);  // the box, closed
  // Ranges: consecutive frames of one clip, covering the selection exactly.
  int covered = 0;
  for (std::size_t i = 0; i < panel->ranges().size(); ++i) {
    const FrameRange& r = panel->ranges()[i];
    EXPECT_LE(r.first, r.last);
    covered += r.frames();
    if (i > 0 && panel->ranges()[i - 1].clip == r.clip) {
      EXPECT_GT(r.first, panel->ranges()[i - 1].last + 1);
    }
  }
  EXPECT_EQ(covered, int(panel->frames().size()));
  // The list: one entry per clip, its ranges under it.
  std::set<int> clips;
  for (const auto& f : got) clips.insert(f.first);
  EXPECT_EQ(panel->tree()->topLevelItemCount(), int(clips.size()));
  EXPECT_TRUE(panel->tree()->topLevelItem(0)->text(0).startsWith("clip "));
  // A right click clears it.
  QTest::mouseClick(view, Qt::RightButton, Qt::NoModifier, a);
  EXPECT_TRUE(panel->frames().empty());
  EXPECT_EQ(view->selection().rows(), 0);
}

TEST(StudioSelection, ALassoSelectsThePolygonAndExportsAClipListAndCsv) {
  if (!haveSwings()) GTEST_SKIP() << "no CMU swings in " << kData;
  auto w = twoSwings();
  ASSERT_NE(w->currentMap(), nullptr);
  MapView* view = w->mapView();
  auto* panel = w->findChild<SelectionPanel*>();
  const QRectF plot = view->plotRect();
  auto at = [&](double u, double v) {
    return (plot.topLeft() + QPointF(plot.width() * u, plot.height() * v)).toPoint();
  };
  const std::vector<QPoint> lasso{at(0.1, 0.1), at(0.9, 0.2), at(0.8, 0.9), at(0.5, 0.5),
                                  at(0.15, 0.85)};
  QPolygonF polygon;
  for (const QPoint& p : lasso) polygon << QPointF(p);
  const auto want =
      expected(*w, [&](QPointF p) { return polygon.containsPoint(p, Qt::OddEvenFill); });
  rightDrag(view, lasso, Qt::ShiftModifier);
  const auto got = selected(*panel);
  std::size_t differ = 0;
  for (const auto& f : want) differ += !got.count(f);
  for (const auto& f : got) differ += !want.count(f);
  EXPECT_LE(differ, 2u) << want.size() << " expected, " << got.size() << " selected";
  ASSERT_FALSE(got.empty());
  EXPECT_GE(view->selectionOutline().size(), 5);
  // The clip list reads back as the selected clips' files.
  QTemporaryDir dir;
  const QString list = dir.filePath("selection.txt");
  QString error;
  ASSERT_TRUE(panel->exportList(list, &error)) << error.toStdString();
  const std::vector<std::string> paths = io::read_clip_list(list.toStdString());
  std::set<int> clips;
  for (const auto& f : got) clips.insert(f.first);
  ASSERT_EQ(paths.size(), clips.size());
  const char* names[] = {"64_08.bvh", "64_09.bvh"};
  std::size_t k = 0;
  for (const int c : clips) EXPECT_TRUE(paths[k++].ends_with(names[c])) << paths[k - 1];
  QFile text(list);
  ASSERT_TRUE(text.open(QIODevice::ReadOnly));
  const QString listText = QString::fromUtf8(text.readAll());
  EXPECT_TRUE(listText.contains("# clip ")) << listText.toStdString();
  // The CSV: a header and one line per frame.
  const QString csv = dir.filePath("selection.csv");
  ASSERT_TRUE(panel->exportCsv(csv, &error)) << error.toStdString();
  QFile csvFile(csv);
  ASSERT_TRUE(csvFile.open(QIODevice::ReadOnly));
  const QStringList lines = QString::fromUtf8(csvFile.readAll()).split('\n', Qt::SkipEmptyParts);
  ASSERT_EQ(lines.size(), qsizetype(panel->frames().size()) + 1);
  EXPECT_EQ(lines[0], "clip,frame,x,y");
  const SelectedFrame& first = panel->frames().front();
  const QStringList fields = lines[1].split(',');
  ASSERT_EQ(fields.size(), 4);
  EXPECT_TRUE(fields[0].endsWith(names[first.clip]));
  EXPECT_EQ(fields[1].toInt(), first.frame);
  EXPECT_DOUBLE_EQ(fields[2].toDouble(), first.x);
  EXPECT_DOUBLE_EQ(fields[3].toDouble(), first.y);
}

TEST(StudioSelection, PlayAllPlaysEveryRangeInOrder) {
  if (!haveSwings()) GTEST_SKIP() << "no CMU swings in " << kData;
  auto w = twoSwings();
  ASSERT_NE(w->currentMap(), nullptr);
  MapView* view = w->mapView();
  auto* panel = w->findChild<SelectionPanel*>();
  const QRectF plot = view->plotRect();
  rightDrag(view, {plot.topLeft().toPoint(), plot.center().toPoint(), plot.bottomRight().toPoint()},
            Qt::NoModifier);  // everything
  ASSERT_FALSE(panel->ranges().empty());
  // Keep a few short ranges of both clips: play them fast.
  w->setPlaybackSpeed(8.0);
  const bool loopBefore = w->loop();
  std::vector<std::pair<int, int>> shown;  // (clip, frame) while the sequence runs
  QObject::connect(w.get(), &MainWindow::frameChanged, [&](int frame) {
    if (panel->playingAll()) shown.push_back({w->currentClip(), frame});
  });
  panel->playAll();
  EXPECT_TRUE(panel->playingAll());
  ASSERT_TRUE(QTest::qWaitFor([&] { return !panel->playingAll(); }, kTimeoutMs));
  EXPECT_EQ(w->loop(), loopBefore);
  // Every frame shown lies in a selected range, and the clips follow the ranges' order.
  std::vector<int> clipsSeen;
  for (const auto& [clip, frame] : shown) {
    bool in = false;
    for (const FrameRange& r : panel->ranges())
      in |= r.clip == clip && frame >= r.first && frame <= r.last;
    EXPECT_TRUE(in) << "clip " << clip << " frame " << frame;
    if (clipsSeen.empty() || clipsSeen.back() != clip) clipsSeen.push_back(clip);
  }
  std::vector<int> clipsWanted;
  for (const FrameRange& r : panel->ranges())
    if (clipsWanted.empty() || clipsWanted.back() != r.clip) clipsWanted.push_back(r.clip);
  EXPECT_EQ(clipsSeen, clipsWanted);
  // The last range played to its end.
  EXPECT_EQ(w->currentClip(), panel->ranges().back().clip);
  EXPECT_EQ(w->currentFrame(), panel->ranges().back().last);
}

// The nearest frames of other clips to the point under the mouse, each one click away.
TEST(StudioNearest, ListsTheNearestFrameOfEachOtherClipAndAClickPlaysIt) {
  if (!haveSwings()) GTEST_SKIP() << "no CMU swings in " << kData;
  auto w = twoSwings();
  ASSERT_NE(w->currentMap(), nullptr);
  auto* panel = w->findChild<NearestPanel*>();
  ASSERT_NE(panel, nullptr);
  panel->show();
  QTest::qWait(20);  // the dock takes its room
  MapView* view = w->mapView();
  ASSERT_EQ(w->currentClip(), 0);
  const MapResult* map = w->currentMap();
  const Eigen::MatrixXd& xy = map->map.embedding.coordinates;
  const QPoint at = view->toWidget(xy.row(120).transpose().head<2>()).toPoint() + QPoint(2, 1);
  QTest::mouseMove(view, at);
  ASSERT_EQ(panel->entries().size(), 1u);  // one other clip: its nearest frame
  const NearestPanel::Entry& e = panel->entries().front();
  EXPECT_EQ(e.clip, 1);
  // The nearest sample of clip 1, found by brute force.
  const Eigen::Vector2d p = view->toMap(QPointF(at));
  double best = INFINITY;
  int bestFrame = -1;
  for (Eigen::Index i = 0; i < xy.rows(); ++i) {
    if (map->map.features->clip_of[std::size_t(i)] != 1) continue;
    const double d = (xy.row(i).transpose().head<2>() - p).norm();
    if (d < best) {
      best = d;
      bestFrame = map->map.features->frame_of[std::size_t(i)];
    }
  }
  EXPECT_EQ(e.frame, bestFrame);
  EXPECT_NEAR(e.distance, best, 1e-12);
  // The list stays when the mouse leaves the map; a click on the entry plays it.
  QTreeWidget* tree = panel->tree();
  ASSERT_EQ(tree->topLevelItemCount(), 1);
  EXPECT_TRUE(tree->topLevelItem(0)->text(0).startsWith("clip 2: 64_09"));
  QTest::mouseClick(tree->viewport(), Qt::LeftButton, Qt::NoModifier,
                    tree->visualItemRect(tree->topLevelItem(0)).center());
  EXPECT_EQ(w->currentClip(), 1);
  EXPECT_EQ(w->currentFrame(), bestFrame);
}

}  // namespace
}  // namespace motionmap::studio
