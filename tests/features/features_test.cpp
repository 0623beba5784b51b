#include "motionmap/features/features.h"

#include <atomic>
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "motionmap/core/error.h"
#include "support/small_clip.h"

namespace motionmap::features {
namespace {

using test::chain_skeleton;
using test::smooth_clip;

TEST(Features, QuaternionFeaturesAreSignConsistent) {
  Motion m;
  m.resize(4, 2);
  const Eigen::Quaterniond q = axis_rotation(Axis::X, 0.3);
  const Eigen::Quaterniond minus_q(-q.w(), -q.x(), -q.y(), -q.z());
  m.rotation(0, 1) = minus_q;  // w < 0 in frame 0 → flipped to w ≥ 0
  m.rotation(1, 1) = q;
  m.rotation(2, 1) = minus_q;  // opposite sign to the previous row → flipped
  m.rotation(3, 1) = axis_rotation(Axis::X, 0.35);
  const std::vector<int> joints{1}, frames{0, 1, 2, 3};
  const Eigen::MatrixXd X = quaternion_features(m, joints, frames);
  ASSERT_EQ(X.rows(), 4);
  ASSERT_EQ(X.cols(), 4);
  for (int r = 0; r < 4; ++r) EXPECT_GT(X(r, 0), 0.9) << r;
  EXPECT_NEAR(X(2, 1), q.x(), 1e-15);
}

TEST(Features, PairwiseDistancesMatchBruteForce) {
  RowMatrix P = RowMatrix::Random(37, 11);
  const Eigen::MatrixXd D = pairwise_distances(P);
  for (int i = 0; i < 37; ++i) {
    for (int j = 0; j < 37; ++j) EXPECT_NEAR(D(i, j), (P.row(i) - P.row(j)).norm(), 1e-14);
  }
}

TEST(Features, GeodesicDistanceSumsJointAngles) {
  Eigen::MatrixXd X(2, 8);
  const Eigen::Quaterniond a = axis_rotation(Axis::X, 0.3), b = axis_rotation(Axis::Y, -0.4);
  X.row(0) << 1, 0, 0, 0, 1, 0, 0, 0;
  X.row(1) << a.w(), a.x(), a.y(), a.z(), b.w(), b.x(), b.y(), b.z();
  const Eigen::MatrixXd D = geodesic_distances(X);
  EXPECT_NEAR(D(0, 1), std::sqrt(0.3 * 0.3 + 0.4 * 0.4), 1e-12);
  EXPECT_EQ(D(0, 0), 0.0);
  EXPECT_EQ(D(1, 0), D(0, 1));
}

TEST(Features, BuildsXAndPointCloudDistance) {
  const Clip clip = smooth_clip();
  FeatureOptions opt;
  const FeatureSet set = build_features(std::span<const Clip>(&clip, 1), opt);
  EXPECT_EQ(set.num_samples(), 50);
  EXPECT_EQ(set.X.cols(), 4 * 3);  // every non-root joint
  EXPECT_EQ(set.D.rows(), 50);
  EXPECT_TRUE(set.notes.empty());
  EXPECT_EQ(set.frame_of[7], 7);
  // D is the Euclidean distance of heading-local point clouds.
  const RowMatrix cloud = heading_local_points(clip.skeleton, clip.motion);
  EXPECT_NEAR(set.D(3, 40), (cloud.row(3) - cloud.row(40)).norm(), 1e-12);
  EXPECT_TRUE(set.D.isApprox(set.D.transpose(), 0.0));
}

TEST(Features, LeavesOutALeadingBindPoseUnlessAsked) {
  Clip clip = smooth_clip();
  for (int j = 1; j < 4; ++j)
    clip.motion.rotation(0, j) = axis_rotation(Axis::Z, 1.5);  // a far pose
  FeatureOptions opt;
  const FeatureSet set = build_features(std::span<const Clip>(&clip, 1), opt);
  EXPECT_EQ(set.num_samples(), 49);
  EXPECT_EQ(set.frame_of.front(), 1);  // the CSV's frame column keeps file indices
  ASSERT_EQ(set.notes.size(), 1u);
  EXPECT_NE(set.notes[0].find("bind pose"), std::string::npos);
  opt.keep_first = true;
  EXPECT_EQ(build_features(std::span<const Clip>(&clip, 1), opt).num_samples(), 50);
}

TEST(Features, ANoteSaysWhenEveryFrameHasTheSamePose) {
  Clip clip = smooth_clip();
  for (int f = 1; f < clip.motion.num_frames; ++f) {
    for (int j = 0; j < clip.motion.num_joints; ++j) {
      clip.motion.rotation(f, j) = clip.motion.rotation(0, j);
      clip.motion.translation(f, j) = clip.motion.translation(0, j);
    }
    clip.motion.translation(f, 0) += Eigen::Vector3d(0.1 * f, 0, 0.05 * f);  // it slides along
  }
  FeatureOptions opt;
  for (DistanceKind d :
       {DistanceKind::PointCloud, DistanceKind::Geodesic, DistanceKind::Features}) {
    opt.distance = d;
    const FeatureSet set = build_features(std::span<const Clip>(&clip, 1), opt);
    ASSERT_EQ(set.notes.size(), 1u) << distance_kind_name(d);
    EXPECT_NE(set.notes[0].find("every frame has the same pose"), std::string::npos)
        << set.notes[0];
  }
  // A single frame more that differs: no note.
  clip.motion.rotation(20, 1) = axis_rotation(Axis::X, 0.3);
  opt.distance = DistanceKind::PointCloud;
  EXPECT_TRUE(build_features(std::span<const Clip>(&clip, 1), opt).notes.empty());
}

TEST(Features, FramesStrideAndExclude) {
  const Clip clip = smooth_clip();
  FeatureOptions opt;
  opt.first_frame = 10;
  opt.end_frame = 30;
  opt.stride = 3;
  opt.exclude = ".*Thumb.*";
  const FeatureSet set = build_features(std::span<const Clip>(&clip, 1), opt);
  EXPECT_EQ(set.frame_of, (std::vector<int>{10, 13, 16, 19, 22, 25, 28}));
  EXPECT_EQ(set.joints, (std::vector<int>{1, 3}));
  EXPECT_EQ(set.X.cols(), 8);
  // The thumb (and its end site) are out of the point cloud too: its rotation changes nothing.
  Clip still_thumb = clip;
  for (int f = 0; f < 50; ++f) still_thumb.motion.rotation(f, 2) = Eigen::Quaterniond::Identity();
  const FeatureSet set2 = build_features(std::span<const Clip>(&still_thumb, 1), opt);
  EXPECT_LT((set.D - set2.D).norm(), 1e-12);
}

TEST(Features, SeveralClipsOfOneHierarchy) {
  std::vector<Clip> clips{smooth_clip(20, "a.bvh"), smooth_clip(30, "b.bvh")};
  clips[1].skeleton.joints[1].offset *= 1.1;  // other offsets are fine
  FeatureOptions opt;
  const FeatureSet set = build_features(clips, opt);
  EXPECT_EQ(set.num_samples(), 50);
  EXPECT_EQ(set.segment_starts, (std::vector<int>{0, 20}));
  EXPECT_EQ(set.clip_of[25], 1);
  EXPECT_EQ(set.frame_of[25], 5);

  clips[1].skeleton.joints[3].name = "Neck";
  try {
    build_features(clips, opt);
    FAIL() << "expected ParameterError";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("b.bvh"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("hierarchy"), std::string::npos) << e.what();
  }
}

TEST(Features, BadInputsGiveClearErrors) {
  Clip clip = smooth_clip();
  const std::span<const Clip> one(&clip, 1);
  auto message = [&](FeatureOptions opt) {
    try {
      build_features(one, opt);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  FeatureOptions opt;
  opt.stride = 0;
  EXPECT_NE(message(opt).find("stride"), std::string::npos);
  opt = {};
  opt.first_frame = 60;
  EXPECT_NE(message(opt).find("holds no frame"), std::string::npos);
  opt = {};
  opt.first_frame = 5;
  opt.end_frame = 5;
  EXPECT_NE(message(opt).find("empty"), std::string::npos);
  opt = {};
  opt.exclude = "(";
  EXPECT_NE(message(opt).find("not a valid regular expression"), std::string::npos);
  opt.exclude = ".*";
  EXPECT_NE(message(opt).find("leaves no joint"), std::string::npos);

  clip.motion.rotation(7, 2).x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(message({}).find("frame 7, joint 'LeftThumb'"), std::string::npos) << message({});
  EXPECT_THROW(build_features(std::span<const Clip>(), {}), ParameterError);
}

TEST(Features, CancelStopsTheDistanceMatrix) {
  const Clip clip = smooth_clip(400);
  const FeatureOptions opt;
  EXPECT_THROW(
      build_features(std::span<const Clip>(&clip, 1), opt, Control({}, [] { return true; })),
      Cancelled);
  std::vector<double> seen;
  build_features(std::span<const Clip>(&clip, 1), opt,
                 Control([&](double p, std::string_view) { seen.push_back(p); }));
  ASSERT_FALSE(seen.empty());
  EXPECT_EQ(seen.back(), 1.0);
  for (std::size_t i = 1; i < seen.size(); ++i) EXPECT_GE(seen[i], seen[i - 1]);
}

}  // namespace
}  // namespace motionmap::features
