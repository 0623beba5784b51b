#include "motionmap/render/map_plot.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <QCoreApplication>
#include <QFile>
#include <QGuiApplication>
#include <QImage>
#include <QXmlStreamReader>

#include "motionmap/core/error.h"
#include "support/error_message.h"

namespace motionmap::render {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string temp_file(const std::string& name) {
  return (std::filesystem::path(::testing::TempDir()) / ("motionmap_render_" + name)).string();
}

// `n` samples on three quarters of a circle (angles 0 … 1.5π), so the start and end are apart.
// With n - 1 divisible by 3 samples land on π/2 and π, and the bounding box is the full
// circle's: x and y both span [cx - r, cx + r].
Eigen::MatrixXd arc(int n, double r = 1.0, double cx = 0.0, double cy = 0.0) {
  Eigen::MatrixXd c(n, 2);
  for (int i = 0; i < n; ++i) {
    const double a = 1.5 * std::numbers::pi * i / (n - 1);
    c(i, 0) = cx + r * std::cos(a);
    c(i, 1) = cy + r * std::sin(a);
  }
  return c;
}

// Samples evenly from (x0, y) to (x1, y).
Eigen::MatrixXd line(int n, double x0, double x1, double y) {
  Eigen::MatrixXd c(n, 2);
  for (int i = 0; i < n; ++i) {
    c(i, 0) = x0 + (x1 - x0) * i / (n - 1);
    c(i, 1) = y;
  }
  return c;
}

bool is_white(const QColor& c) {
  return c.red() > 245 && c.green() > 245 && c.blue() > 245;
}
bool is_dark(const QColor& c) {
  return c.red() < 90 && c.green() < 90 && c.blue() < 90;
}
bool is_reddish(const QColor& c) {  // dark red, red or orange-red: the start of the ramp
  return c.red() > 150 && c.green() < 120 && c.blue() < 70;
}
bool is_bluish(const QColor& c) {  // blue or dark blue: its end
  return c.blue() > 150 && c.red() < 70 && c.green() < 120;
}

// Whether some pixel within `radius` of `p` satisfies `pred`.
bool any_near(const QImage& img, QPointF p, int radius, const std::function<bool(QColor)>& pred) {
  const int px = static_cast<int>(std::floor(p.x())), py = static_cast<int>(std::floor(p.y()));
  for (int y = py - radius; y <= py + radius; ++y) {
    for (int x = px - radius; x <= px + radius; ++x) {
      if (img.valid(x, y) && pred(img.pixelColor(x, y))) return true;
    }
  }
  return false;
}

bool all_near(const QImage& img, QPointF p, int radius, const std::function<bool(QColor)>& pred) {
  return !any_near(img, p, radius, [&](QColor c) { return !pred(c); });
}

QColor pixel_at(const QImage& img, QPointF p) {
  return img.pixelColor(static_cast<int>(std::floor(p.x())), static_cast<int>(std::floor(p.y())));
}

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

using test::error_message;

// Tests that draw: under the QGuiApplication that render_test_main.cpp makes.
class MapPlotTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    ASSERT_NE(qobject_cast<QGuiApplication*>(QCoreApplication::instance()), nullptr)
        << "render_test_main.cpp makes the QGuiApplication";
  }
};

// --- colours ----------------------------------------------------------------------------------

TEST(TimeColorTest, RunsJetBackwardsThroughItsKnots) {
  EXPECT_EQ(time_color(0.0), QColor(128, 0, 0));      // dark red
  EXPECT_EQ(time_color(0.125), QColor(255, 0, 0));    // red
  EXPECT_EQ(time_color(0.375), QColor(255, 255, 0));  // yellow
  EXPECT_EQ(time_color(0.5), QColor(128, 255, 128));  // green, halfway yellow → cyan
  EXPECT_EQ(time_color(0.625), QColor(0, 255, 255));  // cyan
  EXPECT_EQ(time_color(0.875), QColor(0, 0, 255));    // blue
  EXPECT_EQ(time_color(1.0), QColor(0, 0, 128));      // dark blue
}

TEST(TimeColorTest, IsLinearBetweenKnotsAndClamped) {
  EXPECT_EQ(time_color(0.0625), QColor(192, 0, 0));  // halfway dark red → red
  EXPECT_EQ(time_color(0.25), QColor(255, 128, 0));  // orange, halfway red → yellow
  EXPECT_EQ(time_color(0.75), QColor(0, 128, 255));  // halfway cyan → blue
  EXPECT_EQ(time_color(0.9375), QColor(0, 0, 192));  // halfway blue → dark blue
  EXPECT_EQ(time_color(-3.0), QColor(128, 0, 0));
  EXPECT_EQ(time_color(7.0), QColor(0, 0, 128));
  EXPECT_EQ(time_color(kNaN), QColor(128, 128, 128));
  // Hue order: red before yellow before green before cyan before blue, never back.
  double last_hue = -1.0;
  for (int k = 13; k <= 87; ++k) {
    const QColor c = time_color(k / 100.0);
    const double hue = c.hsvHueF();
    EXPECT_GE(hue, last_hue - 1e-9) << k;
    last_hue = hue;
  }
}

// --- plain-data geometry ----------------------------------------------------------------------

TEST(CategorySlotsTest, UpToTwelveValuesAreEachColouredInValueOrder) {
  EXPECT_TRUE(category_slots(std::vector<int>{}).empty());
  // Colours follow the values, not their counts (a value with no sample still has its colour).
  EXPECT_EQ(category_slots(std::vector<int>{5, 50, 0, 7}), (std::vector<int>{0, 1, 2, 3}));
  std::vector<int> twelve(kCategoryColors, 0);
  for (int v = 0; v < kCategoryColors; ++v) twelve[std::size_t(v)] = 100 - v;
  std::vector<int> all(kCategoryColors, 0);
  for (int v = 0; v < kCategoryColors; ++v) all[std::size_t(v)] = v;
  EXPECT_EQ(category_slots(twelve), all);
}

