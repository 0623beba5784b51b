// Every real BVH under ../shared/data: loads, matches the counts in SOURCES.md, writes back
// bit-exactly, and survives the quaternion round trip (to_motion ∘ from_motion).
#include <cctype>
#include <cstring>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "motionmap/core/error.h"
#include "motionmap/io/bvh.h"
#include "motionmap/io/load.h"
#include "motionmap/skeleton/forward_kinematics.h"
#include "support/test_data.h"

namespace motionmap::io {
namespace {

std::vector<std::string> real_bvh_files() {
  return test::shared_files_with_extension(".bvh");
}
using test::file_test_name;

class BvhRealFile : public ::testing::TestWithParam<std::string> {};

TEST_P(BvhRealFile, LoadsAsAValidClip) {
  const Clip clip = load_bvh(GetParam());
  EXPECT_EQ(clip.path, GetParam());
  EXPECT_NO_THROW(clip.skeleton.validate());
  EXPECT_TRUE(clip.warnings.empty()) << clip.warnings.front();
  EXPECT_GT(clip.skeleton.num_joints(), 0);
  EXPECT_GT(clip.motion.num_frames, 0);
  EXPECT_GT(clip.motion.frame_time, 0.0);
  EXPECT_EQ(clip.motion.num_joints, clip.skeleton.num_joints());
  for (const auto& q : clip.motion.rotations) ASSERT_NEAR(q.norm(), 1.0, 1e-12);
  for (const auto& t : clip.motion.translations) ASSERT_TRUE(t.allFinite());
}

TEST_P(BvhRealFile, WriteThenReadIsBitExact) {
  const BvhDocument doc = read_bvh(GetParam());
  std::ostringstream out;
  write_bvh(doc, out);
  const std::string text = out.str();
  EXPECT_EQ(text.find('\r'), std::string::npos);
  const BvhDocument back = parse_bvh(text, "written");
  ASSERT_EQ(back.skeleton.num_joints(), doc.skeleton.num_joints());
  for (int j = 0; j < doc.skeleton.num_joints(); ++j) {
    const Joint& a = doc.skeleton.joints[j];
    const Joint& b = back.skeleton.joints[j];
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.parent, b.parent);
    EXPECT_EQ(a.offset, b.offset);
    EXPECT_EQ(a.channels, b.channels);
    EXPECT_EQ(a.end_sites, b.end_sites);
  }
  EXPECT_EQ(back.num_frames, doc.num_frames);
  EXPECT_EQ(back.frame_time, doc.frame_time);
  ASSERT_EQ(back.values.size(), doc.values.size());
  EXPECT_EQ(std::memcmp(back.values.data(), doc.values.data(), doc.values.size() * sizeof(double)),
            0);
  // Writing is a fixed point: the second write is the same text.
  std::ostringstream again;
  write_bvh(back, again);
  EXPECT_EQ(again.str(), text);
}

TEST_P(BvhRealFile, QuaternionRoundTripReproducesRotationsAndPositions) {
  const BvhDocument doc = read_bvh(GetParam());
  const Motion motion = to_motion(doc);
  const BvhDocument exported = from_motion(doc.skeleton, motion);
  const Motion back = to_motion(exported);
  ASSERT_EQ(back.num_frames, motion.num_frames);
  double worst = 0.0;
  for (std::size_t i = 0; i < motion.rotations.size(); ++i) {
    worst = std::max(worst, rotation_angle(motion.rotations[i], back.rotations[i]));
    ASSERT_EQ(motion.translations[i], back.translations[i]) << i;
  }
  EXPECT_LT(worst, 1e-9);
  const auto p = world_points(doc.skeleton, motion);
  const auto q = world_points(doc.skeleton, back);
  const double scale = std::max(1.0, p.cwiseAbs().maxCoeff());
  EXPECT_LT((p - q).cwiseAbs().maxCoeff(), 1e-9 * scale);
  // Exported angles are continuous: no ±360° wraps between consecutive frames.
  for (int f = 1; f < exported.num_frames; ++f) {
    int c = 0;
    for (const Joint& j : exported.skeleton.joints) {
      for (const ChannelType ch : j.channels) {
        if (is_rotation(ch)) {
          ASSERT_LT(std::abs(exported.value(f, c) - exported.value(f - 1, c)), 180.0)
              << j.name << " frame " << f;
        }
        ++c;
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(SharedData, BvhRealFile, ::testing::ValuesIn(real_bvh_files()),
                         file_test_name);
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(BvhRealFile);

TEST(BvhRealFiles, Present) {
  if (real_bvh_files().empty()) {
    GTEST_SKIP() << "no .bvh files under " << test::shared_data_dir()
                 << ": the real-file BVH tests did not run";
  }
}

// Counts from SOURCES.md (joints = ROOT/JOINT nodes, channels per row, Frames:).
struct Known {
  int joints;
  int channels;
  int frames;
  double frame_time;
};

TEST(BvhRealFiles, CountsMatchSources) {
  const std::map<std::string, Known> known = {
      {"cmu/02_03.bvh", {31, 96, 174, 0.0083333}},
      {"cmu/64_08.bvh", {31, 96, 365, 0.0083333}},
      {"cmu/64_09.bvh", {31, 96, 453, 0.0083333}},
      {"other/20tab_test_freebvh.bvh", {55, 168, 69, 0.0333333}},
      {"other/20tab_test_mocapbank.bvh", {19, 60, 455, 0.033333}},
      {"other/BandaiNamcoResearchInc_dataset-1_walk_normal_001.bvh", {22, 132, 195, 0.0333333}},
      {"other/facebookresearch_pfnn_hierarchy.bvh", {31, 96, 60, 0.0333333}},
      {"other/facebookresearch_sinusoidal.bvh", {4, 15, 120, 0.016666666666666666}},
      {"other/omimo_AV_8Walk_Meredith_HVHA_Rep1.bvh", {23, 72, 1064, 0.008333}},
  };
  int found = 0;
  for (const auto& [file, k] : known) {
    if (!std::filesystem::exists(test::shared_file(file))) continue;
    ++found;
    const BvhDocument doc = read_bvh(test::shared_file(file));
    EXPECT_EQ(doc.skeleton.num_joints(), k.joints) << file;
    EXPECT_EQ(doc.num_channels(), k.channels) << file;
    EXPECT_EQ(doc.num_frames, k.frames) << file;
    EXPECT_EQ(doc.frame_time, k.frame_time) << file;
  }
  if (found == 0)
    GTEST_SKIP() << "none of the files of SOURCES.md under " << test::shared_data_dir();
}

TEST(BvhRealFiles, KnownValuesOfTheQuirkyFiles) {
  MOTIONMAP_REQUIRE_SHARED("other/BandaiNamcoResearchInc_dataset-1_walk_normal_001.bvh");
  MOTIONMAP_REQUIRE_SHARED("other/20tab_test_freebvh.bvh");
  MOTIONMAP_REQUIRE_SHARED("other/facebookresearch_sinusoidal.bvh");
  MOTIONMAP_REQUIRE_SHARED("cmu/64_08.bvh");
  // Bandai Namco: a 6-channel Hips below a static joint_Root, ZXY; the animated y replaces the
  // offset's 93.9241.
  const Clip bandai =
      load_bvh(test::shared_file("other/BandaiNamcoResearchInc_dataset-1_walk_normal_001.bvh"));
  EXPECT_EQ(bandai.skeleton.joints[0].name, "joint_Root");
  EXPECT_EQ(bandai.skeleton.joints[1].name, "Hips");
  EXPECT_EQ(bandai.skeleton.joints[1].offset, Eigen::Vector3d(0, 93.9241, -3));
  EXPECT_EQ(bandai.skeleton.joints[1].channels[3], ChannelType::Zrotation);
  EXPECT_EQ(bandai.skeleton.joints[1].channels[4], ChannelType::Xrotation);
  EXPECT_NE(bandai.motion.translation(0, 1).y(), 93.9241);
  EXPECT_NEAR(bandai.motion.translation(0, 1).y(), 90.0, 5.0);
  // Mixamo: colons in names, tab-separated offsets.
  const BvhDocument mixamo = read_bvh(test::shared_file("other/20tab_test_freebvh.bvh"));
  EXPECT_EQ(mixamo.skeleton.joints[0].name, "mixamorig:Hips");
  EXPECT_EQ(mixamo.skeleton.joints[1].offset, Eigen::Vector3d(0.0, 9.9235, -1.2273));
  // Sinusoidal: the leaf JOINT child3 has no End Site; only channel 9 moves (−90, −89, …).
  const BvhDocument sine = read_bvh(test::shared_file("other/facebookresearch_sinusoidal.bvh"));
  EXPECT_EQ(sine.skeleton.joints[3].name, "child3");
  EXPECT_TRUE(sine.skeleton.joints[3].end_sites.empty());
  EXPECT_EQ(sine.value(0, 9), -90.0);
  EXPECT_EQ(sine.value(1, 9), -89.0);
  // CMU: frame 1 is the T-pose of integer zeros; the root's offset is zero, its position animated.
  const BvhDocument cmu = read_bvh(test::shared_file("cmu/64_08.bvh"));
  EXPECT_EQ(cmu.skeleton.joints[0].channels.size(), 6u);
  EXPECT_EQ(cmu.skeleton.num_end_sites(), 7);
  EXPECT_EQ(cmu.frame_time, 0.0083333);
}

}  // namespace
}  // namespace motionmap::io
