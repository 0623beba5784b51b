// Routes through the clips' own frames (route.h, find_clip_route).
#include <algorithm>
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "motionmap/core/error.h"
#include "motionmap/synth/route.h"
#include "support/error_message.h"

namespace motionmap::synth {
namespace {

// Two clips on a line, 0.1 apart per sample: clip A along y = 0 from x = 0 to 3, clip B along
// y = 0.05 from x = 2 to 5 (its samples between A's), so A's tail and B's head overlap.
struct TwoClips {
  std::vector<Eigen::Vector2d> points;
  std::vector<int> next;
  int a_first = 0, b_first = 0;

  TwoClips() {
    for (int i = 0; i <= 30; ++i) points.emplace_back(0.1 * i, 0.0);
    b_first = static_cast<int>(points.size());
    for (int i = 0; i <= 30; ++i) points.emplace_back(2.0 + 0.1 * i + 0.05, 0.05);
    next.assign(points.size(), -1);
    for (int i = 0; i < 30; ++i) {
      next[static_cast<std::size_t>(a_first + i)] = a_first + i + 1;
      next[static_cast<std::size_t>(b_first + i)] = b_first + i + 1;
    }
  }
};

TEST(SynthClipRoute, FollowsAClipAtItsOwnPaceForFree) {
  const TwoClips c;
  const MapField field(c.points, 0.3);
  const ClipRoute r = find_clip_route(field, c.next, c.points[5], c.points[25], 20);
  ASSERT_EQ(r.samples.size(), 21u);
  for (int t = 0; t <= 20; ++t) EXPECT_EQ(r.samples[t], 5 + t) << t;
  EXPECT_EQ(r.cost, 0.0);
}

TEST(SynthClipRoute, HoldsOrSkipsToLandOnTime) {
  const TwoClips c;
  // A reach of one sample's spacing: ending a sample off costs more than a skip or a hold.
  const MapField field(c.points, 0.1);
  for (const int steps : {15, 25}) {
    const ClipRoute r = find_clip_route(field, c.next, c.points[5], c.points[25], steps);
    ASSERT_EQ(r.samples.size(), static_cast<std::size_t>(steps) + 1);
    EXPECT_EQ(r.samples.front(), 5);
    EXPECT_EQ(r.samples.back(), 25);
    // 5 skips (or holds), each at its cost, and nothing else.
    EXPECT_NEAR(r.cost, 5 * ClipRouteCosts{}.skip, 1e-12) << steps;
    for (int t = 1; t <= steps; ++t) {
      const int d = r.samples[t] - r.samples[t - 1];
      EXPECT_TRUE(d >= 0 && d <= 2) << "step " << t << ": " << d;
    }
  }
}

TEST(SynthClipRoute, JumpsBetweenClipsWhereTheyMeet) {
  const TwoClips c;
  const MapField field(c.points, 0.3);
  // From A's sample 5 to B's sample 25 (x = 4.55): 40 steps along the data, one jump.
  const ClipRoute r = find_clip_route(field, c.next, c.points[5], c.points[c.b_first + 25], 40);
  EXPECT_EQ(r.samples.front(), 5);
  EXPECT_EQ(r.samples.back(), c.b_first + 25);
  int jumps = 0;
  for (std::size_t t = 1; t < r.samples.size(); ++t) {
    const int from = r.samples[t - 1], to = r.samples[t];
    if (to == from || to == c.next[from] || (c.next[from] >= 0 && to == c.next[c.next[from]]))
      continue;
    ++jumps;
    EXPECT_LE((c.points[to] - c.points[c.next[from] >= 0 ? c.next[from] : from]).norm(), 0.3);
  }
  EXPECT_EQ(jumps, 1);
}

TEST(SynthClipRoute, EndCostsChooseAmongTheNearestSamplesAndAStartIsKept) {
  const TwoClips c;
  const MapField field(c.points, 0.3);
  ClipRouteEnds ends;
  // Ending on B's sample 8 (x = 2.85) is made dear: the route ends on another sample near b.
  ends.end_cost = [&](int s) { return s == c.b_first + 8 ? 100.0 : 0.0; };
  const ClipRoute r =
      find_clip_route(field, c.next, c.points[5], c.points[c.b_first + 8], 24, ends);
  EXPECT_NE(r.samples.back(), c.b_first + 8);
  EXPECT_LE((c.points[r.samples.back()] - c.points[c.b_first + 8]).norm(), 0.3);
  ends = {};
  ends.start = 7;
  EXPECT_EQ(find_clip_route(field, c.next, c.points[5], c.points[20], 13, ends).samples.front(), 7);
}

TEST(SynthClipRoute, FurtherEndsAreTakenOnlyWhereCheaperThanEveryNearOne) {
  // The end b is A's sample 25 (x = 2.5); the 16 samples nearest it cost 2 each beyond their
  // distance (a pose unlike the key's), the others 100 but A's sample 12 (x = 1.2, 1.3 away:
  // 1.69), where the route from A's sample 5 lands in 7 steps for free.
  const TwoClips c;
  const MapField field(c.points, 1.0);
  const int far = 12;
  std::vector<int> nearest;
  field.nearest(c.points[25], kClipRouteEnds, nearest);
  const auto near_b = [&](int s) {
    return std::find(nearest.begin(), nearest.end(), s) != nearest.end();
  };
  ClipRouteEnds ends;
  ends.candidates = static_cast<int>(c.points.size());
  for (const double far_cost : {0.0, 0.5}) {
    ends.end_cost = [&](int s) { return s == far ? far_cost : near_b(s) ? 2.0 : 100.0; };
    const ClipRoute r = find_clip_route(field, c.next, c.points[5], c.points[25], 7, ends);
    if (far_cost == 0.0) {
      // 1.69 < 2: it beats every near end, so the route ends on it.
      EXPECT_EQ(r.samples.back(), far);
      EXPECT_NEAR(r.cost, 1.69, 1e-9);
    } else {
      // 2.19 > 2: not a candidate, though the route to it would be cheaper in all.
      EXPECT_TRUE(near_b(r.samples.back())) << r.samples.back();
    }
  }
  // The default: the nearest 16 only.
  ends.candidates = kClipRouteEnds;
  ends.end_cost = [&](int s) { return s == far ? 0.0 : near_b(s) ? 2.0 : 100.0; };
  EXPECT_TRUE(
      near_b(find_clip_route(field, c.next, c.points[5], c.points[25], 7, ends).samples.back()));
}

// Two clips the map's jumps do not join: A along y = 0 from x = 0 to 3, B along y = 10.
struct ApartClips {
  std::vector<Eigen::Vector2d> points;
  std::vector<int> next;
  int b_first = 0;