TEST(CategorySlotsTest, MoreThanTwelveColourTheElevenMostFrequentAndGreyTheRest) {
  // 14 values: counts 1 … 14 backwards but values 3 and 9 rare; the 11 most frequent coloured
  // and numbered in value order, the 3 least frequent grey.
  const std::vector<int> counts = {40, 39, 38, 1, 36, 35, 34, 33, 32, 2, 30, 29, 28, 3};
  const std::vector<int> slot_of = category_slots(counts);
  EXPECT_EQ(slot_of, (std::vector<int>{0, 1, 2, -1, 3, 4, 5, 6, 7, -1, 8, 9, 10, -1}));
  // Ties in value order: of 13 equal counts the first 11 values are coloured.
  const std::vector<int> tied = category_slots(std::vector<int>(13, 5));
  for (int v = 0; v < 11; ++v) EXPECT_EQ(tied[std::size_t(v)], v);
  EXPECT_EQ(tied[11], -1);
  EXPECT_EQ(tied[12], -1);
  // A tie at the cut is broken by value order, wherever the tied values lie.
  std::vector<int> cut(13, 10);
  cut[0] = 1;   // least frequent: grey
  cut[12] = 1;  // tied with value 0 at the bottom: grey
  const std::vector<int> s = category_slots(cut);
  EXPECT_EQ(s[0], -1);
  EXPECT_EQ(s[12], -1);
  for (int v = 1; v < 12; ++v) EXPECT_EQ(s[std::size_t(v)], v - 1);
}

TEST(TrajectorySegmentsTest, OneClipGivesColouredUnitSquareSegments) {
  const Eigen::MatrixXd c = arc(121, 3.0, 10.0, -5.0);
  const auto segs = trajectory_segments(c, {});
  ASSERT_EQ(segs.size(), 120u);
  for (std::size_t k = 0; k < segs.size(); ++k) {
    EXPECT_EQ(segs[k].sample, static_cast<int>(k));
    EXPECT_NEAR(segs[k].time, (k + 0.5) / 120.0, 1e-12);
    EXPECT_EQ(segs[k].color, time_color(segs[k].time));
    if (k > 0) {
      EXPECT_EQ(segs[k].from, segs[k - 1].to);
    }
    // The circle of radius 3 around (10, -5) becomes the circle of radius 0.5 around (0.5, 0.5).
    EXPECT_NEAR(std::hypot(segs[k].from.x() - 0.5, segs[k].from.y() - 0.5), 0.5, 1e-9);
  }
  EXPECT_NEAR(segs.front().from.x(), 1.0, 1e-12);  // angle 0: rightmost
  EXPECT_NEAR(segs.front().from.y(), 0.5, 1e-12);
  EXPECT_NEAR(segs[40].from.y(), 1.0, 1e-9);  // angle π/2: the top, so y points up
}

TEST(TrajectorySegmentsTest, EqualScaleOnBothAxes) {
  Eigen::MatrixXd c(3, 2);
  c << 0, 0, 4, 0, 4, 1;  // 4 wide, 1 tall
  const auto segs = trajectory_segments(c, {});
  ASSERT_EQ(segs.size(), 2u);
  EXPECT_NEAR(segs[0].from.x(), 0.0, 1e-12);
  EXPECT_NEAR(segs[0].to.x(), 1.0, 1e-12);
  EXPECT_NEAR(segs[0].from.y(), 0.5 - 0.125, 1e-12);  // the short side is centred
  EXPECT_NEAR(segs[1].to.y(), 0.5 + 0.125, 1e-12);
}

TEST(FillAxesTest, ScalesTheShorterAxisToTheLongerAboutItsCentre) {
  Eigen::MatrixXd coords(4, 3);
  coords << 0, 5, 7,  //
      10, 6, 8,       //
      std::nan(""), 100, 9, 5, 5.5, 1;
  const Eigen::MatrixXd filled = fill_axes(coords);
  EXPECT_EQ(filled.col(0).head(2), coords.col(0).head(2));  // the longer axis is kept
  EXPECT_DOUBLE_EQ(filled(0, 1), 0.5);                      // y: [5, 6] → [0.5, 10.5]
  EXPECT_DOUBLE_EQ(filled(1, 1), 10.5);
  EXPECT_DOUBLE_EQ(filled(3, 1), 5.5);
  EXPECT_EQ(filled.col(2), coords.col(2));  // a third column is left alone
  EXPECT_TRUE(std::isnan(filled(2, 0)));    // a gap stays a gap, and did not count for y
  // Zero extent: unchanged, finite.
  Eigen::MatrixXd flat(3, 2);
  flat << 0, 1, 1, 1, 2, 1;
  EXPECT_EQ(fill_axes(flat), flat);
  // Rounding noise around a value (a static clip's flat axis) is not stretched either.
  Eigen::MatrixXd noise(10, 2);
  for (int i = 0; i < 10; ++i) noise.row(i) << 5.0 + i * 1e-15, 0.0;
  EXPECT_EQ(fill_axes(noise), noise);
}

TEST(TrajectorySegmentsTest, ClipsAreNotJoinedAndEachHasItsOwnTime) {
  Eigen::MatrixXd c(30, 2);
  c << line(10, 0, 1, 0), line(20, 0, 1, 1);
  const auto segs = trajectory_segments(c, {0, 10});
  ASSERT_EQ(segs.size(), 9u + 19u);
  for (const auto& s : segs) EXPECT_NE(s.sample, 9) << "segment across the clip boundary";
  EXPECT_NEAR(segs[0].time, 0.5 / 9, 1e-12);
  EXPECT_NEAR(segs[8].time, 1 - 0.5 / 9, 1e-12);
  EXPECT_EQ(segs[9].sample, 10);
  EXPECT_NEAR(segs[9].time, 0.5 / 19, 1e-12);
  EXPECT_NEAR(segs.back().time, 1 - 0.5 / 19, 1e-12);
  // Without 0 in the list, row 0 still starts a clip: same result.
  EXPECT_EQ(trajectory_segments(c, {10}).size(), segs.size());
}

