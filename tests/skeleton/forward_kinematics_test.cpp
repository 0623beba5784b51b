#include "motionmap/skeleton/forward_kinematics.h"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "motionmap/io/bvh.h"
#include "support/test_data.h"

namespace motionmap {
namespace {

// A 3-joint chain A → B → C with an End Site, then a second root D.
constexpr const char* kChain =
    "HIERARCHY\n"
    "ROOT A\n{\n"
    "  OFFSET 0 0 0\n"
    "  CHANNELS 6 Xposition Yposition Zposition Zrotation Yrotation Xrotation\n"
    "  JOINT B\n  {\n"
    "    OFFSET 0 2 0\n"
    "    CHANNELS 3 Zrotation Yrotation Xrotation\n"
    "    JOINT C\n    {\n"
    "      OFFSET 1 0 0\n"
    "      CHANNELS 3 Zrotation Yrotation Xrotation\n"
    "      End Site\n      {\n        OFFSET 0 0 3\n      }\n"
    "    }\n"
    "  }\n"
    "}\n"
    "ROOT D\n{\n"
    "  OFFSET 10 0 0\n"
    "  CHANNELS 1 Yrotation\n"
    "  End Site\n  {\n    OFFSET 1 0 0\n  }\n"
    "}\n"
    "MOTION\n"
    "Frames: 3\n"
    "Frame Time: 0.1\n"
    // frame 0: everything at rest
    "0 0 0 0 0 0 0 0 0 0 0 0 0\n"
    // frame 1: root at (1,2,3) turned Rz(90); B turned Rx(90); D turned Ry(90)
    "1 2 3 90 0 0 0 0 90 0 0 0 90\n"
    // frame 2: root Rz(90)·Ry(90) (ZYX channels: Z=90, Y=90), C turned Rz(-90)
    "0 0 0 90 90 0 0 0 0 -90 0 0 0\n";

void expect_near(const Eigen::Vector3d& actual, const Eigen::Vector3d& expected) {
  EXPECT_LT((actual - expected).norm(), 1e-12)
      << actual.transpose() << " vs " << expected.transpose();
}

TEST(ForwardKinematics, RestPoseIsTheSumOfOffsets) {
  const io::BvhDocument doc = io::parse_bvh(kChain);
  const WorldPose w = forward_kinematics(doc.skeleton, io::to_motion(doc), 0);
  expect_near(w.positions[0], {0, 0, 0});
  expect_near(w.positions[1], {0, 2, 0});
  expect_near(w.positions[2], {1, 2, 0});
  expect_near(w.positions[3], {10, 0, 0});
  ASSERT_EQ(w.end_sites.size(), 2u);
  expect_near(w.end_sites[0], {1, 2, 3});
  expect_near(w.end_sites[1], {11, 0, 0});
}

TEST(ForwardKinematics, HandComputedPositionsOfARotatedChain) {
  const io::BvhDocument doc = io::parse_bvh(kChain);
  const WorldPose w = forward_kinematics(doc.skeleton, io::to_motion(doc), 1);
  // Rz(90) maps (x,y,z) → (−y,x,z); Rx(90) maps (x,y,z) → (x,−z,y); Ry(90) maps (x,y,z) → (z,y,−x).
  // A = root position channels = (1,2,3).
  expect_near(w.positions[0], {1, 2, 3});
  // B = A + Rz90·(0,2,0) = (1,2,3) + (−2,0,0).
  expect_near(w.positions[1], {-1, 2, 3});
  // C = B + Rz90·Rx90·(1,0,0) = B + Rz90·(1,0,0) = B + (0,1,0).
  expect_near(w.positions[2], {-1, 3, 3});
  // End = C + Rz90·Rx90·(0,0,3) = C + Rz90·(0,−3,0) = C + (3,0,0).
  expect_near(w.end_sites[0], {2, 3, 3});
  // The second root is independent: D = (10,0,0), its end = D + Ry90·(1,0,0) = D + (0,0,−1).
  expect_near(w.positions[3], {10, 0, 0});
  expect_near(w.end_sites[1], {10, 0, -1});
}

TEST(ForwardKinematics, ChannelOrderIsTheCompositionOrder) {
  const io::BvhDocument doc = io::parse_bvh(kChain);
  const WorldPose w = forward_kinematics(doc.skeleton, io::to_motion(doc), 2);
  // Root R = Rz90·Ry90. B = R·(0,2,0) = Rz90·(0,2,0) = (−2,0,0).
  expect_near(w.positions[1], {-2, 0, 0});
  // C = B + R·(1,0,0) = B + Rz90·(0,0,−1) = B + (0,0,−1). (Ry90·Rz90 would give (0,1,0).)
  expect_near(w.positions[2], {-2, 0, -1});
  // End = C + R·Rz(−90)·(0,0,3) = C + R·(0,0,3) = C + Rz90·(3,0,0) = C + (0,3,0).
  expect_near(w.end_sites[0], {-2, 3, -1});
}

TEST(ForwardKinematics, WorldPointsRowsHoldJointsThenEndSites) {
  const io::BvhDocument doc = io::parse_bvh(kChain);
  const auto points = world_points(doc.skeleton, io::to_motion(doc));
  ASSERT_EQ(points.rows(), 3);
  ASSERT_EQ(points.cols(), 3 * (4 + 2));
  expect_near(points.row(1).segment<3>(3 * 2).transpose(), {-1, 3, 3});
  expect_near(points.row(1).segment<3>(3 * 4).transpose(), {2, 3, 3});
  expect_near(points.row(1).segment<3>(3 * 5).transpose(), {10, 0, -1});
}

TEST(ForwardKinematics, PositionChannelsOnAChildReplaceItsOffset) {
  // Bandai Namco style: a child joint with position channels (y 93.9 in the offset, 90 animated).
  const io::BvhDocument doc = io::parse_bvh(
      "HIERARCHY\nROOT R\n{\nOFFSET 0 0 0\nCHANNELS 0\n"
      "JOINT Hips\n{\nOFFSET 0 93.9 -3\nCHANNELS 6 Xposition Yposition Zposition Zrotation "
      "Xrotation Yrotation\nEnd Site\n{\nOFFSET 0 10 0\n}\n}\n}\n"
      "MOTION\nFrames: 1\nFrame Time: 1\n1 90 2 0 0 90\n");
  const WorldPose w = forward_kinematics(doc.skeleton, io::to_motion(doc), 0);
  expect_near(w.positions[1], {1, 90, 2});
  expect_near(w.end_sites[0], {1, 100, 2});  // Ry(90) leaves (0,10,0) as it is
}

// Bone lengths of every real clip are constant over time: |p_j − p_parent| equals the length of
// the joint's local translation (its offset where it has no position channels).
class ForwardKinematicsRealFile : public ::testing::TestWithParam<std::string> {};

TEST_P(ForwardKinematicsRealFile, BoneLengthsAreConstant) {
  const io::BvhDocument doc = io::read_bvh(GetParam());
  const Motion motion = io::to_motion(doc);
  const Skeleton& skel = doc.skeleton;
  double scale = 0.0;
  for (const Joint& j : skel.joints) scale = std::max(scale, j.offset.norm());
  WorldPose w;
  int checked = 0;
  for (int f = 0; f < motion.num_frames; ++f) {
    forward_kinematics(skel, motion.pose(f), w);
    for (int j = 0; j < skel.num_joints(); ++j) {
      const Joint& joint = skel.joints[j];
      if (joint.parent < 0) continue;
      const double length = (w.positions[j] - w.positions[joint.parent]).norm();
      bool animated = false;
      for (const ChannelType c : joint.channels) animated = animated || !is_rotation(c);
      const double expected = animated ? motion.translation(f, j).norm() : joint.offset.norm();
      ASSERT_NEAR(length, expected, 1e-9 * std::max(expected, scale))
          << skel.joints[j].name << " frame " << f;
      ++checked;
    }
  }
  EXPECT_GT(checked, 0);
}

std::vector<std::string> real_bvh_files() {
  return test::shared_files_with_extension(".bvh");
}
using test::file_test_name;

INSTANTIATE_TEST_SUITE_P(SharedData, ForwardKinematicsRealFile,
                         ::testing::ValuesIn(real_bvh_files()), file_test_name);
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(ForwardKinematicsRealFile);

TEST(ForwardKinematics, RealFilesPresent) {
  if (real_bvh_files().empty()) {
    GTEST_SKIP() << "no .bvh files under " << test::shared_data_dir()
                 << ": the real-file bone-length tests did not run";
  }
}

}  // namespace
}  // namespace motionmap
