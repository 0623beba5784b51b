// Key poses: the rule's choice against brute force over every choice, exact cases, the
// interpolation and its error measure on constructed motions, and real clips where the key poses
// rebuild the motion better than evenly spaced frames.
#include "motionmap/pipeline/key_poses.h"

#include <cmath>
#include <functional>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "motionmap/core/error.h"
#include "motionmap/io/load.h"
#include "support/error_message.h"
#include "support/test_data.h"

namespace motionmap::pipeline {
namespace {

// The squared deviations of `points` from the time-linear interpolation between `keys`.
double chord_cost(const Eigen::MatrixXd& points, const std::vector<int>& keys) {
  double cost = 0.0;
  for (std::size_t i = 1; i < keys.size(); ++i) {
    const int a = keys[i - 1], b = keys[i];
    for (int t = a + 1; t < b; ++t) {
      const double s = double(t - a) / double(b - a);
      cost += (points.row(t) - ((1 - s) * points.row(a) + s * points.row(b))).squaredNorm();
    }
  }
  return cost;
}

// Every choice of count − 2 inner keys, the least cost (ties: the first in lexicographic order).
std::vector<int> brute_force(const Eigen::MatrixXd& points, int count) {
  const int n = static_cast<int>(points.rows());
  std::vector<int> keys(static_cast<std::size_t>(count)), best;
  double best_cost = INFINITY;
  std::function<void(int, int)> choose = [&](int slot, int from) {
    if (slot == count - 1) {
      keys.back() = n - 1;
      const double c = chord_cost(points, keys);
      if (c < best_cost - 1e-12) {
        best_cost = c;
        best = keys;
      }
      return;
    }
    for (int t = from; t < n - 1; ++t) {
      keys[std::size_t(slot)] = t;
      choose(slot + 1, t + 1);
    }
  };
  keys[0] = 0;
  choose(1, 1);
  return best;
}

TEST(KeyPoses, TheChoiceIsTheLeastSquaredDeviationOverEveryChoice) {
  std::mt19937 random(7);
  std::normal_distribution<double> step(0.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    const int n = 9 + trial % 6, count = 3 + trial % 3;
    Eigen::MatrixXd points(n, 2);
    points.row(0).setZero();
    for (int t = 1; t < n; ++t)
      points.row(t) = points.row(t - 1) + Eigen::RowVector2d(step(random), step(random));
    const std::vector<int> keys = select_key_poses(points, count);
    const std::vector<int> best = brute_force(points, count);
    EXPECT_NEAR(chord_cost(points, keys), chord_cost(points, best),
                1e-9 * (1 + chord_cost(points, best)))
        << "trial " << trial;
    EXPECT_EQ(keys, best) << "trial " << trial;
  }
}

TEST(KeyPoses, ACornerAndAPauseAreKeys) {
  // Right for 10 steps, then up for 10: the corner is the key.
  Eigen::MatrixXd corner(21, 2);
  for (int t = 0; t <= 20; ++t)
    corner.row(t) = t <= 10 ? Eigen::RowVector2d(t, 0) : Eigen::RowVector2d(10, t - 10);
  EXPECT_EQ(select_key_poses(corner, 3), (std::vector<int>{0, 10, 20}));
  // A straight line walked at one speed, then held still from frame 12: the stop is the key.
  Eigen::MatrixXd pause(21, 1);
  for (int t = 0; t <= 20; ++t) pause(t, 0) = std::min(t, 12);
  EXPECT_EQ(select_key_poses(pause, 3), (std::vector<int>{0, 12, 20}));
  // Enough keys for every point: all of them.
  EXPECT_EQ(select_key_poses(corner.topRows(4), 6), (std::vector<int>{0, 1, 2, 3}));
}

TEST(KeyPoses, LongTrajectoriesAreSearchedOnEveryKthPoint) {
  const int n = 3 * kExactPoints + 5;
  Eigen::MatrixXd circle(n, 2);
  for (int t = 0; t < n; ++t) {
    const double a = 2.0 * std::numbers::pi * t / (n - 1);
    circle.row(t) << std::cos(a), std::sin(a);
  }
  const std::vector<int> keys = select_key_poses(circle, 5);
  ASSERT_EQ(keys.size(), 5u);
  EXPECT_EQ(keys.front(), 0);
  EXPECT_EQ(keys.back(), n - 1);
  for (std::size_t i = 1; i < keys.size(); ++i) EXPECT_GT(keys[i], keys[i - 1]);
  for (std::size_t i = 1; i + 1 < keys.size(); ++i) EXPECT_EQ(keys[i] % 4, 0);  // every 4th
  // A circle is cut evenly: the three inner keys at a quarter, half and three quarters.
  for (std::size_t i = 1; i + 1 < keys.size(); ++i)
    EXPECT_NEAR(keys[i], double(i) * (n - 1) / 4.0, 4.0);
}

TEST(KeyPoses, BadInputsSayWhatWasExpected) {
  const Eigen::MatrixXd two = Eigen::MatrixXd::Zero(2, 2);
  EXPECT_EQ(test::error_message<ParameterError>([&] { select_key_poses(two, 1); }),
            "key poses: 1 asked for, expected at least 2 (the first and the last frame)");
  EXPECT_EQ(test::error_message<ParameterError>([&] { select_key_poses(two.topRows(1), 2); }),
            "key poses: a trajectory of 1 points, expected at least 2");
  Eigen::MatrixXd nan = two;
  nan(1, 0) = NAN;
  EXPECT_EQ(test::error_message<ParameterError>([&] { select_key_poses(nan, 2); }),
            "key poses: the trajectory has a non-finite point");
  EXPECT_EQ(uniform_key_poses(9, 3), (std::vector<int>{0, 4, 8}));
  EXPECT_EQ(uniform_key_poses(3, 8), (std::vector<int>{0, 1, 2}));
}

// One joint turning about z at a constant rate, another still; translations moving linearly.
Motion turning(int frames, double degrees_per_frame) {
  Motion m;
  m.resize(frames, 2);
  for (int f = 0; f < frames; ++f) {
    m.rotation(f, 1) = Eigen::Quaterniond(Eigen::AngleAxisd(
        f * degrees_per_frame * std::numbers::pi / 180, Eigen::Vector3d::UnitZ()));
    m.translation(f, 0) = Eigen::Vector3d(f, 0, 0);
  }
  return m;
}

TEST(KeyPoses, InterpolationIsExactOnConstantTurnsAndTheErrorIsInDegrees) {
  const Motion m = turning(30, 3.0);
  const std::vector<int> ends{0, 29};
  const Motion rebuilt = interpolate_keys(m, ends);
  EXPECT_LT(rms_rotation_error(m, rebuilt, 0, 29), 1e-6);
  EXPECT_LT((rebuilt.translation(17, 0) - m.translation(17, 0)).norm(), 1e-12);
  // Frames outside the keys hold them.
  const std::vector<int> inner{5, 20};
  const Motion held = interpolate_keys(m, inner);
  EXPECT_TRUE(held.rotation(0, 1).isApprox(m.rotation(5, 1)));
  EXPECT_TRUE(held.rotation(29, 1).isApprox(m.rotation(20, 1)));
  // One of two joints off by 10° on every frame: RMS = sqrt(10²/2).
  Motion off = m;
  for (int f = 0; f < off.num_frames; ++f)
    off.rotation(f, 0) = Eigen::Quaterniond(
        Eigen::AngleAxisd(10 * std::numbers::pi / 180, Eigen::Vector3d::UnitX()));
  EXPECT_NEAR(rms_rotation_error(m, off, 0, 29), std::sqrt(50.0), 1e-9);
  const std::vector<int> backwards{20, 5};
  EXPECT_EQ(test::error_message<ParameterError>([&] { interpolate_keys(m, backwards); }),
            "interpolate keys: key 5 is out of order or outside the motion's 30 frames");
  EXPECT_EQ(test::error_message<ParameterError>([&] { rms_rotation_error(m, off, 3, 30); }),
            "rotation error: frames 3–30 outside the motion's 30 frames");
}

// On real clips the key poses of the PCA map rebuild the motion better than as many evenly
// spaced frames (the README's table lists every shared clip, with the ones where they do not).
TEST(KeyPoses, OnRealClipsTheyRebuildTheMotionBetterThanEvenSpacing) {
  for (const char* file : {"cmu/64_09.bvh", "bandai/dataset-1_walk_angry_001.bvh",
                           "bandai/dataset-1_punch_normal_001.bvh"}) {
    const std::vector<Clip> clips{io::load_clip(test::shared_file(file))};
    ClipMapOptions options;
    options.embed.method = embed::Method::Pca;
    const ClipMap map = map_clips(clips, options);
    const auto& frames = map.features->frame_of;
    std::vector<int> keys;
    for (const int r : clip_key_rows(map, 0, 8)) keys.push_back(frames[std::size_t(r)]);
    ASSERT_EQ(keys.size(), 8u);
    EXPECT_EQ(keys.front(), frames.front());
    EXPECT_EQ(keys.back(), frames.back());
    std::vector<int> even;
    for (const int u : uniform_key_poses(static_cast<int>(frames.size()), 8))
      even.push_back(frames[std::size_t(u)]);
    const Motion& motion = clips[0].motion;
    const double ours =
        rms_rotation_error(motion, interpolate_keys(motion, keys), keys.front(), keys.back());
    const double evenly =
        rms_rotation_error(motion, interpolate_keys(motion, even), keys.front(), keys.back());
    EXPECT_LT(ours, 0.95 * evenly) << file << ": " << ours << "° vs " << evenly << "°";
  }
}

}  // namespace
}  // namespace motionmap::pipeline