TEST(TrajectorySegmentsTest, NonFiniteRowsAreGaps) {
  Eigen::MatrixXd c = line(10, 0, 9, 0);
  c(4, 1) = kNaN;
  c(7, 0) = std::numeric_limits<double>::infinity();
  const auto segs = trajectory_segments(c, {});
  ASSERT_EQ(segs.size(), 9u - 4u);  // 3-4, 4-5, 6-7, 7-8 dropped
  for (const auto& s : segs) {
    EXPECT_TRUE(s.sample != 3 && s.sample != 4 && s.sample != 6 && s.sample != 7) << s.sample;
    EXPECT_TRUE(std::isfinite(s.from.x()) && std::isfinite(s.to.y()));
  }
  // The bounding box ignores the infinite row: x spans 0 … 9 → 0 … 1.
  EXPECT_NEAR(segs.front().from.x(), 0.0, 1e-12);
  EXPECT_NEAR(segs.back().to.x(), 1.0, 1e-12);
}

TEST(TrajectorySegmentsTest, DegenerateInputsGiveFiniteOrNoSegments) {
  EXPECT_TRUE(trajectory_segments(Eigen::MatrixXd(0, 2), {}).empty());
  EXPECT_TRUE(trajectory_segments(Eigen::MatrixXd::Constant(1, 2, 3.0), {}).empty());
  const auto same = trajectory_segments(Eigen::MatrixXd::Constant(5, 3, 7.0), {});
  ASSERT_EQ(same.size(), 4u);
  for (const auto& s : same) EXPECT_EQ(s.from, QPointF(0.5, 0.5));
  EXPECT_TRUE(trajectory_segments(Eigen::MatrixXd::Constant(5, 2, kNaN), {}).empty());
  // Huge and tiny extents stay finite.
  Eigen::MatrixXd huge(2, 2);
  huge << -1e308, -1e308, 1e308, 1e308;
  const auto h = trajectory_segments(huge, {});
  ASSERT_EQ(h.size(), 1u);
  EXPECT_NEAR(h[0].from.x(), 0.0, 1e-12);
  EXPECT_NEAR(h[0].to.y(), 1.0, 1e-12);
  Eigen::MatrixXd tiny(2, 2);
  tiny << 1.0, 1.0, 1.0 + 1e-310, 1.0;
  for (const auto& s : trajectory_segments(tiny, {})) {
    EXPECT_TRUE(std::isfinite(s.from.x()) && std::isfinite(s.to.x()));
  }
}

TEST(TrajectorySegmentsTest, InvalidInputIsAParameterError) {
  EXPECT_EQ(error_message<ParameterError>([] { trajectory_segments(Eigen::MatrixXd(4, 1), {}); }),
            "map plot: coords has 1 column(s); need at least 2 (x, y)");
  const Eigen::MatrixXd c = line(5, 0, 1, 0);
  EXPECT_EQ(error_message<ParameterError>([&] {
              trajectory_segments(c, {0, 5});
            }),
            "map plot: segment_starts[1] = 5 is outside [0, 5)");
  EXPECT_EQ(error_message<ParameterError>([&] { trajectory_segments(c, {-1}); }),
            "map plot: segment_starts[0] = -1 is outside [0, 5)");
  EXPECT_EQ(error_message<ParameterError>([&] {
              trajectory_segments(c, {0, 3, 2});
            }),
            "map plot: segment_starts must be strictly increasing, but [2] = 2 follows 3");
  EXPECT_EQ(error_message<ParameterError>([&] {
              trajectory_segments(c, {3, 3});
            }),
            "map plot: segment_starts must be strictly increasing, but [1] = 3 follows 3");
}

TEST(MapTransformTest, DataAreaIsASquareInsideTheRect) {
  MapPlotOptions o;
  o.title = "title";
  o.notes = {"one", "two", "three"};
  o.time_legend = true;
  for (const QRectF rect :
       {QRectF(0, 0, 800, 800), QRectF(10, 20, 900, 400), QRectF(0, 0, 300, 1000)}) {
    const QRectF d = data_area(rect, o);
    EXPECT_NEAR(d.width(), d.height(), 1e-9);
    EXPECT_GT(d.width(), 0.5 * std::min(rect.width(), rect.height()));
    EXPECT_TRUE(rect.contains(d));
    EXPECT_NEAR(d.center().x(), rect.center().x(), 1e-9);
  }
  // A zero-size rect still gives an invertible transform.
  EXPECT_TRUE(unit_transform(QRectF(0, 0, 0, 0)).isInvertible());
}

TEST(MapTransformTest, MapsDataToPixelsAndBack) {
  const Eigen::MatrixXd c = arc(49, 2.0, 1.0, 1.0);
  const QRectF rect(0, 0, 640, 480);
  const MapPlotOptions o;
  const QTransform t = map_transform(c, rect, o);
  ASSERT_TRUE(t.isInvertible());
  const QRectF d = data_area(rect, o);
  // The circle's bounding box (-1 … 3 on both axes) fills the data area; y points up.
  EXPECT_NEAR(t.map(QPointF(-1, 3)).x(), d.left(), 1e-9);
  EXPECT_NEAR(t.map(QPointF(-1, 3)).y(), d.top(), 1e-9);
  EXPECT_NEAR(t.map(QPointF(3, -1)).x(), d.right(), 1e-9);
  EXPECT_NEAR(t.map(QPointF(3, -1)).y(), d.bottom(), 1e-9);
  const QPointF back = t.inverted().map(t.map(QPointF(0.3, 2.2)));
  EXPECT_NEAR(back.x(), 0.3, 1e-9);
  EXPECT_NEAR(back.y(), 2.2, 1e-9);
  // Same placement as the cached segments: data_to_unit then unit_transform.
  const auto segs = trajectory_segments(c, {});
  const QPointF via_unit = unit_transform(rect, o).map(segs[7].from);
  const QPointF direct = t.map(QPointF(c(7, 0), c(7, 1)));
  EXPECT_NEAR(via_unit.x(), direct.x(), 1e-9);
  EXPECT_NEAR(via_unit.y(), direct.y(), 1e-9);
  // Identical samples: still invertible, the point in the middle.
  const Eigen::MatrixXd same = Eigen::MatrixXd::Constant(3, 2, 5.0);
  const QTransform ts = map_transform(same, rect, o);
  ASSERT_TRUE(ts.isInvertible());
  EXPECT_NEAR(ts.map(QPointF(5, 5)).x(), d.center().x(), 1e-9);
  EXPECT_NEAR(ts.map(QPointF(5, 5)).y(), d.center().y(), 1e-9);
}