  ApartClips() {
    for (int i = 0; i <= 30; ++i) points.emplace_back(0.1 * i, 0.0);
    b_first = static_cast<int>(points.size());
    for (int i = 0; i <= 30; ++i) points.emplace_back(0.1 * i, 10.0);
    next.assign(points.size(), -1);
    for (int i = 0; i < 30; ++i) {
      next[static_cast<std::size_t>(i)] = i + 1;
      next[static_cast<std::size_t>(b_first + i)] = b_first + i + 1;
    }
  }
};

TEST(SynthClipRoute, KeysNoJumpJoinsAreBridged) {
  const ApartClips c;
  const MapField field(c.points, 0.3);
  // From A's sample 5 to B's sample 20 in 10 steps: without the bridge the route ends on the A
  // sample nearest B's 20 (A's 20, under it, reached by skips).
  const ClipRoute plain = find_clip_route(field, c.next, c.points[5], c.points[c.b_first + 20], 10);
  EXPECT_LT(plain.samples.back(), c.b_first);
  ClipRouteEnds ends;
  ends.bridge_jump_cost = [](int, int) { return 0.0; };
  const ClipRoute r =
      find_clip_route(field, c.next, c.points[5], c.points[c.b_first + 20], 10, ends);
  const std::vector<int> want{5,
                              6,
                              7,
                              8,
                              9,
                              10,
                              c.b_first + 16,
                              c.b_first + 17,
                              c.b_first + 18,
                              c.b_first + 19,
                              c.b_first + 20};
  EXPECT_EQ(r.samples, want);
  EXPECT_NEAR(r.cost, ClipRouteCosts{}.jump, 1e-12);
  // Near B's start, B's part holds its first sample for the steps before it.
  const ClipRoute held =
      find_clip_route(field, c.next, c.points[5], c.points[c.b_first + 2], 10, ends);
  EXPECT_EQ(held.samples[6], c.b_first);
  EXPECT_EQ(held.samples[7], c.b_first);
  EXPECT_EQ(held.samples[8], c.b_first);
  EXPECT_EQ(held.samples.back(), c.b_first + 2);
  EXPECT_NEAR(held.cost, ClipRouteCosts{}.jump + 2 * ClipRouteCosts{}.hold, 1e-12);
}

TEST(SynthClipRoute, BadInputsAreRefused) {
  const TwoClips c;
  const MapField field(c.points, 0.3);
  const auto message = [](const std::function<void()>& f) {
    return test::error_message<ParameterError>(f);
  };
  EXPECT_NE(message([&] {
              find_clip_route(field, std::vector<int>{1, 2}, c.points[0], c.points[1], 3);
            }).find("2 successors for 62 samples"),
            std::string::npos);
  std::vector<int> bad = c.next;
  bad[3] = 99;
  EXPECT_NE(message([&] {
              find_clip_route(field, bad, c.points[0], c.points[1], 3);
            }).find("sample 3's successor 99 is out of range"),
            std::string::npos);
  EXPECT_NE(message([&] {
              find_clip_route(field, c.next, c.points[0], c.points[1], 0);
            }).find("0 steps is out of range"),
            std::string::npos);
  EXPECT_NE(message([&] {
              find_clip_route(field, c.next, {NAN, 0.0}, c.points[1], 3);
            }).find("not finite"),
            std::string::npos);
  ClipRouteEnds ends;
  ends.candidates = 0;
  EXPECT_NE(message([&] {
              find_clip_route(field, c.next, c.points[0], c.points[1], 3, ends);
            }).find("0 candidate ends (must be at least 1)"),
            std::string::npos);
  ends.candidates = kClipRouteEnds;
  ends.start = 62;
  EXPECT_NE(message([&] {
              find_clip_route(field, c.next, c.points[0], c.points[1], 3, ends);
            }).find("start sample 62 is out of range"),
            std::string::npos);
  EXPECT_EQ(parse_route_mode("grid"), RouteMode::Grid);
  EXPECT_EQ(std::string(route_mode_name(parse_route_mode("clips"))), "clips");
  EXPECT_NE(message([] { parse_route_mode("fast"); }).find("'fast' is not a route (clips or grid)"),
            std::string::npos);
}

}  // namespace
}  // namespace motionmap::synth
