#include "motionmap/skeleton/skeleton.h"

#include <gtest/gtest.h>

#include "motionmap/core/error.h"

namespace motionmap {
namespace {

Skeleton static_root_above_hips() {
  Skeleton s;
  s.joints.push_back({"joint_Root", -1, {0, 0, 0}, {}, {}});
  s.joints.push_back({"Hips", 0, {0, 90, 0}, {}, {}});
  s.joints.push_back({"LeftLeg", 1, {10, -40, 0}, {}, {}});
  s.joints.push_back({"RightLeg", 1, {-10, -40, 0}, {}, {}});
  return s;
}

TEST(Skeleton, MotionRootSkipsAStaticJointAboveTheHips) {
  const Skeleton s = static_root_above_hips();
  Motion m;
  m.resize(3, 4);
  for (int f = 0; f < 3; ++f) {
    for (int j = 0; j < 4; ++j) m.translation(f, j) = s.joints[j].offset;
    m.translation(f, 1) = Eigen::Vector3d(5.0 * f, 90, 0);
  }
  EXPECT_EQ(motion_root(s, m), 1);
  // When the top joint itself moves, it is the motion root.
  m.rotation(2, 0) = axis_rotation(Axis::Y, 0.1);
  EXPECT_EQ(motion_root(s, m), 0);
  // Hips branch into two legs: the descent stops there even if nothing moves.
  Motion still;
  still.resize(2, 4);
  EXPECT_EQ(motion_root(s, still), 1);
}

TEST(Skeleton, ValidateRejectsChildBeforeParentAndDuplicateNames) {
  Skeleton s = static_root_above_hips();
  EXPECT_NO_THROW(s.validate());
  s.joints[2].parent = 3;
  EXPECT_THROW(s.validate(), Error);
  s = static_root_above_hips();
  s.joints[3].name = "LeftLeg";
  try {
    s.validate();
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'LeftLeg'"), std::string::npos);
  }
}

TEST(Skeleton, CountsAndLookups) {
  Skeleton s = static_root_above_hips();
  s.joints[0].channels = {ChannelType::Xposition, ChannelType::Yposition, ChannelType::Zposition,
                          ChannelType::Zrotation, ChannelType::Yrotation, ChannelType::Xrotation};
  s.joints[2].end_sites.push_back({0, -40, 0});
  EXPECT_EQ(s.num_channels(), 6);
  EXPECT_EQ(s.num_end_sites(), 1);
  EXPECT_EQ(s.find("RightLeg"), 3);
  EXPECT_EQ(s.find("Nope"), -1);
  EXPECT_EQ(s.roots(), std::vector<int>{0});
  EXPECT_EQ(parse_channel_name("Zrotation"), ChannelType::Zrotation);
  EXPECT_FALSE(parse_channel_name("zrotation").has_value());
  EXPECT_EQ(channel_axis(ChannelType::Yposition), Axis::Y);
}

TEST(Skeleton, MotionFramesCutsARangeOfFrames) {
  Motion m;
  m.frame_time = 0.0083333;
  m.resize(5, 2);
  for (int f = 0; f < 5; ++f) m.translation(f, 1) = Eigen::Vector3d(f, 0, 0);
  const Motion cut = m.frames(1, 4);
  EXPECT_EQ(cut.num_frames, 3);
  EXPECT_EQ(cut.num_joints, 2);
  EXPECT_EQ(cut.frame_time, m.frame_time);
  ASSERT_EQ(cut.translations.size(), 6u);
  for (int f = 0; f < 3; ++f) EXPECT_EQ(cut.translation(f, 1).x(), f + 1);
  EXPECT_EQ(m.frames(2, 2).num_frames, 0);
  for (const auto& [first, end] : {std::pair{-1, 2}, std::pair{3, 2}, std::pair{0, 6}}) {
    try {
      (void)m.frames(first, end);
      ADD_FAILURE() << first << " " << end;
    } catch (const ParameterError& e) {
      EXPECT_NE(std::string(e.what()).find("of a motion of 5 frames"), std::string::npos);
    }
  }
}

}  // namespace
}  // namespace motionmap