// --- images -----------------------------------------------------------------------------------

TEST_F(MapPlotTest, PngOfAnArcShowsTimeColoursStartMarkerAndSquarePanel) {
  const Eigen::MatrixXd c = arc(199);
  MapPlotOptions o;
  o.title = "Circle";
  o.notes = {"trustworthiness 0.99", "continuity 0.98"};
  o.line_width = 3.0;
  const std::string path = temp_file("arc.png");
  save_map_plot(path, c, {}, o, 400);
  QImage img(QString::fromStdString(path));
  ASSERT_FALSE(img.isNull());
  ASSERT_EQ(img.size(), QSize(400, 400));

  for (QPoint corner : {QPoint(0, 0), QPoint(399, 0), QPoint(0, 399), QPoint(399, 399)}) {
    EXPECT_TRUE(is_white(img.pixelColor(corner))) << corner.x() << "," << corner.y();
  }
  const QTransform t = map_transform(c, QRectF(0, 0, 400, 400), o);
  const QPointF start = t.map(QPointF(c(0, 0), c(0, 1)));
  EXPECT_TRUE(is_white(pixel_at(img, start))) << "marker fill";
  EXPECT_TRUE(any_near(img, start, 8, is_dark)) << "marker outline";
  EXPECT_FALSE(any_near(img, start, 2, is_reddish)) << "the marker covers the line's start";
  EXPECT_TRUE(any_near(img, t.map(QPointF(c(10, 0), c(10, 1))), 1, is_reddish));
  EXPECT_TRUE(any_near(img, t.map(QPointF(c(190, 0), c(190, 1))), 1, is_bluish));
  EXPECT_FALSE(any_near(img, t.map(QPointF(c(190, 0), c(190, 1))), 1, is_reddish));
  EXPECT_TRUE(all_near(img, t.map(QPointF(0, 0)), 20, is_white)) << "the circle's centre";

  // Equal scale: the coloured pixels (the full circle's bounding box) form a square centred in
  // the data area.
  int x0 = 400, x1 = -1, y0 = 400, y1 = -1;
  for (int y = 0; y < 400; ++y) {
    for (int x = 0; x < 400; ++x) {
      const QColor p = img.pixelColor(x, y);
      if (std::max({p.red(), p.green(), p.blue()}) - std::min({p.red(), p.green(), p.blue()}) < 100)
        continue;  // not saturated (the ramp's dark ends are 128): background, frame, text, marker
      x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
  }
  ASSERT_GT(x1, x0);
  EXPECT_NEAR(x1 - x0, y1 - y0, 2);
  const QRectF d = data_area(QRectF(0, 0, 400, 400), o);
  EXPECT_NEAR((x0 + x1 + 1) / 2.0, d.center().x(), 2);
  EXPECT_NEAR((y0 + y1 + 1) / 2.0, d.center().y(), 2);
  EXPECT_NEAR(x1 - x0, d.width(), 5);
  // The title sits above the data area and the notes below it: dark text pixels there.
  bool title = false, notes = false;
  for (int y = 0; y < 400; ++y) {
    for (int x = 0; x < 400; ++x) {
      if (!is_dark(img.pixelColor(x, y))) continue;
      title |= y < d.top() - 10;
      notes |= y > d.bottom() + 10;
    }
  }
  EXPECT_TRUE(title);
  EXPECT_TRUE(notes);
}

TEST_F(MapPlotTest, ClipsAreDrawnSeparatelyEachFromRedToBlue) {
  Eigen::MatrixXd c(100, 2);
  c << line(50, 0, 1, 0), line(50, 0, 1, 1);
  MapPlotOptions o;
  o.line_width = 3.0;
  const std::string path = temp_file("clips.png");
  save_map_plot(path, c, {0, 50}, o, 300);
  QImage img(QString::fromStdString(path));
  ASSERT_EQ(img.size(), QSize(300, 300));
  const QTransform t = map_transform(c, QRectF(0, 0, 300, 300), o);
  // Between the end of clip 1 (1, 0) and the start of clip 2 (0, 1): background.
  EXPECT_TRUE(all_near(img, t.map(QPointF(0.5, 0.5)), 3, is_white));
  EXPECT_TRUE(all_near(img, t.map(QPointF(0.25, 0.75)), 3, is_white));
  EXPECT_TRUE(all_near(img, t.map(QPointF(0.75, 0.25)), 3, is_white));
  for (const double y : {0.0, 1.0}) {
    EXPECT_TRUE(is_white(pixel_at(img, t.map(QPointF(0, y))))) << "start marker of clip y=" << y;
    EXPECT_TRUE(any_near(img, t.map(QPointF(0.1, y)), 1, is_reddish)) << y;
    EXPECT_TRUE(any_near(img, t.map(QPointF(0.95, y)), 1, is_bluish)) << y;
  }
  // Joined clips would draw the diagonal: check that drawing them as one clip does.
  save_map_plot(path, c, {}, o, 300);
  QImage joined(QString::fromStdString(path));
  EXPECT_FALSE(all_near(joined, t.map(QPointF(0.5, 0.5)), 3, is_white));
}

TEST_F(MapPlotTest, ColourByClipDrawsEachClipInItsOwnColourWithANamedLegend) {
  Eigen::MatrixXd c(100, 2);
  c << line(50, 0, 1, 0), line(50, 0, 1, 1);
  MapPlotOptions o;
  o.line_width = 3.0;
  o.clip_names = {"first.bvh", "second.bvh"};
  o.time_legend = true;
  const std::string path = temp_file("by-clip.png");
  save_map_plot(path, c, {0, 50}, o, 300);
  QImage img(QString::fromStdString(path));
  const QTransform t = map_transform(c, QRectF(0, 0, 300, 300), o);
  auto near_colour = [](QColor want) {
    return [want](QColor p) {
      return std::abs(p.red() - want.red()) + std::abs(p.green() - want.green()) +
                 std::abs(p.blue() - want.blue()) <
             30;
    };
  };
  EXPECT_NE(clip_color(0), clip_color(1));
  for (const double x : {0.1, 0.5, 0.95}) {  // the whole clip, not a time ramp
    EXPECT_TRUE(any_near(img, t.map(QPointF(x, 0)), 1, near_colour(clip_color(0)))) << x;
    EXPECT_FALSE(any_near(img, t.map(QPointF(x, 0)), 1, near_colour(clip_color(1)))) << x;
    EXPECT_TRUE(any_near(img, t.map(QPointF(x, 1)), 1, near_colour(clip_color(1)))) << x;
    EXPECT_FALSE(any_near(img, t.map(QPointF(x, 1)), 1, is_reddish)) << x;
  }
  // The legend under the box: swatches of both colours, no time bar.
  const QRectF d = data_area(QRectF(0, 0, 300, 300), o);
  bool swatch[2] = {false, false}, ramp_green = false;
  for (int y = static_cast<int>(d.bottom()) + 3; y < 300; ++y) {
    for (int x = 0; x < 300; ++x) {
      const QColor p = img.pixelColor(x, y);
      for (int k = 0; k < 2; ++k) swatch[k] |= near_colour(clip_color(k))(p);
      ramp_green |= near_colour(QColor(0, 255, 0))(p);
    }
  }
  EXPECT_TRUE(swatch[0] && swatch[1]);
  EXPECT_FALSE(ramp_green);
  EXPECT_EQ(clip_color(10), clip_color(0));  // the palette cycles
  EXPECT_EQ(clip_color(-1), QColor(128, 128, 128));
}

TEST_F(MapPlotTest, AClipGivenAColourIsDrawnAndKeyedInItTrajectoryAndSwatchAlike) {
  // clip_colors: clip 1 (e.g. compared with another) in teal, flat, over a time ramp; its legend
  // swatch in the same teal, clip 0's as before (drawn_clip_color, one rule).
  Eigen::MatrixXd c(100, 2);
  c << line(50, 0, 1, 0), line(50, 0, 1, 1);
  MapPlotOptions o;
  o.line_width = 3.0;
  o.clip_names = {"first.bvh", "second.bvh"};
  o.time_legend = true;
  o.clip_time_ramp = true;
  const QColor teal(0, 140, 150);
  o.clip_colors = {QColor(), teal};
  EXPECT_EQ(drawn_clip_color(o, 1, 0.0), teal);
  EXPECT_EQ(drawn_clip_color(o, 1, 1.0), teal);
  EXPECT_EQ(drawn_clip_color(o, 0, 0.3), clip_time_color(0, 0.3));
  EXPECT_EQ(drawn_clip_color(o, 5, 0.3), clip_time_color(5, 0.3));  // past the list: its own
  const std::string path = temp_file("clip-colour.png");
  save_map_plot(path, c, {0, 50}, o, 300);
  QImage img(QString::fromStdString(path));
  const QTransform t = map_transform(c, QRectF(0, 0, 300, 300), o);
  auto is_teal = [teal](QColor p) {
    return std::abs(p.red() - teal.red()) + std::abs(p.green() - teal.green()) +
               std::abs(p.blue() - teal.blue()) <
           12;
  };
  for (const double x : {0.1, 0.5, 0.95}) {
    EXPECT_TRUE(any_near(img, t.map(QPointF(x, 1)), 1, is_teal)) << x;
    EXPECT_FALSE(any_near(img, t.map(QPointF(x, 0)), 1, is_teal)) << x;
  }
  const QRectF d = data_area(QRectF(0, 0, 300, 300), o);
  int swatch = 0;
  for (int y = static_cast<int>(d.bottom()) + 3; y < 300; ++y)
    for (int x = 0; x < 300; ++x) swatch += is_teal(img.pixelColor(x, y));
  EXPECT_GT(swatch, 10);
  // Without the colour no teal in the legend.
  o.clip_colors.clear();
  save_map_plot(path, c, {0, 50}, o, 300);
  QImage own(QString::fromStdString(path));
  int none = 0;
  for (int y = static_cast<int>(d.bottom()) + 3; y < 300; ++y)
    for (int x = 0; x < 300; ++x) none += is_teal(own.pixelColor(x, y));
  EXPECT_EQ(none, 0);
}

TEST_F(MapPlotTest, ColourByCategoryDrawsEachSampleInItsValuesColourWithALegend) {
  // One clip of 100 samples along y = 0: the first 40 category 0, the next 40 category 2, the
  // last 20 "other" (−1).
  const Eigen::MatrixXd c = line(100, 0, 1, 0);
  MapPlotOptions o;
  o.line_width = 3.0;
  o.time_legend = true;
  o.point_category.assign(100, 0);
  for (int i = 40; i < 80; ++i) o.point_category[std::size_t(i)] = 2;
  for (int i = 80; i < 100; ++i) o.point_category[std::size_t(i)] = -1;
  o.categories = {"walk (40)", "run (0)", "bow (40)"};
  o.other_category = "other (20)";
  const std::string path = temp_file("by-category.png");
  save_map_plot(path, c, {}, o, 300);
  QImage img(QString::fromStdString(path));
  const QTransform t = map_transform(c, QRectF(0, 0, 300, 300), o);
  auto near_colour = [](QColor want) {
    return [want](QColor p) {
      return std::abs(p.red() - want.red()) + std::abs(p.green() - want.green()) +
                 std::abs(p.blue() - want.blue()) <
             30;
    };
  };
  // Twelve distinct colours, grey for "other".
  for (int a = 0; a < kCategoryColors; ++a) {
    for (int b = a + 1; b < kCategoryColors; ++b) EXPECT_NE(category_color(a), category_color(b));
  }
  EXPECT_EQ(category_color(-1), QColor(200, 200, 200));
  const double step = 1.0 / 99;
  EXPECT_TRUE(any_near(img, t.map(QPointF(20 * step, 0)), 1, near_colour(category_color(0))));
  EXPECT_FALSE(any_near(img, t.map(QPointF(20 * step, 0)), 1, near_colour(category_color(2))));
  EXPECT_TRUE(any_near(img, t.map(QPointF(60 * step, 0)), 1, near_colour(category_color(2))));
  EXPECT_TRUE(any_near(img, t.map(QPointF(90 * step, 0)), 1, near_colour(category_color(-1))));
  EXPECT_FALSE(any_near(img, t.map(QPointF(60 * step, 0)), 2, is_reddish));  // no time colours
  // The legend under the box: a swatch of each category's colour and of "other".
  const QRectF d = data_area(QRectF(0, 0, 300, 300), o);
  bool swatch[4] = {false, false, false, false};
  const QColor want[4] = {category_color(0), category_color(1), category_color(2),
                          category_color(-1)};
  for (int y = static_cast<int>(d.bottom()) + 3; y < 300; ++y) {
    for (int x = 0; x < 300; ++x) {
      for (int k = 0; k < 4; ++k)
        swatch[k] = swatch[k] || near_colour(want[k])(img.pixelColor(x, y));
    }
  }
  for (int k = 0; k < 4; ++k) EXPECT_TRUE(swatch[k]) << k;
  // One category per sample, or an error before anything is written.
  o.point_category.pop_back();
  EXPECT_THROW(save_map_plot(temp_file("bad-category.png"), c, {}, o, 300), ParameterError);
  EXPECT_FALSE(std::filesystem::exists(temp_file("bad-category.png")));
}

TEST_F(MapPlotTest, ABackdropIsDrawnUnderTheTrajectoryAndFramedWithIt) {
  // A short line in the middle of a wide backdrop (a saved map's samples under new frames).
  const Eigen::MatrixXd c = line(20, 0.4, 0.6, 0.5);
  MapPlotOptions o;
  o.line_width = 3.0;
  o.backdrop.resize(4, 2);
  o.backdrop << 0, 0, 1, 0, 0, 1, 1, 1;
  o.backdrop_color = QColor(0, 200, 0);
  const std::string path = temp_file("backdrop.png");
  save_map_plot(path, c, {}, o, 300);
  QImage img(QString::fromStdString(path));
  ASSERT_EQ(img.size(), QSize(300, 300));
  const QTransform t = map_transform(c, QRectF(0, 0, 300, 300), o);
  const QRectF d = data_area(QRectF(0, 0, 300, 300), o);
  // The backdrop's corners are the data area's: the extent covers it.
  EXPECT_NEAR(t.map(QPointF(0, 1)).x(), d.left(), 1e-9);
  EXPECT_NEAR(t.map(QPointF(1, 0)).y(), d.bottom(), 1e-9);
  auto green = [](QColor p) { return p.green() > 150 && p.red() < 60 && p.blue() < 60; };
  for (const auto& [x, y] : {std::pair{0.0, 0.0}, {1.0, 0.0}, {0.0, 1.0}, {1.0, 1.0}}) {
    EXPECT_TRUE(any_near(img, t.map(QPointF(x, y)), 1, green)) << x << "," << y;
  }
  EXPECT_TRUE(any_near(img, t.map(QPointF(0.44, 0.5)), 1, is_reddish));
  EXPECT_TRUE(any_near(img, t.map(QPointF(0.59, 0.5)), 1, is_bluish));
  // Without it, the line alone fills the panel.
  EXPECT_NEAR(map_transform(c, QRectF(0, 0, 300, 300), {}).map(QPointF(0.4, 0.5)).x(), d.left(),
              1e-9);
  // A backdrop needs x and y.
  o.backdrop.resize(3, 1);
  EXPECT_EQ(error_message<ParameterError>([&] { save_map_plot(path, c, {}, o, 300); }),
            "map plot: backdrop has 1 column(s); need at least 2 (x, y)");
}

TEST_F(MapPlotTest, DegenerateInputsStillProduceAnImage) {
  const QRectF rect(0, 0, 200, 200);
  MapPlotOptions o;
  o.title = "degenerate";
  o.draw_points = true;
  Eigen::MatrixXd nan_middle = arc(20);
  nan_middle.row(7).setConstant(kNaN);
  Eigen::MatrixXd noise(10, 2);  // one pose up to rounding: a point, not a stretched line
  for (int i = 0; i < 10; ++i) noise.row(i) << 5.0 + i * 1e-15, 0.0;
  const std::vector<Eigen::MatrixXd> inputs = {Eigen::MatrixXd(0, 2),
                                               Eigen::MatrixXd::Constant(1, 2, 3.0),
                                               Eigen::MatrixXd::Constant(10, 2, -2.5),
                                               Eigen::MatrixXd::Constant(10, 2, kNaN),
                                               nan_middle,
                                               noise};
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    const std::string path = temp_file("degenerate" + std::to_string(k) + ".png");
    ASSERT_NO_THROW(save_map_plot(path, inputs[k], {}, o, 200)) << k;
    QImage img(QString::fromStdString(path));
    ASSERT_EQ(img.size(), QSize(200, 200)) << k;
    const QRectF d = data_area(rect, o);
    // The frame is drawn in every case.
    EXPECT_FALSE(all_near(img, QPointF(d.center().x(), d.top() - d.width() * 0.05), 1, is_white))
        << k;
    if (k == 1 || k == 2 || k == 5) {  // one point: the marker in the middle of the data area
      EXPECT_TRUE(is_white(pixel_at(img, d.center()))) << k;
      EXPECT_TRUE(any_near(img, d.center(), 7, is_dark)) << k;
    }
    if (k == 5) {  // and no trajectory out to the sides
      EXPECT_TRUE(all_near(img, QPointF(d.left() + 10, d.center().y()), 3, is_white));
      EXPECT_TRUE(all_near(img, QPointF(d.right() - 10, d.center().y()), 3, is_white));
    }
  }
  // The NaN row splits the arc but the rest is drawn.
  const QTransform t = map_transform(nan_middle, rect, o);
  QImage img(QString::fromStdString(temp_file("degenerate4.png")));
  EXPECT_FALSE(all_near(img, t.map(QPointF(nan_middle(3, 0), nan_middle(3, 1))), 1, is_white));
}

