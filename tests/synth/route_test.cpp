#include "motionmap/synth/route.h"

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "motionmap/core/error.h"
#include "support/error_message.h"

namespace motionmap::synth {
namespace {

// Samples along a U: down the left arm, round the bottom, up the right arm; the arms 4 apart, so
// the straight line between the tips crosses a gap far wider than the reach.
std::vector<Eigen::Vector2d> u_shape(double step = 0.05) {
  std::vector<Eigen::Vector2d> p;
  for (double y = 6.0; y > 0.0; y -= step) p.emplace_back(-2.0, y);
  const int arc = static_cast<int>(std::ceil(std::numbers::pi * 2.0 / step));
  for (int i = 0; i <= arc; ++i) {
    const double a = std::numbers::pi + std::numbers::pi * i / arc;
    p.emplace_back(2.0 * std::cos(a), 2.0 * std::sin(a));
  }
  for (double y = step; y <= 6.0; y += step) p.emplace_back(2.0, y);
  return p;
}

// Every point of the polyline, at steps of r/50, is valid.
void expect_inside(const MapField& field, const std::vector<Eigen::Vector2d>& route) {
  for (std::size_t i = 1; i < route.size(); ++i) {
    const double len = (route[i] - route[i - 1]).norm();
    const int steps = std::max(1, static_cast<int>(std::ceil(len * 50 / field.reach_distance())));
    for (int s = 0; s <= steps; ++s) {
      const double t = static_cast<double>(s) / steps;
      const Eigen::Vector2d p = (1 - t) * route[i - 1] + t * route[i];
      ASSERT_LE(field.distance(p), field.reach_distance()) << "segment " << i << " t " << t;
    }
  }
}

TEST(SynthRoute, CostGrowsWithTheDistanceToTheDataAndIsInfiniteOutside) {
  const MapField field({{0.0, 0.0}, {1.0, 0.0}}, 0.5);
  EXPECT_EQ(field.cost({0, 0}), 1.0);
  EXPECT_DOUBLE_EQ(field.cost({0, 0.25}), 1.0 + kRoutePenalty * 0.25);
  EXPECT_DOUBLE_EQ(field.cost({1, 0.5}), 1.0 + kRoutePenalty);
  EXPECT_TRUE(std::isinf(field.cost({0.5, 0.6})));
  EXPECT_TRUE(field.valid({0.2, 0.4}));
  EXPECT_FALSE(field.valid({0.5, 0.6}));
  EXPECT_TRUE(field.segment_valid({0, 0}, {1, 0}));
  EXPECT_FALSE(field.segment_valid({0, 0.45}, {1, 0.45}));  // its middle is 0.67 from both
}

TEST(SynthRoute, GridResolutionFollowsTheDensityWithinItsBounds) {
  const MapField field(u_shape(), 0.15);
  const RouteGrid g = make_grid(field);
  // The box is 4.3 × 8.3 (the U grown by the reach): r/2 = 0.075 would be 111 cells along y.
  EXPECT_EQ(g.ny, 111);
  EXPECT_NEAR(g.cell, 8.3 / 111, 1e-12);
  EXPECT_EQ(make_grid(MapField(u_shape(), 0.01)).ny, kMaxGridCells);
  EXPECT_EQ(make_grid(MapField(u_shape(), 2.0)).ny, kMinGridCells);
  const RouteGrid forty = make_grid(field, {.grid = 40, .smooth = true, .cross_gaps = true});
  EXPECT_EQ(forty.ny, 40);
  EXPECT_EQ(forty.nx, static_cast<int>(std::ceil(4.3 / (8.3 / 40))));
  EXPECT_EQ(motionmap::test::error_message<ParameterError>(
                [&] { make_grid(field, {.grid = 1, .smooth = true, .cross_gaps = true}); }),
            "grid: 1 cells is out of range (must be 0 = from the map's density, or in [2, 2000])");
}

TEST(SynthRoute, GoesRoundTheGapAndHitsItsEnds) {
  const MapField field(u_shape(), 0.15);
  const Eigen::Vector2d a(-2.0, 5.5), b(2.0, 5.5);
  for (const int grid : {0, 20, 40, 200}) {
    for (const bool smooth : {false, true}) {
      SCOPED_TRACE(testing::Message() << "grid " << grid << " smooth " << smooth);
      const RouteOptions opt{.grid = grid, .smooth = smooth, .cross_gaps = true};
      const auto route = find_route(field, make_grid(field, opt), a, b, opt);
      ASSERT_GE(route.size(), 3u);
      EXPECT_EQ(route.front(), a);
      EXPECT_EQ(route.back(), b);
      expect_inside(field, route);
      // Down one arm, round the bottom and up the other: at least 2·5.5 + 2π·1 long (the inner
      // edge of the valid band, radius 2 − r).
      EXPECT_GT(polyline_length(route), 2 * 5.0 + std::numbers::pi * (2.0 - 0.15));
      double lowest = 10;
      for (const auto& p : route) lowest = std::min(lowest, p.y());
      EXPECT_LT(lowest, -1.5);
    }
  }
}

TEST(SynthRoute, SmoothingShortensTheGridRouteWithoutLeavingTheData) {
  const MapField field(u_shape(), 0.15);
  const RouteGrid g = make_grid(field);
  const Eigen::Vector2d a(-2.0, 5.5), b(2.0, 5.5);
  const auto raw = find_route(field, g, a, b, {.grid = 0, .smooth = false, .cross_gaps = true});
  const auto smooth = find_route(field, g, a, b, {.grid = 0, .smooth = true, .cross_gaps = true});
  EXPECT_LT(polyline_length(smooth), polyline_length(raw));
  EXPECT_LT(smooth.size(), raw.size() * 3);
  expect_inside(field, smooth);
}

TEST(SynthRoute, StaysNearTheDataWhereItCan) {
  // A straight line of samples: the route between two points on it runs along it.
  std::vector<Eigen::Vector2d> line;
  for (int i = 0; i <= 200; ++i) line.emplace_back(0.05 * i, 0.0);
  const MapField field(line, 0.5);
  const RouteGrid g = make_grid(field);
  const auto route = find_route(field, g, {0.5, 0.0}, {9.5, 0.0});
  for (const auto& p : route) EXPECT_LE(std::abs(p.y()), 0.1 * g.cell + 1e-12) << p.transpose();
}

TEST(SynthRoute, AKeyOutsideTheDataJoinsItByAStraightStretch) {
  const MapField field(u_shape(), 0.15);
  const RouteGrid g = make_grid(field);
  const Eigen::Vector2d outside(0.0, 5.0), b(2.0, 5.5);
  const auto route = find_route(field, g, outside, b);
  EXPECT_EQ(route.front(), outside);
  EXPECT_EQ(route.back(), b);
  // Only the start, up to where it reaches the data, is outside.
  std::size_t first_inside = 0;
  while (first_inside < route.size() && !field.valid(route[first_inside])) ++first_inside;
  ASSERT_LT(first_inside, route.size());
  expect_inside(field, std::vector<Eigen::Vector2d>(route.begin() + first_inside, route.end()));
}

TEST(SynthRoute, AcrossACutInTheDataItCrossesTheGapOrFails) {
  std::vector<Eigen::Vector2d> two;
  for (int i = 0; i <= 20; ++i) two.emplace_back(0.05 * i, 0.0);
  for (int i = 0; i <= 20; ++i) two.emplace_back(5.0 + 0.05 * i, 0.0);
  const MapField field(two, 0.2);
  const RouteGrid g = make_grid(field);
  // By default the route crosses the gap, straight (the cheapest way), and is valid elsewhere.
  const Eigen::Vector2d a(0.5, 0.0), b(5.5, 0.0);
  const auto route = find_route(field, g, a, b);
  EXPECT_EQ(route.front(), a);
  EXPECT_EQ(route.back(), b);
  for (const auto& p : route) {
    EXPECT_LE(std::abs(p.y()), 0.6 * g.cell) << p.transpose();
    if (!field.valid(p)) {
      EXPECT_TRUE(p.x() > 1.0 + 0.2 && p.x() < 5.0 - 0.2) << p.transpose();
    }
  }
  EXPECT_LT(polyline_length(route), 5.0 * 1.05);
  // Without crossing gaps, an error saying why.
  const std::string message = motionmap::test::error_message<ParameterError>(
      [&] { find_route(field, g, a, b, {.grid = 0, .smooth = true, .cross_gaps = false}); });
  EXPECT_NE(message.find("no route through the valid region joins the map points 0.5,0 and 5.5,0"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("--reach"), std::string::npos) << message;
}

TEST(SynthRoute, BadInputs) {
  EXPECT_THROW(MapField({}, 1.0), ParameterError);
  EXPECT_THROW(MapField({{0.0, 0.0}}, 0.0), ParameterError);
  const MapField field({{0.0, 0.0}, {1.0, 0.0}}, 0.5);
  EXPECT_THROW(find_route(field, make_grid(field), {NAN, 0}, {1, 0}), ParameterError);
}

}  // namespace
}  // namespace motionmap::synth
