// Finding one's way in a map of several clips: the clip search (highlight, Enter, Escape), the
// legend's names (numbered as hover numbers, without the common prefix), each trajectory's time
// direction (light → dark in its colour) and take paths in a colour no clip has.
#include <QApplication>
#include <QDir>
#include <QImage>
#include <QLabel>
#include <QTest>

#include "explore/clip_search.h"
#include "map/map_source.h"
#include "map/map_view.h"
#include "motionmap/render/map_plot.h"
#include "studio_test_util.h"

namespace motionmap::studio {
namespace {

using testing::kTimeoutMs;

Clip named(sample::SampleKind kind, const std::string& path, double seconds) {
  sample::SampleOptions options;
  options.seconds = seconds;
  Clip clip = sample::make_sample_clip(kind, options);
  clip.path = path;
  return clip;
}

/// A window with three clips of one skeleton mapped together (PCA).
std::unique_ptr<MainWindow> threeClips() {
  auto w = std::make_unique<MainWindow>();
  w->setInteractive(false);
  w->resize(1100, 650);
  w->show();
  w->setMethod(embed::Method::Pca);
  w->openClip(named(sample::SampleKind::Walk, "/data/lib/walk_happy_01.bvh", 1.0));
  EXPECT_TRUE(w->addClip(named(sample::SampleKind::Walk, "/data/lib/walk_happy_02.bvh", 1.5)));
  EXPECT_TRUE(w->addClip(named(sample::SampleKind::Walk, "/data/lib/walk_sad_01.bvh", 1.2)));
  EXPECT_TRUE(QTest::qWaitFor(
      [&] {
        return (w->currentMap() != nullptr && !w->isComputing()) || !w->lastError().isEmpty();
      },
      kTimeoutMs));
  EXPECT_NE(w->currentMap(), nullptr) << w->lastError().toStdString();
  return w;
}

ClipSearch* searchOf(MainWindow& w) {
  return w.findChild<ClipSearch*>();
}

TEST(StudioExplore, LegendNamesAreNumberedAndLoseOnlyTheCommonPrefix) {
  EXPECT_EQ(legendNames({"walk_happy_01.bvh", "walk_happy_02.bvh", "walk_sad_01.bvh"}),
            QStringList({"clip 1: …happy_01", "clip 2: …happy_02", "clip 3: …sad_01"}));
  EXPECT_EQ(legendNames({"64_08.bvh", "64_09.bvh", "02_03.amc"}),
            QStringList({"clip 1: 64_08.bvh", "clip 2: 64_09.bvh", "clip 3: 02_03.amc"}));
  // Cut at a separator, never inside a word nor the whole name.
  EXPECT_EQ(legendNames({"run01.bvh", "run02.bvh"}),
            QStringList({"clip 1: run01.bvh", "clip 2: run02.bvh"}));
  EXPECT_EQ(legendNames({"aaaa_bbbb_x", "aaaa_bbbb_x_c"}),
            QStringList({"clip 1: …x", "clip 2: …x_c"}));
  EXPECT_EQ(legendNames({"same_name_here_1", "same_name_here_1"}),
            QStringList({"clip 1: same_name_here_1", "clip 2: same_name_here_1"}));
  // Short names fit whole: only numbered.
  EXPECT_EQ(legendNames({"a_b", "a_c"}), QStringList({"clip 1: a_b", "clip 2: a_c"}));
  EXPECT_EQ(legendNames({"only.bvh"}), QStringList({"only.bvh"}));
}

TEST(StudioExplore, EachClipRunsLightToDarkInItsColourAndTakesHaveAColourOfTheirOwn) {
  for (int c = 0; c < 10; ++c) {
    const QColor light = render::clip_time_color(c, 0.0), dark = render::clip_time_color(c, 1.0);
    EXPECT_GT(light.lightness(), render::clip_color(c).lightness()) << c;
    EXPECT_LT(dark.lightness(), render::clip_color(c).lightness()) << c;
    EXPECT_EQ(render::clip_time_color(c, 0.5), render::clip_color(c));
    // The take's path is no clip's colour, nor near one.
    const QColor take = MapView::takeColor();
    EXPECT_GT(std::abs(take.red() - render::clip_color(c).red()) +
                  std::abs(take.green() - render::clip_color(c).green()) +
                  std::abs(take.blue() - render::clip_color(c).blue()),
              120)
        << c;
  }
  auto w = threeClips();
  ASSERT_NE(w->currentMap(), nullptr);
  w->pause();
  const render::MapPlotOptions& options = w->mapView()->plotOptions();
  EXPECT_TRUE(options.clip_time_ramp);
  EXPECT_EQ(options.clip_names,
            QStringList({"clip 1: …happy_01", "clip 2: …happy_02", "clip 3: …sad_01"}));
  const QString dir = QDir::temp().filePath("motionmap-studio-explore");
  QDir().mkpath(dir);
  w->mapView()->grab().toImage().save(dir + "/three-clips.png");
  // Drawn: two parallel clips, each light at its start and dark at its end in its own colour.
  Eigen::MatrixXd c(100, 2);
  for (int i = 0; i < 50; ++i) c.row(i) << i / 49.0, 0.0;
  for (int i = 0; i < 50; ++i) c.row(50 + i) << i / 49.0, 1.0;
  render::MapPlotOptions two;
  two.line_width = 4.0;
  two.clip_names = {"a", "b"};
  two.clip_time_ramp = true;
  MapView view;
  view.resize(400, 400);
  view.setMap(c, {0, 50}, two);
  const QImage shot = view.grab().toImage();
  auto distance = [&](Eigen::Vector2d at, QColor want) {
    const QPoint p = view.toWidget(at).toPoint();
    const QColor got = shot.pixelColor(p);
    return std::abs(got.red() - want.red()) + std::abs(got.green() - want.green()) +
           std::abs(got.blue() - want.blue());
  };
  for (int k = 0; k < 2; ++k) {
    EXPECT_LT(distance({0.1, double(k)}, render::clip_time_color(k, 0.1)), 30) << k;
    EXPECT_LT(distance({0.5, double(k)}, render::clip_color(k)), 30) << k;
    EXPECT_LT(distance({0.9, double(k)}, render::clip_time_color(k, 0.9)), 30) << k;
    EXPECT_GT(shot.pixelColor(view.toWidget({0.1, double(k)}).toPoint()).lightness(),
              shot.pixelColor(view.toWidget({0.9, double(k)}).toPoint()).lightness() + 40)
        << k;
  }
}

TEST(StudioExplore, TheSearchHighlightsMatchingClipsEnterPlaysThemEscapeClears) {
  auto w = threeClips();
  ASSERT_NE(w->currentMap(), nullptr);
  w->pause();
  ClipSearch* search = searchOf(*w);
  ASSERT_NE(search, nullptr);
  MapView* view = w->mapView();
  search->setFocus();
  QTest::keyClicks(search, "happy");
  EXPECT_EQ(search->matches(), (std::vector<int>{0, 1}));
  EXPECT_EQ(search->countLabel()->text(), "2 clips");
  const std::vector<int>& starts = w->currentMap()->map.features->segment_starts;
  EXPECT_EQ(view->highlight().rows(), starts[2]);  // every sample of clips 1 and 2
  // Words must all occur, case-insensitive.
  search->setText("SAD 01");
  EXPECT_EQ(search->matches(), (std::vector<int>{2}));
  // Enter plays the first match; with it playing, Enter goes on to the next (here: itself).
  QTest::keyClick(search, Qt::Key_Return);
  EXPECT_EQ(w->currentClip(), 2);
  EXPECT_EQ(w->currentFrame(), 0);
  search->setText("happy");
  QTest::keyClick(search, Qt::Key_Return);
  EXPECT_EQ(w->currentClip(), 0);
  QTest::keyClick(search, Qt::Key_Return);
  EXPECT_EQ(w->currentClip(), 1);
  QTest::keyClick(search, Qt::Key_Return);
  EXPECT_EQ(w->currentClip(), 0);
  // The highlight is drawn (magenta inside the plot).
  const QImage shot = view->grab().toImage();
  QDir().mkpath(QDir::temp().filePath("motionmap-studio-explore"));
  shot.save(QDir::temp().filePath("motionmap-studio-explore/search.png"));
  int magenta = 0;
  for (int y = 0; y < shot.height(); ++y)
    for (int x = 0; x < shot.width(); ++x)
      magenta += shot.pixelColor(x, y) == MapView::highlightColor();
  EXPECT_GT(magenta, 50);
  // Nothing matches: no highlight.
  search->setText("zebra");
  EXPECT_TRUE(search->matches().empty());
  EXPECT_EQ(search->countLabel()->text(), "no clip");
  EXPECT_EQ(view->highlight().rows(), 0);
  // Escape clears the text and the highlight.
  search->setText("walk");
  EXPECT_EQ(search->matches().size(), 3u);
  QTest::keyClick(search, Qt::Key_Escape);
  EXPECT_TRUE(search->text().isEmpty());
  EXPECT_EQ(view->highlight().rows(), 0);
  // Ctrl+F puts the cursor in the field.
  w->mapView()->setFocus();
  QTest::keyClick(w.get(), Qt::Key_F, Qt::ControlModifier);
  EXPECT_TRUE(search->hasFocus());
}

TEST(StudioExplore, TheSearchFollowsANewMap) {
  auto w = threeClips();
  ASSERT_NE(w->currentMap(), nullptr);
  w->pause();
  ClipSearch* search = searchOf(*w);
  search->setText("sad");
  const Eigen::Index before = w->mapView()->highlight().rows();
  EXPECT_GT(before, 0);
  w->setMethod(embed::Method::Mds);
  ASSERT_TRUE(
      QTest::qWaitFor([&] { return w->currentMap() != nullptr && !w->isComputing(); }, kTimeoutMs));
  EXPECT_EQ(w->mapView()->highlight().rows(), before);  // highlighted again on the new map
  const Eigen::MatrixXd& xy = w->currentMap()->map.embedding.coordinates;
  const int start = w->currentMap()->map.features->segment_starts[2];
  EXPECT_EQ(w->mapView()->highlight().row(0), xy.row(start).leftCols(2));
}

}  // namespace
}  // namespace motionmap::studio