TEST_F(MapPlotTest, PaintMapDrawsIntoAnyPainterInItsRect) {
  QImage img(300, 200, QImage::Format_RGB32);
  img.fill(Qt::black);
  {
    QPainter p(&img);
    paint_map(p, QRectF(100, 0, 200, 200), arc(40), {}, MapPlotOptions{});
  }
  EXPECT_EQ(img.pixelColor(50, 100), QColor(Qt::black)) << "outside the rect: untouched";
  EXPECT_TRUE(is_white(img.pixelColor(101, 1))) << "inside: background";
}

TEST_F(MapPlotTest, SvgAndPdfAreWritten) {
  MapPlotOptions o;
  o.title = "Circle";
  o.notes = {"a note"};
  o.time_legend = true;
  const std::string svg = temp_file("arc.svg");
  save_map_plot(svg, arc(100), {}, o, 300);
  const std::string text = read_all(svg);
  ASSERT_FALSE(text.empty());
  QXmlStreamReader xml(QByteArray::fromStdString(text));
  bool stroke = false, found_title = false;
  while (!xml.atEnd()) {
    xml.readNext();
    if (xml.isStartElement()) {
      stroke |= xml.name() == QStringLiteral("path") || xml.name() == QStringLiteral("polyline");
    }
    if (xml.isCharacters()) found_title |= xml.text().contains(QStringLiteral("Circle"));
  }
  EXPECT_FALSE(xml.hasError()) << xml.errorString().toStdString();
  EXPECT_TRUE(stroke);
  EXPECT_TRUE(found_title);

  const std::string pdf = temp_file("ARC.PDF");  // the extension is case-insensitive
  save_map_plot(pdf, arc(100), {}, o, 300);
  const std::string bytes = read_all(pdf);
  ASSERT_GT(bytes.size(), 500u);
  EXPECT_EQ(bytes.substr(0, 5), "%PDF-");
  // One square page, 300 px at 96 dpi = 225 pt.
  EXPECT_NE(bytes.find("/MediaBox [0 0 225.000000 225.000000]"), std::string::npos);
  EXPECT_NE(bytes.find("/Count 1"), std::string::npos);
}

