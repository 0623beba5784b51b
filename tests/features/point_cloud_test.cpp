#include "motionmap/features/point_cloud.h"

#include <gtest/gtest.h>

#include "motionmap/features/diagnostics.h"

namespace motionmap::features {
namespace {

// Root with two children: an "arm" sideways and a "leg" down, each with an end site.
Skeleton tiny_skeleton() {
  Skeleton s;
  s.joints.push_back({"root", -1, {0, 0, 0}, {}, {}});
  s.joints.push_back({"arm", 0, {10, 5, 0}, {}, {{0, 0, 4}}});
  s.joints.push_back({"leg", 0, {0, -9, 2}, {}, {{0, -8, 0}}});
  return s;
}

Motion one_pose_many_headings(const Skeleton& s, Axis up) {
  Motion m;
  m.resize(4, s.num_joints());
  const Eigen::Quaterniond bend = axis_rotation(Axis::X, 0.4);
  for (int f = 0; f < 4; ++f) {
    const double yaw = 0.9 * f - 1.0;
    for (int j = 0; j < s.num_joints(); ++j) m.translation(f, j) = s.joints[j].offset;
    Eigen::Vector3d floor = Eigen::Vector3d::Zero();
    floor[(static_cast<int>(up) + 1) % 3] = 100.0 * f;
    floor[(static_cast<int>(up) + 2) % 3] = -30.0 * f;
    floor[static_cast<int>(up)] = 90.0;
    m.translation(f, 0) = floor;
    m.rotation(f, 0) = axis_rotation(up, yaw) * axis_rotation(Axis::Z, 0.2);
    m.rotation(f, 1) = bend;
  }
  return m;
}

TEST(PointCloud, InvariantToHeadingAndFloorPosition) {
  const Skeleton s = tiny_skeleton();
  for (Axis up : {Axis::Y, Axis::Z}) {
    const RowMatrix p = heading_local_points(s, one_pose_many_headings(s, up), up);
    ASSERT_EQ(p.cols(), 3 * (3 + 2));
    for (int f = 1; f < 4; ++f) EXPECT_LT((p.row(f) - p.row(0)).norm(), 1e-9) << "frame " << f;
    // Height is kept: the root stays 90 units up.
    EXPECT_NEAR(p(0, static_cast<int>(up)), 90.0, 1e-12);
  }
}

TEST(PointCloud, HeadingOfPureYaw) {
  for (double yaw : {-3.0, -1.2, 0.0, 0.5, 2.9}) {
    EXPECT_NEAR(heading_angle(axis_rotation(Axis::Y, yaw), Axis::Y), yaw, 1e-12);
    EXPECT_NEAR(heading_angle(axis_rotation(Axis::Z, yaw), Axis::Z), yaw, 1e-12);
  }
  // Bending 90° forward keeps the heading defined (one floor axis points straight up then).
  const Eigen::Quaterniond bent = axis_rotation(Axis::Y, 0.7) * axis_rotation(Axis::X, kPi / 2);
  EXPECT_NEAR(heading_angle(bent, Axis::Y), 0.7, 1e-12);
}

TEST(Diagnostics, DetectsLeadingBindPose) {
  RowMatrix points(20, 3);
  for (int f = 0; f < 20; ++f) points.row(f) << f * 0.1, 0, 0;
  EXPECT_FALSE(check_leading_bind_pose(points).detected);
  points.row(0) << -50, 0, 0;  // 50 / 0.1 = 500× the median step
  const BindPoseCheck check = check_leading_bind_pose(points);
  EXPECT_TRUE(check.detected);
  EXPECT_NEAR(check.ratio, (50.0 + 0.1) / 0.1, 1e-9);
  EXPECT_NEAR(check.median_step, 0.1, 1e-12);
}

TEST(Diagnostics, AStartThatMovesOnIsNotABindPose) {
  // Moving at its start, then standing nearly still: the first step is 50× the median step, but
  // the steps after it are as large (a synthesized path held at the data's edge).
  RowMatrix points(40, 3);
  double x = 0.0;
  for (int f = 0; f < 40; ++f) {
    points.row(f) << x, 0, 0;
    x += f < 5 ? 5.0 : 0.1;
  }
  const BindPoseCheck check = check_leading_bind_pose(points);
  EXPECT_GT(check.ratio, 10.0);
  EXPECT_NEAR(check.local_ratio, 1.0, 1e-12);
  EXPECT_FALSE(check.detected);
}

TEST(Diagnostics, StillClipIsNotABindPose) {
  RowMatrix points = RowMatrix::Zero(10, 6);
  EXPECT_FALSE(check_leading_bind_pose(points).detected);
  EXPECT_FALSE(check_leading_bind_pose(RowMatrix::Zero(2, 3)).detected);  // too short to tell
}

TEST(Diagnostics, FindsRotationFlipsWithFrames) {
  const Skeleton s = tiny_skeleton();
  Motion m;
  m.resize(10, 3);
  m.frame_time = 1.0 / 120;
  for (int f = 0; f < 10; ++f) {
    m.rotation(f, 1) = axis_rotation(Axis::X, 0.01 * f);
    m.rotation(f, 2) = axis_rotation(Axis::Z, (f >= 4 && f < 7) ? kPi * 0.9 : 0.0);
  }
  const auto flips = find_rotation_flips(s, m);
  ASSERT_EQ(flips.size(), 1u);
  EXPECT_EQ(flips[0].joint, 2);
  EXPECT_EQ(flips[0].frames, (std::vector<int>{3, 6}));
  EXPECT_NEAR(flips[0].max_degrees, 162.0, 1e-9);
  const auto warnings = clip_warnings(s, m);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("'leg'"), std::string::npos);
  EXPECT_NE(warnings[0].find("3→4, 6→7"), std::string::npos);
  // At a low frame rate fast motion is plausible: no flip warning.
  m.frame_time = 1.0 / 30;
  EXPECT_TRUE(clip_warnings(s, m).empty());
}

TEST(Diagnostics, JumpOutOfABindPoseIsNotAFlip) {
  const Skeleton s = tiny_skeleton();
  Motion m;
  m.resize(20, 3);
  m.frame_time = 1.0 / 120;
  for (int j = 0; j < 3; ++j) {
    for (int f = 0; f < 20; ++f) m.translation(f, j) = s.joints[j].offset;
  }
  for (int f = 1; f < 20; ++f) m.rotation(f, 1) = axis_rotation(Axis::X, 2.0 + 0.01 * f);
  const auto warnings = clip_warnings(s, m);
  ASSERT_EQ(warnings.size(), 1u) << warnings.back();
  EXPECT_NE(warnings[0].find("bind pose"), std::string::npos);
  EXPECT_EQ(find_rotation_flips(s, m).size(), 1u);  // the raw finder still sees it
}

}  // namespace
}  // namespace motionmap::features
