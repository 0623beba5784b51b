// render::ReachField and reach_image: the shading of where a map point is within reach of a
// sample, checked pixel by pixel against the disc rule evaluated by brute force at every pixel
// centre, at the whole map and zoomed, with coarse and fine grids.
#include "motionmap/render/reach_shading.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "motionmap/core/error.h"

namespace motionmap::render {
namespace {

/// Clustered points: three blobs and a thin arc, and a NaN row (left out).
Eigen::MatrixXd clusteredPoints(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Eigen::MatrixXd xy(n + 1, 3);
  const double cx[3] = {-3.0, 2.0, 0.5}, cy[3] = {1.0, 2.5, -2.0}, s[3] = {0.6, 0.3, 0.9};
  for (int i = 0; i < n; ++i) {
    if (i % 4 == 3) {
      const double t = 3.0 * u(rng);
      xy.row(i) << 4.0 * std::cos(t), 4.0 * std::sin(t) - 1.0, 0.0;
    } else {
      const int b = i % 4;
      xy.row(i) << cx[b] + s[b] * g(rng), cy[b] + s[b] * g(rng), 0.0;
    }
  }
  xy.row(n) << std::nan(""), 0.0, 0.0;
  return xy;
}

bool bruteWithin(const Eigen::MatrixXd& xy, const Eigen::Vector2d& p, double reach) {
  for (Eigen::Index i = 0; i < xy.rows(); ++i) {
    if (!std::isfinite(xy(i, 0))) continue;
    if ((Eigen::Vector2d(xy(i, 0), xy(i, 1)) - p).norm() <= reach) return true;
  }
  return false;
}

struct Count {
  int shaded = 0, asked = 0, disagree = 0, pixels = 0;
};

/// Every pixel of `size` against the brute-force rule at its centre.
Count compare(const Eigen::MatrixXd& xy, double reach, int cells, const QTransform& toMap,
              const QSize& size) {
  const ReachField field(xy, reach, cells);
  Count count;
  const QImage image =
      reach_image(field, toMap, size, QColor(30, 170, 70), [&](const Eigen::Vector2d& p) {
        ++count.asked;
        return bruteWithin(xy, p, reach);
      });
  for (int y = 0; y < size.height(); ++y) {
    for (int x = 0; x < size.width(); ++x) {
      const QPointF p = toMap.map(QPointF(x + 0.5, y + 0.5));
      const bool want = bruteWithin(xy, Eigen::Vector2d(p.x(), p.y()), reach);
      const bool got = qAlpha(image.pixel(x, y)) != 0;
      count.shaded += got;
      count.disagree += got != want;
      ++count.pixels;
    }
  }
  return count;
}

/// Pixel → map of a view of `side` px showing the square [c − half, c + half]² (y up).
QTransform view(double cx, double cy, double half, int side) {
  const double s = 2.0 * half / side;
  return QTransform(s, 0, 0, -s, cx - half, cy + half);
}

TEST(ReachShading, EqualsTheDiscRuleAtEveryPixelCentre) {
  const Eigen::MatrixXd xy = clusteredPoints(600, 1);
  const double reach = 0.45;
  const QSize size(120, 120);
  struct Case {
    const char* name;
    QTransform toMap;
    int cells;
  };
  const Case cases[] = {
      {"whole map, fine grid", view(0.0, 0.0, 6.0, 120), 2048},
      {"whole map, coarse grid", view(0.0, 0.0, 6.0, 120), 24},
      {"zoomed 8x on a blob's edge", view(-4.4, 1.0, 0.75, 120), 256},
      {"zoomed 40x on the arc's edge", view(4.3, -1.0, 0.15, 120), 512},
      {"panned off the data", view(20.0, 20.0, 6.0, 120), 256},
  };
  for (const Case& c : cases) {
    const Count count = compare(xy, reach, c.cells, c.toMap, size);
    std::printf("%s: %d of %d pixels shaded, %d asked, %d disagree\n", c.name, count.shaded,
                count.pixels, count.asked, count.disagree);
    EXPECT_EQ(count.disagree, 0) << c.name;
  }
  // The field decides most pixels: the exact test is asked only along the edge.
  const Count fine = compare(xy, reach, 2048, view(0.0, 0.0, 6.0, 120), size);
  EXPECT_GT(fine.shaded, fine.pixels / 10);
  EXPECT_LT(fine.shaded, fine.pixels * 9 / 10);
  EXPECT_LT(fine.asked, fine.pixels / 10);
}

TEST(ReachShading, AClipLimitsTheShadedPixels) {
  const Eigen::MatrixXd xy = clusteredPoints(200, 2);
  const ReachField field(xy, 1.0, 256);
  const QRect clip(10, 20, 50, 40);
  const QImage image = reach_image(
      field, view(0.0, 0.0, 6.0, 100), QSize(100, 100), Qt::green,
      [&](const Eigen::Vector2d& p) { return bruteWithin(xy, p, 1.0); }, clip);
  int inside = 0, outside = 0;
  for (int y = 0; y < 100; ++y)
    for (int x = 0; x < 100; ++x)
      (clip.contains(x, y) ? inside : outside) += qAlpha(image.pixel(x, y)) != 0;
  EXPECT_GT(inside, 0);
  EXPECT_EQ(outside, 0);
}

TEST(ReachShading, EmptyAndBadInput) {
  const Eigen::MatrixXd none(0, 2);
  const ReachField empty(none, 1.0);
  EXPECT_TRUE(empty.empty());
  EXPECT_EQ(empty.side(0.0, 0.0), ReachField::Side::Outside);
  Eigen::MatrixXd one(1, 2);
  one << 1.0, 2.0;
  EXPECT_TRUE(ReachField(one, 0.0).empty());
  EXPECT_TRUE(ReachField(one, std::nan("")).empty());
  const ReachField single(one, 0.5, 64);
  ASSERT_FALSE(single.empty());
  EXPECT_EQ(single.side(1.0, 2.0), ReachField::Side::Inside);
  EXPECT_EQ(single.side(1.0, 3.0), ReachField::Side::Outside);
  EXPECT_EQ(single.side(100.0, 2.0), ReachField::Side::Outside);
  Eigen::MatrixXd huge(2, 2);
  huge << -1e308, 0.0, 1e308, 0.0;
  EXPECT_TRUE(ReachField(huge, 1.0).empty());
  EXPECT_THROW(ReachField(Eigen::MatrixXd(3, 1), 1.0), ParameterError);
  EXPECT_THROW(ReachField(one, 1.0, 8), ParameterError);
  const QImage blank = reach_image(empty, QTransform(), QSize(8, 8), Qt::green,
                                   [](const Eigen::Vector2d&) { return true; });
  EXPECT_EQ(blank.size(), QSize(8, 8));
  EXPECT_EQ(qAlpha(blank.pixel(3, 3)), 0);
}

// A level field (a GP-LVM map's variance in Studio): its cells sure on their corners, level()
// exact at the corners and for a bilinear function everywhere, and reach_image over it, with
// level() deciding the unsure cells, as the threshold says at all but the pixels beside the edge.
TEST(ReachShading, ALevelFieldDecidesFromItsCornersAndInterpolatesBetween) {
  // A bowl: inside the unit circle.
  const auto bowl = [](const Eigen::Vector2d& p) { return p.squaredNorm(); };
  const ReachField f =
      ReachField::level_set(Eigen::Vector2d(-2, -2), Eigen::Vector2d(2, 2), 64, bowl, 1.0, 0.25);
  EXPECT_EQ(f.nx(), 64);
  EXPECT_DOUBLE_EQ(f.reach(), 1.0);
  EXPECT_EQ(f.side(0.01, 0.02), ReachField::Side::Inside);
  EXPECT_EQ(f.side(1.9, 1.9), ReachField::Side::Outside);
  EXPECT_EQ(f.side(0.0, 0.999), ReachField::Side::Unsure);
  EXPECT_EQ(f.side(3.0, 0.0), ReachField::Side::Outside);  // off the grid
  EXPECT_DOUBLE_EQ(f.level(-2.0 + 10 * f.cell(), -2.0 + 7 * f.cell()),
                   bowl(Eigen::Vector2d(-2.0 + 10 * f.cell(), -2.0 + 7 * f.cell())));
  EXPECT_TRUE(std::isinf(f.level(3.0, 0.0)));
  const auto plane = [](const Eigen::Vector2d& p) {
    return 2 * p.x() - p.y() + 0.5 * p.x() * p.y();
  };
  const ReachField g =
      ReachField::level_set(Eigen::Vector2d(-1, -1), Eigen::Vector2d(1, 1), 16, plane, 0.0, 0.1);
  std::mt19937 random(4);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int t = 0; t < 100; ++t) {
    const Eigen::Vector2d p(u(random), u(random));
    EXPECT_NEAR(g.level(p.x(), p.y()), plane(p), 1e-12);
  }
  // The image of the bowl's field at 200 × 200 pixels over [−2, 2]²: pixels decided by the
  // corners and the interpolation, against the circle, differ only within a cell of the edge.
  const QTransform to_map = QTransform::fromScale(0.02, 0.02) * QTransform::fromTranslate(-2, -2);
  const QImage image =
      reach_image(f, to_map, QSize(200, 200), Qt::green,
                  [&](const Eigen::Vector2d& p) { return f.level(p.x(), p.y()) <= 1.0; });
  int inside = 0;
  for (int j = 0; j < 200; ++j) {
    for (int i = 0; i < 200; ++i) {
      const QPointF m = to_map.map(QPointF(i + 0.5, j + 0.5));
      const double r = std::hypot(m.x(), m.y());
      const bool shaded = qAlpha(image.pixel(i, j)) != 0;
      inside += shaded;
      if (std::abs(r - 1.0) > f.cell()) {
        EXPECT_EQ(shaded, r <= 1.0) << i << " " << j;
      }
    }
  }
  EXPECT_NEAR(inside, 3.14159 * 50 * 50, 60);
  EXPECT_THROW(ReachField::level_set(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1), 8, bowl, 1, 0),
               ParameterError);
  EXPECT_THROW(ReachField::level_set(Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1), 16, bowl, 1, 1),
               ParameterError);
}

}  // namespace
}  // namespace motionmap::render