TEST_F(MapPlotTest, FigureIsAGridOfPanels) {
  std::vector<FigurePanel> panels;
  for (int k = 0; k < 5; ++k) {
    FigurePanel p;
    p.coords = arc(60 + 10 * k, 1.0 + k);
    p.options.title = QString("method %1").arg(k);
    p.options.notes = {QString("metric %1").arg(k)};
    if (k == 2) p.options.notes.append("second line");
    panels.push_back(p);
  }
  const std::string path = temp_file("figure.png");
  save_figure(path, panels, 3, 200, "Six methods");
  QImage img(QString::fromStdString(path));
  ASSERT_FALSE(img.isNull());
  EXPECT_EQ(img.width(), 600);
  EXPECT_GT(img.height(), 400);
  EXPECT_LT(img.height(), 700);
  // Every panel drew its trajectory (saturated pixels) in its cell; the sixth cell is empty.
  const int cell_h = img.height() / 2;  // header is small; the rows split near the middle
  auto saturated_in = [&](int col, int row) {
    for (int y = row * cell_h + 40; y < (row + 1) * cell_h; ++y) {
      for (int x = col * 200; x < (col + 1) * 200; ++x) {
        const QColor p = img.pixelColor(x, y);
        if (std::max({p.red(), p.green(), p.blue()}) - std::min({p.red(), p.green(), p.blue()}) >
            200)
          return true;
      }
    }
    return false;
  };
  for (int k = 0; k < 5; ++k) EXPECT_TRUE(saturated_in(k % 3, k / 3)) << k;
  EXPECT_FALSE(saturated_in(2, 1));

  const std::string svg = temp_file("figure.svg");
  save_figure(svg, panels, 2, 150);
  EXPECT_NE(read_all(svg).find("<svg"), std::string::npos);
}

// --- errors -----------------------------------------------------------------------------------

TEST_F(MapPlotTest, UnknownExtensionNamesThePath) {
  const std::string bmp = temp_file("plot.bmp");
  EXPECT_EQ(error_message<Error>([&] { save_map_plot(bmp, arc(10), {}, {}); }),
            "cannot write '" + bmp + "': unknown extension '.bmp' (expected .png, .svg or .pdf)");
  EXPECT_FALSE(std::filesystem::exists(bmp));
  const std::string none = temp_file("plot");
  EXPECT_EQ(error_message<Error>([&] {
              save_figure(none, {FigurePanel{arc(10), {}, {}}});
            }),
            "cannot write '" + none + "': no file extension (expected .png, .svg or .pdf)");
}

TEST_F(MapPlotTest, WriteFailureNamesThePath) {
  for (const std::string ext : {".png", ".svg", ".pdf"}) {
    const std::string path = "/nonexistent-motionmap-dir/plot" + ext;
    const std::string msg = error_message<Error>([&] { save_map_plot(path, arc(10), {}, {}); });
    EXPECT_EQ(msg.rfind("cannot write '" + path + "': ", 0), 0u) << msg;
    EXPECT_GT(msg.size(), ("cannot write '" + path + "': ").size()) << "a reason follows";
  }
}

TEST_F(MapPlotTest, BadSizesAndDataAreParameterErrors) {
  const std::string png = temp_file("bad.png");
  EXPECT_EQ(error_message<ParameterError>([&] { save_map_plot(png, arc(10), {}, {}, 8); }),
            "save_map_plot: size_px = 8 is outside [16, 16384]");
  EXPECT_EQ(error_message<ParameterError>([&] { save_map_plot(png, arc(10), {20}, {}); }),
            "map plot: segment_starts[0] = 20 is outside [0, 10)");
  EXPECT_FALSE(std::filesystem::exists(png)) << "nothing written for invalid input";
  EXPECT_EQ(error_message<ParameterError>([&] { save_figure(png, {}); }), "save_figure: no panels");
  const std::vector<FigurePanel> one{FigurePanel{arc(10), {}, {}}};
  EXPECT_EQ(error_message<ParameterError>([&] { save_figure(png, one, 0); }),
            "save_figure: columns = 0 is outside [1, 64]");
  EXPECT_EQ(error_message<ParameterError>([&] { save_figure(png, one, 3, 10); }),
            "save_figure: panel_px = 10 is outside [64, 4096]");
  const std::vector<FigurePanel> many(400, one[0]);
  EXPECT_EQ(error_message<ParameterError>([&] {
              save_figure(png, many, 1, 4096);
            }).rfind("save_figure: the figure would be 4096x", 0),
            0u);
  const std::vector<FigurePanel> bad{FigurePanel{Eigen::MatrixXd(3, 1), {}, {}}};
  EXPECT_EQ(error_message<ParameterError>([&] { save_figure(png, bad); }),
            "map plot: coords has 1 column(s); need at least 2 (x, y)");
  EXPECT_FALSE(std::filesystem::exists(png));
}

TEST_F(MapPlotTest, DrawingLeavesTheApplicationAndTheProcessAlone) {
  const auto current_handler = [] {
    const QtMessageHandler h = qInstallMessageHandler(nullptr);
    qInstallMessageHandler(h);
    return h;
  };
  QCoreApplication* const app = QCoreApplication::instance();
  const QByteArray platform = qgetenv("QT_QPA_PLATFORM");
  const QtMessageHandler handler = current_handler();
  save_map_plot(temp_file("alone.png"), arc(10), {}, {});
  save_figure(temp_file("alone.svg"), {FigurePanel{arc(10), {}, {}}});
  EXPECT_EQ(QCoreApplication::instance(), app);
  EXPECT_EQ(qgetenv("QT_QPA_PLATFORM"), platform);
  EXPECT_EQ(current_handler(), handler) << "no message handler installed";
}

// Runs in a child process without the test main's QGuiApplication (see render_test_main.cpp):
// with `core_app`, a plain QCoreApplication exists. Draws each way the library offers and exits
// 3 after printing each error, in order, when all three refused and nothing was written.
[[noreturn]] void draw_without_gui_application(bool core_app) {
  static int argc = 1;
  static char name[] = "render_test";
  static char* argv[] = {name, nullptr};
  std::unique_ptr<QCoreApplication> app;
  if (core_app) app = std::make_unique<QCoreApplication>(argc, argv);
  const std::string png = temp_file(core_app ? "core_app.png" : "no_app.png");
  std::filesystem::remove(png);
  int refused = 0;
  const auto attempt = [&](const std::function<void()>& draw) {
    try {
      draw();
    } catch (const Error& e) {
      std::fprintf(stderr, "%s\n", e.what());
      ++refused;
    }
  };
  attempt([&] { save_map_plot(png, arc(10), {}, {}); });
  attempt([&] { save_figure(png, {FigurePanel{arc(10), {}, {}}}); });
  QImage image(64, 64, QImage::Format_RGB32);
  attempt([&] {
    QPainter painter(&image);
    paint_map(painter, QRectF(0, 0, 64, 64), arc(10), {}, {});
  });
  std::exit(refused == 3 && !std::filesystem::exists(png) ? 3 : 1);
}

// Drawing needs the caller's QGuiApplication; without one the library throws, never creates one.
TEST(RenderDeathTest, NoApplicationIsReported) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");  // a fresh process, re-executed
  qputenv("MOTIONMAP_RENDER_TESTS_NO_APP", "1");
  EXPECT_EXIT(draw_without_gui_application(false), ::testing::ExitedWithCode(3),
              "save_map_plot: no QGuiApplication exists; create one before drawing .the render "
              "library draws into what it is given and never creates the application.\n"
              "save_figure: no QGuiApplication exists.*\n"
              "paint_map: no QGuiApplication exists");
  qunsetenv("MOTIONMAP_RENDER_TESTS_NO_APP");
}

TEST(RenderDeathTest, PlainCoreApplicationIsReported) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  qputenv("MOTIONMAP_RENDER_TESTS_NO_APP", "1");
  EXPECT_EXIT(draw_without_gui_application(true), ::testing::ExitedWithCode(3),
              "save_map_plot: a QCoreApplication exists, but drawing needs a QGuiApplication "
              ".create one instead.\n"
              "save_figure: a QCoreApplication exists.*\n"
              "paint_map: a QCoreApplication exists");
  qunsetenv("MOTIONMAP_RENDER_TESTS_NO_APP");
}

}  // namespace
}  // namespace motionmap::render
